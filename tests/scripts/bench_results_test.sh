#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of the benchmark results file: bench/README.md stays short (the
# figures live in bench/RESULTS.md), and bench/update_results.py replaces one
# marked section, adds a missing one, and leaves the file alone when the
# benchmark fails or prints nothing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
UPDATE="$ROOT/bench/update_results.py"
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
fails=0
check() { # check NAME EXPECTED ACTUAL
  if [ "$2" = "$3" ]; then echo "ok   $1"; else echo "FAIL $1: expected '$2', got '$3'"; fails=$((fails + 1)); fi
}
# section FILE NAME: the lines strictly between NAME's markers.
section() { awk -v b="<!-- begin $2 -->" -v e="<!-- end $2 -->" '$0 == e { p = 0 } p { print } $0 == b { p = 1 }' "$1"; }

lines="$(wc -l < "$ROOT/bench/README.md")"
check "bench/README.md has at most 200 lines ($lines)" yes "$([ "$lines" -le 200 ] && echo yes || echo no)"
# Every section of RESULTS.md is closed, once.
check "RESULTS.md markers pair up" "" \
  "$(grep -oE '<!-- (begin|end) [^>]*-->' "$ROOT/bench/RESULTS.md" | sed -E 's/<!-- (begin|end) //' | sort | uniq -c | awk '$1 != 2')"

R="$T/R.md"
cat > "$R" <<'EOF'
# Results

<!-- begin one -->
old one
<!-- end one -->

<!-- begin two -->
old two
<!-- end two -->
EOF

# Standard input into an existing section: the other one is untouched.
printf '| a |\n|---|\n| 1 |\n' | "$UPDATE" --results "$R" --section one --command "bench/x.sh --y 1" 2>/dev/null
check "stdin: new body" "| 1 |" "$(section "$R" one | tail -n 1)"
# shellcheck disable=SC2016  # the backquotes are Markdown
check "stdin: heading names the command" '### `bench/x.sh --y 1`' "$(section "$R" one | head -n 1)"
check "stdin: old body gone" 0 "$(grep -c 'old one' "$R" || true)"
check "stdin: other section kept" "old two" "$(section "$R" two)"
check "stdin: one begin marker" 1 "$(grep -c '<!-- begin one -->' "$R")"

# A command: its standard output, in the section named after it (dashes dropped).
"$UPDATE" --results "$R" -- echo made --here >/dev/null 2>&1
check "command: section added" "made --here" "$(section "$R" "echo made here" | tail -n 1)"
check "command: added at the end" '<!-- end echo made here -->' "$(tail -n 1 "$R")"
"$UPDATE" --results "$R" -- sh -c 'echo second' >/dev/null 2>&1
"$UPDATE" --results "$R" -- sh -c 'echo third' >/dev/null 2>&1
check "command: a rerun replaces" "third" "$(section "$R" "sh c echo third" | tail -n 1)"
"$UPDATE" --results "$R" --section two -- sh -c 'echo new two' >/dev/null 2>&1
check "command: --section" "new two" "$(section "$R" two | tail -n 1)"

# A failing or silent benchmark leaves the file as it was.
cp "$R" "$T/before.md"
status=0
"$UPDATE" --results "$R" --section two -- sh -c 'echo partial; exit 3' >/dev/null 2>&1 || status=$?
check "failure: status passed on" 3 "$status"
check "failure: file unchanged" "" "$(diff "$T/before.md" "$R")"
status=0
"$UPDATE" --results "$R" --section two -- true >/dev/null 2>&1 || status=$?
check "no output: fails" 1 "$status"
check "no output: file unchanged" "" "$(diff "$T/before.md" "$R")"
# A section with one marker only is an error, not a second copy.
printf '<!-- begin half -->\nx\n' >> "$R"
cp "$R" "$T/before.md"
status=0
echo y | "$UPDATE" --results "$R" --section half --command c >/dev/null 2>&1 || status=$?
check "half a section: fails" 1 "$status"
check "half a section: file unchanged" "" "$(diff "$T/before.md" "$R")"

[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "all checks passed"
