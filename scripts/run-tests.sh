#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Configures and builds everything (Release) in build/, runs the sanitizer
# build's tests (ASan + UBSan) and a short fuzzing run, then the whole test
# suite through ctest. Run scripts/install-deps.sh once before.
#   SODT_QUICK=1   skip the sanitizer build and the fuzzing run
#   SODT_FUZZ_SECONDS=N   fuzzing time (default 60)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SODT_BUILD_DIR:-$ROOT/build}"
JOBS="${SODT_JOBS:-$(nproc)}"

cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD" -j"$JOBS"
if [ "${SODT_QUICK:-0}" != 1 ]; then
  echo "== sanitizer build (ASan + UBSan) =="
  "$ROOT/scripts/run-sanitizers.sh"
  echo "== fuzzing (${SODT_FUZZ_SECONDS:-60} s) =="
  "$ROOT/scripts/run-fuzz.sh" "${SODT_FUZZ_SECONDS:-60}"
fi
echo "== test suite =="
cd "$BUILD"
ctest --output-on-failure -j"$JOBS" "$@"
