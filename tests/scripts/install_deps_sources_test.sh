#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# scripts/install-deps.sh adds a deb-src source made from the system's own
# deb entries (any mirror), only when none is configured, and stops with a
# clear error when there is no bookworm entry to copy. Run on fake apt trees.
set -u
SCRIPT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/scripts/install-deps.sh"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-aptsrc.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
run() {  # run DIR: the script on apt tree DIR; its output in DIR.out, status returned
  SODT_APT_DIR="$1" SODT_APT_SOURCES_ONLY=1 bash "$SCRIPT" >"$1.out" 2>&1
}
written() { cat "$1/sources.list.d/sodt-deb-src.sources" 2>/dev/null; }

# 1. One-line entries on a mirror, with a key, several components.
t="$WORK/list"
mkdir -p "$t/sources.list.d"
cat >"$t/sources.list" <<'L'
# a comment
deb [arch=amd64 signed-by=/usr/share/keyrings/mirror.gpg] http://mirror.example.org/debian bookworm main contrib
deb http://security.example.org/debian-security bookworm-security main
deb http://mirror.example.org/debian bullseye main
L
run "$t" || fail "one-line entries: status $? ($(cat "$t.out"))"
out="$(written "$t")"
grep -q '^URIs: http://mirror.example.org/debian$' <<<"$out" || fail "one-line: mirror URI not copied: $out"
grep -q '^Components: main contrib$' <<<"$out" || fail "one-line: components not copied"
grep -q '^Signed-By: /usr/share/keyrings/mirror.gpg$' <<<"$out" || fail "one-line: key not copied"
grep -q '^Suites: bookworm-security$' <<<"$out" || fail "one-line: security suite not copied"
grep -q 'bullseye' <<<"$out" && fail "one-line: a bullseye entry was copied"
[ "$(grep -c '^Types: deb-src$' <<<"$out")" -eq 2 ] || fail "one-line: expected 2 stanzas: $out"
grep -q 'deb.debian.org' <<<"$out" && fail "one-line: a fixed mirror was named"

# 2. deb822 entries (Debian 12's default form), one disabled.
t="$WORK/deb822"
mkdir -p "$t/sources.list.d"
cat >"$t/sources.list.d/debian.sources" <<'S'
Types: deb
# a comment
URIs: http://ftp.example.net/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://other.example.net/debian
Suites: bookworm
Components: main
Enabled: no
S
run "$t" || fail "deb822: status $? ($(cat "$t.out"))"
out="$(written "$t")"
grep -q '^URIs: http://ftp.example.net/debian$' <<<"$out" || fail "deb822: mirror not copied: $out"
grep -q '^Suites: bookworm bookworm-updates$' <<<"$out" || fail "deb822: suites not copied"
grep -q 'other.example.net' <<<"$out" && fail "deb822: a disabled stanza was copied"
grep -q '^# a comment' <<<"$out" && fail "deb822: a comment was copied"
[ "$(grep -c '^Types: deb-src$' <<<"$out")" -eq 1 ] || fail "deb822: expected 1 stanza: $out"

# 3. A deb-src entry already there: nothing is written.
t="$WORK/present"
mkdir -p "$t/sources.list.d"
printf 'deb http://m.example/debian bookworm main\ndeb-src http://m.example/debian bookworm main\n' >"$t/sources.list"
run "$t" || fail "deb-src present: status $?"
[ -e "$t/sources.list.d/sodt-deb-src.sources" ] && fail "deb-src present: a file was written"

# 4. Nothing for bookworm to copy: a clear error, nothing written.
t="$WORK/none"
mkdir -p "$t/sources.list.d"
printf 'deb http://m.example/debian bullseye main\n' >"$t/sources.list"
if run "$t"; then fail "no bookworm entry: exit 0"; fi
grep -q 'no deb entry for bookworm' "$t.out" || fail "no bookworm entry: message was: $(cat "$t.out")"
[ -e "$t/sources.list.d/sodt-deb-src.sources" ] && fail "no bookworm entry: a file was written"

# 5. The file written makes the next run find a deb-src entry.
run "$WORK/deb822" || fail "second run: status $?"
grep -q 'adding' "$WORK/deb822.out" && fail "second run added the source again"

[ "$fails" -eq 0 ] && echo "install-deps sources: all cases pass"
exit "$fails"
