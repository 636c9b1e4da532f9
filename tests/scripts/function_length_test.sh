#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The core stays readable: SodtSmoother::Apply is the list of a run's stages
# (at most 60 lines; a new feature adds a stage in stages.h instead), and no
# function of vcg_core/ runs past 120 lines, data tables (paramTable() and
# the lambda that fills it) excepted. Lengths are universal-ctags' start and
# end lines.
# Usage: function_length_test.sh [DIR]   (default: this checkout's vcg_core)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
dir="${1:-$root/vcg_core}"
ctags_bin="$(command -v ctags-universal || command -v ctags || true)"
[ -n "$ctags_bin" ] || { echo "FAIL: universal-ctags is not installed (scripts/install-deps.sh installs it)"; exit 1; }
"$ctags_bin" --version 2>/dev/null | grep -q 'Universal Ctags' ||
  { echo "FAIL: $ctags_bin is not universal-ctags"; exit 1; }

# one line per function: length, file, name, scope
lengths="$("$ctags_bin" -R --languages=C++ --langmap=C++:+.h --kinds-C++=f --fields=+neS -o - "$dir" |
  awk -F'\t' '{
    line = ""; end = ""; scope = "";
    for (i = 4; i <= NF; i++) {
      if ($i ~ /^line:/) line = substr($i, 6);
      else if ($i ~ /^end:/) end = substr($i, 5);
      else if ($i ~ /^(struct|class|function|namespace):/) scope = $i;
    }
    if (line != "" && end != "") print end - line + 1 "\t" $2 "\t" $1 "\t" scope;
  }')"
count="$(printf '%s\n' "$lengths" | grep -c . || true)"
[ "$count" -gt 100 ] || { echo "FAIL: ctags found only $count functions in $dir"; exit 1; }

bad=0
apply="$(printf '%s\n' "$lengths" | awk -F'\t' '$3 == "Apply" && $2 ~ /sodt\/smoother\.h$/')"
if [ -z "$apply" ]; then
  echo "FAIL: no SodtSmoother::Apply in smoother.h"
  bad=1
elif [ "$(printf '%s\n' "$apply" | cut -f1)" -gt 60 ]; then
  echo "FAIL: Apply has $(printf '%s\n' "$apply" | cut -f1) lines (at most 60: add a stage in stages.h instead)"
  bad=1
fi
long="$(printf '%s\n' "$lengths" | awk -F'\t' '$1 > 120 && $3 != "paramTable" && $4 !~ /paramTable/')"
if [ -n "$long" ]; then
  echo "FAIL: functions longer than 120 lines:"
  printf '%s\n' "$long"
  bad=1
fi
[ "$bad" -eq 0 ] || exit 1
echo "ok: $count functions, Apply $(printf '%s\n' "$apply" | cut -f1) lines, none above 120 but the parameter table"
