#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The header-only core (vcg_core/sodt/) stands alone and is layered:
#  - none of its files includes the library beside it (vcg_core/sodt_io/:
#    mesh types, files, measures), so that any vcg mesh type can use the core;
#  - its folders include one way, from the run down to the maths:
#      params.h (0) < maths (1) < mesh (2) < guards (3) < sweeps (4)
#      < remesh, denoise (5, neither includes the other) < the top level (6)
#    A file may include its own folder, params.h and lower folders only.
# Usage: core_boundary_test.sh [CORE_DIR]   (default: this checkout's core)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
core="${1:-$root/vcg_core/sodt}"
[ -f "$core/smoother.h" ] || { echo "FAIL: no core at $core"; exit 1; }
found="$(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"](sodt_io/|(\.\./)+sodt_io/)' "$core" || true)"
if [ -n "$found" ]; then
  echo "FAIL: the core includes the I/O library:"
  echo "$found"
  exit 1
fi

# rank of a header, by its path relative to the core
rank() {
  case "$1" in
    params.h) echo 0 ;;
    maths/*) echo 1 ;;
    mesh/*) echo 2 ;;
    guards/*) echo 3 ;;
    sweeps/*) echo 4 ;;
    remesh/* | denoise/*) echo 5 ;;
    */*) echo "" ;;  # a folder without a rank
    *) echo 6 ;;
  esac
}

bad=0
files=0
while IFS= read -r path; do
  files=$((files + 1))
  rel="${path#"$core"/}"
  from="$(rank "$rel")"
  if [ -z "$from" ]; then
    echo "FAIL: $rel lies in a folder without a rank (add it to $0)"
    bad=1
    continue
  fi
  dir="$(dirname "$rel")"
  while IFS= read -r inc; do
    # resolve the quoted include against the including file's folder
    target="$(cd "$core/$dir" && realpath -m --relative-to="$core" "$inc")"
    [ -f "$core/$target" ] || continue  # not a core header (vcglib, std)
    to="$(rank "$target")"
    tdir="$(dirname "$target")"
    if [ "$tdir" != "$dir" ] && { [ -z "$to" ] || [ "$to" -ge "$from" ]; } && [ "$target" != params.h ]; then
      echo "FAIL: $rel includes $target, a folder at or above its own"
      bad=1
    fi
  done < <(sed -nE 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"([^"]+)".*/\1/p' "$path")
done < <(find "$core" -name '*.h' | sort)
[ "$bad" -eq 0 ] || exit 1
# The check itself must be able to fail: an upward include planted in a
# copy of the core is caught.
if [ -z "${1:-}" ]; then
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  cp -r "$core" "$tmp/sodt"
  echo '#include "../sweeps/sweeper.h"' >>"$tmp/sodt/maths/odt.h"
  if bash "$0" "$tmp/sodt" >/dev/null; then
    echo "FAIL: an include from maths/ up to sweeps/ went unnoticed"
    exit 1
  fi
fi
echo "ok: $files core files, none includes sodt_io, every include points down"
