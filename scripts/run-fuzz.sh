#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the libFuzzer target fuzz/fuzz_mesh.cpp with clang (ASan + UBSan) in
# build-fuzz/, replays every known crasher in fuzz/regressions/, then fuzzes
# for SECONDS (default 60) starting from a temporary copy of fuzz/corpus/ (the
# repository is never modified). Exits non-zero when a regression input still
# fails or the fuzzer finds a crash, printing the reproducer's path.
#
#   scripts/run-fuzz.sh [SECONDS]
#
# Environment:
#   SODT_FUZZ_BUILD_DIR  build directory (default build-fuzz)
#   SODT_FUZZ_JOBS       parallel fuzzing processes (libFuzzer -fork=N; default 1)
#   SODT_FUZZ_WORKDIR    keep the evolving corpus here instead of a temporary
#                        directory (reused, and grown, by later runs)
#   SODT_FUZZ_ARGS       extra libFuzzer arguments
#   SODT_JOBS            build parallelism (default 2)
# See fuzz/README.md for long runs, reproducing and minimising.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECONDS_TO_RUN="${1:-60}"
BUILD="${SODT_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
JOBS="${SODT_FUZZ_JOBS:-1}"
BUILD_JOBS="${SODT_JOBS:-2}"
case "$SECONDS_TO_RUN" in
  ''|*[!0-9]*) echo "usage: $0 [SECONDS]" >&2; exit 2 ;;
esac

CC=clang CXX=clang++ cmake -S "$ROOT/fuzz" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD" -j"$BUILD_JOBS"
FUZZER="$BUILD/fuzz_mesh"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
ARTIFACTS="$BUILD/artifacts"
mkdir -p "$ARTIFACTS"
COMMON=(-max_len=4096 -timeout=10 -rss_limit_mb=2048 -dict="$ROOT/fuzz/ply.dict")

status=0

# 1. Regression check: every known crasher must now run cleanly.
regressions=()
for r in "$ROOT"/fuzz/regressions/*; do
  [ -f "$r" ] || continue
  case "$(basename "$r")" in README*|*.md) continue ;; esac
  regressions+=("$r")
done
if [ "${#regressions[@]}" -gt 0 ]; then
  echo "== regression inputs: ${#regressions[@]}"
  failed=()
  for r in "${regressions[@]}"; do
    if ! SODT_FUZZ_DISTANCE_EVERY=1 "$FUZZER" "${COMMON[@]}" -artifact_prefix="$ARTIFACTS/" "$r" >"$ARTIFACTS/regression.log" 2>&1; then
      failed+=("$r")
      grep -E 'ERROR: (Address|Undefined|Leak)Sanitizer|runtime error|FINDING|deadly signal|timeout' \
        "$ARTIFACTS/regression.log" | head -n 2 | sed 's/^/     /'
    fi
  done
  if [ "${#failed[@]}" -gt 0 ]; then
    echo "== ${#failed[@]} regression input(s) still fail; reproduce with:"
    for r in "${failed[@]}"; do echo "   $FUZZER $r"; done
    status=1
  else
    echo "== all regression inputs pass"
  fi
fi

# 2. Fuzz from a copy of the seed corpus.
if [ "$SECONDS_TO_RUN" -gt 0 ]; then
  if [ -n "${SODT_FUZZ_WORKDIR:-}" ]; then
    WORK="$SODT_FUZZ_WORKDIR"
    mkdir -p "$WORK/corpus"
  else
    WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-fuzz.XXXXXX")"
    trap 'rm -rf "$WORK"' EXIT
    mkdir -p "$WORK/corpus"
  fi
  cp -n "$ROOT"/fuzz/corpus/* "$WORK/corpus/"
  before="$(ls -1 "$ARTIFACTS" | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | sort || true)"
  extra=()
  [ "$JOBS" -gt 1 ] && extra+=(-fork="$JOBS" -ignore_crashes=0)
  # shellcheck disable=SC2206
  [ -n "${SODT_FUZZ_ARGS:-}" ] && extra+=($SODT_FUZZ_ARGS)
  echo "== fuzzing for ${SECONDS_TO_RUN}s ($JOBS process(es)), corpus in $WORK/corpus"
  fuzz_status=0
  (cd "$WORK" && "$FUZZER" "${COMMON[@]}" -max_total_time="$SECONDS_TO_RUN" -print_final_stats=1 \
     -artifact_prefix="$ARTIFACTS/" "${extra[@]}" "$WORK/corpus") 2>&1 | tee "$BUILD/fuzz.log" | \
     grep -vE '^#[0-9]+\s+(NEW|REDUCE|pulse)' || true
  fuzz_status=${PIPESTATUS[0]}
  after="$(ls -1 "$ARTIFACTS" | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | sort || true)"
  new="$(comm -13 <(echo "$before") <(echo "$after") | sed '/^$/d' | grep -v '^slow-unit-' || true)"
  # Final stats (absent after a crash); in fork mode the last progress line.
  execs="$( (grep -Eo 'stat::number_of_executed_units: +[0-9]+' "$BUILD/fuzz.log" || true) | awk '{s+=$2} END{print s+0}')"
  rate="$( (grep -Eo 'stat::average_exec_per_sec: +[0-9]+' "$BUILD/fuzz.log" || true) | awk '{s+=$2} END{print s+0}')"
  if [ "$execs" = 0 ]; then
    last="$( (grep -E '^#[0-9]+' "$BUILD/fuzz.log" || true) | tail -n 1)"
    execs="$(echo "$last" | sed -nE 's/^#([0-9]+).*/\1/p')"
    rate="$(echo "$last" | sed -nE 's/.*exec\/s:? ([0-9]+).*/\1/p')"
  fi
  echo "== fuzzing done: ${execs:-?} executions, ${rate:-?} exec/s (last reported), log $BUILD/fuzz.log"
  if [ -n "$new" ] || [ "$fuzz_status" -ne 0 ]; then
    echo "== the fuzzer found a problem (exit $fuzz_status); reproducer(s):"
    for a in $new; do echo "   $FUZZER $ARTIFACTS/$a"; done
    echo "   (copy it to fuzz/regressions/ once understood; see fuzz/README.md)"
    status=1
  fi
fi
exit "$status"
