#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds MeshLab 2025.07 and PyMeshLab 2025.7 into their cache folder if they
# are not there yet (scripts/build-meshlab-2025.sh), configures and builds
# everything (Release) in build/ (the plugin for MeshLab 2020.09, 2025.07 and
# PyMeshLab, the CLI, the tests), runs the sanitizer build's tests (ASan +
# UBSan) and a short fuzzing run, then the whole test suite through ctest.
# Run scripts/install-deps.sh once before.
#   SODT_QUICK=1   skip the sanitizer build and the fuzzing run
#   SODT_FUZZ_SECONDS=N   fuzzing time (default 60)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SODT_BUILD_DIR:-$ROOT/build}"
JOBS="${SODT_JOBS:-$(nproc)}"

echo "== MeshLab 2025.07 and PyMeshLab 2025.7 (built once per machine) =="
"$ROOT/scripts/build-meshlab-2025.sh" all
ML2025="$("$ROOT/scripts/build-meshlab-2025.sh" --print-dir)"
echo "== build =="
# Tests, benchmarks and tools on: scripts/demo.sh builds the same folder without them.
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DSODT_MESHLAB2025_DIR="$ML2025" -DSODT_BUILD_PLUGIN=ON \
  -DSODT_BUILD_TESTS=ON -DSODT_BUILD_BENCH=ON -DSODT_BUILD_TOOLS=ON
cmake --build "$BUILD" -j"$JOBS"
if [ "${SODT_QUICK:-0}" != 1 ]; then
  echo "== sanitizer build (ASan + UBSan) =="
  "$ROOT/scripts/run-sanitizers.sh"
  echo "== fuzzing (${SODT_FUZZ_SECONDS:-60} s) =="
  "$ROOT/scripts/run-fuzz.sh" "${SODT_FUZZ_SECONDS:-60}"
fi
echo "== test suite =="
cd "$BUILD"
# Every label, "slow" (the full fixtures of the equivalence tests) included.
ctest --output-on-failure -j"$JOBS" "$@"
