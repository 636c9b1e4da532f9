#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the core, the I/O library, the CLI and their test suites with
# AddressSanitizer + UndefinedBehaviorSanitizer (+ LeakSanitizer) in a separate
# build directory (build-asan/, no MeshLab plugin, no benchmarks, no developer
# tools) and runs the whole ctest suite there. Any sanitizer report fails the run, including one
# from a child process (the CLI tests run the `sodt` binary and mostly look at
# its exit code):
#  - sanitizers exit with status 86, which no CLI test expects;
#  - ASan/LSan reports also go to files under build-asan/sanitizer-logs/
#    (gcc's UBSan ignores log_path when linked with ASan: its reports are on
#    the child's stderr), printed at the end;
#  - the ctest log is searched for any report that reached a test's output.
#
#   scripts/run-sanitizers.sh [extra ctest arguments, e.g. -R CliTest]
#
# Environment: SODT_ASAN_BUILD_DIR (default build-asan), SODT_JOBS (default 2),
# CC/CXX (default gcc/g++; clang/clang++ work too), SODT_ASAN_BUILD_TYPE
# (default RelWithDebInfo, compiled -O1 -g1: line tables, enough for the
# reports' stack traces and a third quicker to build than -g; "Debug" also
# enables asserts),
# SODT_ASAN_EXTRA_FLAGS (default -fsanitize=float-cast-overflow with gcc, whose
# -fsanitize=undefined leaves it out while clang's includes it).
# Run scripts/install-deps.sh once before.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SODT_ASAN_BUILD_DIR:-$ROOT/build-asan}"
JOBS="${SODT_JOBS:-2}"
BUILD_TYPE="${SODT_ASAN_BUILD_TYPE:-RelWithDebInfo}"
export CC="${CC:-gcc}" CXX="${CXX:-g++}"

SAN_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
if [ -z "${SODT_ASAN_EXTRA_FLAGS+x}" ]; then
  case "$("$CXX" --version 2>/dev/null | head -n1)" in
    *clang*) SODT_ASAN_EXTRA_FLAGS="" ;;
    *) SODT_ASAN_EXTRA_FLAGS="-fsanitize=float-cast-overflow" ;;
  esac
fi
SAN_FLAGS="$SAN_FLAGS $SODT_ASAN_EXTRA_FLAGS"

start=$(date +%s)
cmake -S "$ROOT" -B "$BUILD" \
  -DCMAKE_BUILD_TYPE="$BUILD_TYPE" \
  -DCMAKE_CXX_FLAGS="$SAN_FLAGS" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DCMAKE_EXE_LINKER_FLAGS="$SAN_FLAGS" \
  -DCMAKE_SHARED_LINKER_FLAGS="$SAN_FLAGS" \
  -DSODT_BUILD_PLUGIN=OFF \
  -DSODT_BUILD_BENCH=OFF \
  -DSODT_BUILD_TOOLS=OFF \
  -DSODT_BUILD_TESTS=ON
# gtest_discover_tests runs the test binaries while building: give them the
# same sanitizer settings as the test run below (reports on stderr there).
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=86 ASAN_OPTIONS=detect_leaks=1:exitcode=86 \
  cmake --build "$BUILD" -j"$JOBS"
built=$(date +%s)

LOGS="$BUILD/sanitizer-logs"
rm -rf "$LOGS"
mkdir -p "$LOGS"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=86:log_path=$LOGS/ubsan"
export ASAN_OPTIONS="detect_leaks=1:exitcode=86:log_path=$LOGS/asan"
export LSAN_OPTIONS="exitcode=86:log_path=$LOGS/lsan"

status=0
(cd "$BUILD" && ctest --output-on-failure -j"$JOBS" "$@") || status=$?
done_t=$(date +%s)

reports=$(find "$LOGS" -type f -size +0 | sort)
if [ -n "$reports" ]; then
  echo
  echo "==== sanitizer reports ($(echo "$reports" | wc -l) file(s)) ===="
  for f in $reports; do
    echo "---- $f"
    cat "$f"
  done
  [ "$status" -ne 0 ] || status=1
fi
LOG="$BUILD/Testing/Temporary/LastTest.log"
PATTERN='runtime error:|ERROR: (AddressSanitizer|LeakSanitizer)|SUMMARY: (AddressSanitizer|UndefinedBehaviorSanitizer|LeakSanitizer)'
if [ -f "$LOG" ] && grep -Eq "$PATTERN" "$LOG"; then
  echo
  echo "==== sanitizer reports in test output ($LOG) ===="
  grep -En "$PATTERN|^[0-9]+/[0-9]+ Test: " "$LOG" | grep -E -B1 "$PATTERN" | grep -v '^--$' | head -n 60
  [ "$status" -ne 0 ] || status=1
fi
echo
echo "run-sanitizers: build $((built - start)) s, tests $((done_t - built)) s, exit $status"
exit "$status"
