#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The header-only core (vcg_core/sodt/) stands alone: none of its files
# includes the library beside it (vcg_core/sodt_io/: mesh types, files,
# measures), so that any vcg mesh type can use the core without them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
core="$root/vcg_core/sodt"
[ -f "$core/smoother.h" ] || { echo "FAIL: no core at $core"; exit 1; }
found="$(grep -nE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"](sodt_io/|\.\./sodt_io/)' "$core"/* || true)"
if [ -n "$found" ]; then
  echo "FAIL: the core includes the I/O library:"
  echo "$found"
  exit 1
fi
echo "ok: $(ls "$core" | wc -l) core files, none includes sodt_io"
