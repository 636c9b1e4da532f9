#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Peak memory of `sodt smooth` on the 4M benchmark mesh of sodt_bench_scaling
# (meshes/blobs_mc.ply subdivided 5 times: 4,907,010 vertices), against the
# memory of the loaded mesh alone. The target is peak <= 2.5 x loaded mesh.
#
# Usage: bench/scaling.sh [--build DIR] [--work DIR] [--size SIZE]
#                         [--iterations N] [--threads T] [--keep] [--results FILE]
#   --build DIR       build tree with cli/sodt and bench/sodt_bench_scaling
#                     (default: build/ next to this folder); both are built
#                     there first (-j1) if missing
#   --work DIR        where IN.ply, the outputs and the logs go (default: a new
#                     temporary directory, removed at the end unless --keep)
#   --size SIZE       a size of sodt_bench_scaling --sizes (default 4M)
#   --iterations N    sweeps of each smoothing run (default 5)
#   --threads T       SodtParams::threads of the --smooth-only run (default:
#                     the library default); the CLI run uses the CLI default
#   --keep            keep the work directory
#   --results FILE    also write the summary into FILE (bench/RESULTS.md), in
#                     the section "scaling.sh size SIZE iterations N [threads T]"
#                     (bench/update_results.py)
#
# What runs, one process at a time, each under GNU time (/usr/bin/time -v):
#   1. sodt_bench_scaling --write-mesh SIZE IN.ply   (binary PLY, float)
#   2. sodt_bench_scaling --load-only IN.ply
#        loads IN.ply with sodt::loadMesh into the double mesh sodt::MeshD,
#        exactly as the CLI does, and exits: its peak RSS is "the loaded mesh
#        alone" (the loader's transient buffers and the process's own few MB
#        included, as in every run below)
#   3. sodt smooth IN.ply OUT.ply --iterations N --quiet
#        the CLI as a user runs it; it measures the input and the output
#        (angles, surface distance, inverted faces) and keeps the input's
#        positions (and faces, with --flips) for that. Then the same with
#        --distance off, which leaves out the surface distance (the other
#        measures are cheap), when `sodt smooth --help` lists it.
#   4. sodt_bench_scaling --smooth-only IN.ply OUT2.ply --sweeps N
#        load, SodtSmoother::Apply with the default parameters, save with the
#        CLI's save function: `sodt smooth` without its measurements and what
#        it keeps of the input. Reports the peak RSS of each phase.
set -u

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="$HERE/../build"
WORK=""
SIZE=4M
ITER=5
THREADS=""
KEEP=0
RESULTS=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) BUILD="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --iterations) ITER="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --keep) KEEP=1; shift ;;
    --results) RESULTS="$2"; shift 2 ;;
    -h|--help) sed -n '3,39p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

die() { echo "error: $*" >&2; exit 1; }
SODT="$BUILD/cli/sodt"
BENCH="$BUILD/bench/sodt_bench_scaling"
if [ ! -x "$SODT" ] || [ ! -x "$BENCH" ]; then
  echo "building sodt and sodt_bench_scaling in $BUILD ..."
  cmake --build "$BUILD" -j1 --target sodt sodt_bench_scaling >/dev/null \
    || die "build failed (configure first: cmake -S . -B build -DCMAKE_BUILD_TYPE=Release)"
fi
grep -q '^CMAKE_BUILD_TYPE:STRING=Release' "$BUILD/CMakeCache.txt" 2>/dev/null \
  || echo "warning: $BUILD is not a Release build; timings will not be representative"
/usr/bin/time -v true >/dev/null 2>&1 || die "needs GNU time at /usr/bin/time (Debian: apt-get install time)"

if [ -z "$WORK" ]; then
  WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-scaling.XXXXXX")" || die "mktemp failed"
  [ "$KEEP" -eq 1 ] || trap 'rm -rf "$WORK"' EXIT
else
  mkdir -p "$WORK" || die "cannot create $WORK"
fi
IN="$WORK/IN.ply"

# timed NAME CMD...: runs CMD under GNU time; its stdout goes to NAME.out, GNU
# time's report to NAME.time. Dies if CMD fails.
timed() {
  local name="$1"
  shift
  echo "== $* =="
  /usr/bin/time -v -o "$WORK/$name.time" "$@" >"$WORK/$name.out" \
    || die "'$*' failed (status $?)$(tail -n 3 "$WORK/$name.time" 2>/dev/null | sed 's/^/ /')"
}
# peak_kb NAME: GNU time's maximum resident set size of run NAME, in kB.
peak_kb() { sed -nE 's/^\s*Maximum resident set size \(kbytes\): ([0-9]+)/\1/p' "$WORK/$1.time"; }
# wall_s NAME: GNU time's elapsed wall-clock time of run NAME, in seconds.
wall_s() {
  sed -nE 's/^\s*Elapsed \(wall clock\) time.*: (.*)/\1/p' "$WORK/$1.time" \
    | awk -F: '{ s = 0; for (i = 1; i <= NF; ++i) s = s * 60 + $i; printf "%.1f", s }'
}
# value NAME KEY: the "KEY value" line printed by a sodt_bench_scaling mode.
value() { awk -v k="$2" '$1 == k { print $2; exit }' "$WORK/$1.out"; }
mb() { awk -v k="$1" 'BEGIN { printf "%.0f", k / 1024 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }

MEM_TOTAL_KB="$(awk '/^MemTotal:/ { print $2 }' /proc/meminfo)"
MACHINE="machine: $(nproc) cores, $(mb "$MEM_TOTAL_KB") MB RAM; load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "$MACHINE"
echo "work directory: $WORK"

timed write "$BENCH" --write-mesh "$SIZE" "$IN"
cat "$WORK/write.out"
timed load "$BENCH" --load-only "$IN"
timed cli "$SODT" smooth "$IN" "$WORK/OUT_cli.ply" --iterations "$ITER" --quiet
# The option of `sodt smooth` that skips the surface distance, if the CLI has it.
SKIP_OPT=""
"$SODT" smooth --help | grep -q -- '--distance on|off' && SKIP_OPT="--distance off"
if [ -n "$SKIP_OPT" ]; then
  # shellcheck disable=SC2086  # two words
  timed cli_skip "$SODT" smooth "$IN" "$WORK/OUT_cli_skip.ply" --iterations "$ITER" --quiet $SKIP_OPT
fi
SMOOTH_ARGS=(--smooth-only "$IN" "$WORK/OUT_core.ply" --sweeps "$ITER")
[ -n "$THREADS" ] && SMOOTH_ARGS+=(--threads "$THREADS")
timed core "$BENCH" "${SMOOTH_ARGS[@]}"

LOAD_KB="$(peak_kb load)"
# The summary: printed, and written into the results file with --results.
report() {
  echo "$MACHINE"
  echo
  echo "peak memory, $(value load vertices) vertices, $(value load faces) faces, $ITER sweeps"
  echo
  echo "loaded mesh alone: peak RSS $(mb "$LOAD_KB") MB (load-only process); RSS after loading" \
       "$(mb "$(value load rss_kb)") MB; vertex + face vectors $(mb "$(value load mesh_vectors_kb)") MB" \
       "(sodt::MeshD); loading took $(value load load_seconds) s"
  echo
  echo "| run | peak RSS (MB) | peak / loaded mesh | wall (s) |"
  echo "|---|---:|---:|---:|"
  echo "| load only (sodt_bench_scaling --load-only) | $(mb "$LOAD_KB") | 1.00 | $(wall_s load) |"
  echo "| sodt smooth --iterations $ITER (measures input and output) | $(mb "$(peak_kb cli)") | $(ratio "$(peak_kb cli)" "$LOAD_KB") | $(wall_s cli) |"
  if [ -n "$SKIP_OPT" ]; then
    echo "| sodt smooth --iterations $ITER $SKIP_OPT | $(mb "$(peak_kb cli_skip)") | $(ratio "$(peak_kb cli_skip)" "$LOAD_KB") | $(wall_s cli_skip) |"
  else
    echo "| sodt smooth --distance off | n/a: \`sodt smooth --help\` lists no --distance | | |"
  fi
  # GNU time reads the kernel's peak, which --smooth-only resets between its
  # phases: the process's own peak_rss_kb (the largest phase peak) is the peak.
  CORE_KB="$(awk -v a="$(peak_kb core)" -v b="$(value core peak_rss_kb)" 'BEGIN { print (b + 0 > a + 0) ? b : a }')"
  echo "| load + Apply + save, no measurements (sodt_bench_scaling --smooth-only) | $(mb "$CORE_KB") | $(ratio "$CORE_KB" "$LOAD_KB") | $(wall_s core) |"
  echo
  SMOOTH_PEAK="$(value core smooth_peak_rss_kb)"
  if [ -n "$SMOOTH_PEAK" ]; then
    echo "phases of the --smooth-only run (peak RSS of each, the loaded mesh included):" \
         "load $(mb "$(value core load_peak_rss_kb)") MB, Apply $(mb "$SMOOTH_PEAK") MB ($(value core smooth_seconds) s)," \
         "save $(mb "$(value core save_peak_rss_kb)") MB ($(value core save_seconds) s; the save reads the file back, positions and triangles only)"
    echo
  fi
  CLI_RATIO="$(ratio "$(peak_kb cli)" "$LOAD_KB")"
  if awk -v r="$CLI_RATIO" 'BEGIN { exit !(r <= 2.5) }'; then
    echo "target peak <= 2.5 x loaded mesh: met by sodt smooth ($CLI_RATIO x)"
  else
    echo "target peak <= 2.5 x loaded mesh: NOT met by sodt smooth ($CLI_RATIO x)"
  fi
}
echo
report | tee "$WORK/report.md"
if [ -n "$RESULTS" ]; then
  NAME="scaling.sh size $SIZE iterations $ITER${THREADS:+ threads $THREADS}"
  "$HERE/update_results.py" --results "$RESULTS" --section "$NAME" \
    --command "bench/scaling.sh --size $SIZE --iterations $ITER${THREADS:+ --threads $THREADS}" <"$WORK/report.md" \
    || die "could not update $RESULTS"
fi
