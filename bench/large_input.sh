#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Large-input run of the `sodt` CLI: generates a ~5M-triangle closed mesh and
# smooths it once, measuring time per phase, peak memory and file sizes.
# Not part of the test suite (it takes minutes and a few GB of RAM).
#
# Usage: bench/large_input.sh [--build DIR] [--work DIR] [--subdiv N | --frequency N]
#                             [--iterations N] [--busy N] [--keep] [--results FILE]
#   --build DIR       build tree with cli/sodt and bench/sodt_make_big_sphere
#                     (default: build/ next to this folder); both targets are
#                     built there first if missing
#   --work DIR        where BIG.ply, OUT.ply and the logs go (default: a new
#                     temporary directory, removed at the end unless --keep)
#   --subdiv N        icosphere level (default 9: 2,621,442 vertices,
#                     5,242,880 faces)
#   --frequency N     geodesic sphere of frequency N instead (724: 5,241,762
#                     vertices, 10,483,520 faces)
#   --iterations N    sweeps (default 5)
#   --busy N          keep N other processes spinning on the CPU during the
#                     run, as on a shared machine (default 0)
#   --keep            keep the work directory
#   --results FILE    also write the results into FILE (bench/RESULTS.md), in
#                     the section "large_input.sh subdiv N|frequency N
#                     iterations N busy N" (bench/update_results.py)
#
# What runs:
#   sodt_make_big_sphere BIG.ply --subdiv N  (or --frequency N)
#   /usr/bin/time -v sodt smooth BIG.ply OUT.ply --iterations N --report R.json
# The smoother runs under `script`, which gives it a pseudo-terminal: the CLI
# draws its progress bar only on a terminal. Every '\r'-separated update of
# that status line is time-stamped as it arrives; the time between "loading
# BIG.ply..." and "measuring input..." is the load time, and so on for each
# phase. Peak RSS comes from GNU time (Debian package `time`); without it the
# script polls VmHWM in /proc/PID/status instead.
set -u

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="$HERE/../build"
WORK=""
SUBDIV=9
FREQ=""
BUSY=0
ITER=5
KEEP=0
RESULTS=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) BUILD="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --subdiv) SUBDIV="$2"; shift 2 ;;
    --frequency) FREQ="$2"; shift 2 ;;
    --busy) BUSY="$2"; shift 2 ;;
    --iterations) ITER="$2"; shift 2 ;;
    --keep) KEEP=1; shift ;;
    --results) RESULTS="$2"; shift 2 ;;
    -h|--help) sed -n '3,36p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

die() { echo "error: $*" >&2; exit 1; }
BUSY_PIDS=()
RM_WORK=0
cleanup() {
  [ "${#BUSY_PIDS[@]}" -gt 0 ] && kill "${BUSY_PIDS[@]}" 2>/dev/null
  [ "$RM_WORK" -eq 1 ] && rm -rf "$WORK"
  return 0
}
trap cleanup EXIT
SODT="$BUILD/cli/sodt"
GEN="$BUILD/bench/sodt_make_big_sphere"
if [ ! -x "$SODT" ] || [ ! -x "$GEN" ]; then
  echo "building sodt and sodt_make_big_sphere in $BUILD ..."
  cmake --build "$BUILD" --target sodt sodt_make_big_sphere >/dev/null || die "build failed (configure first: cmake -S . -B build -DCMAKE_BUILD_TYPE=Release)"
fi
grep -q '^CMAKE_BUILD_TYPE:STRING=Release' "$BUILD/CMakeCache.txt" 2>/dev/null \
  || echo "warning: $BUILD is not a Release build; timings will not be representative"

if [ -z "$WORK" ]; then
  WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-large.XXXXXX")" || die "mktemp failed"
  [ "$KEEP" -eq 1 ] || RM_WORK=1
else
  mkdir -p "$WORK" || die "cannot create $WORK"
fi
BIG="$WORK/BIG.ply" OUT="$WORK/OUT.ply" REPORT="$WORK/R.json"
TIMEV="$WORK/time.txt" TTY="$WORK/progress.log"

[ -n "${EPOCHREALTIME:-}" ] || die "needs bash 5 (EPOCHREALTIME)"
now() { echo "$EPOCHREALTIME"; }
sub() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a - b }'; }
mb() { awk -v b="$1" 'BEGIN { printf "%.1f MB", b / 1e6 }'; }

MEM_TOTAL_KB="$(awk '/^MemTotal:/ { print $2 }' /proc/meminfo)"
MEM_AVAIL_KB="$(awk '/^MemAvailable:/ { print $2 }' /proc/meminfo)"
MACHINE="machine: $(nproc) cores, $(awk -v k="$MEM_TOTAL_KB" 'BEGIN { printf "%.1f GB", k / 1048576 }') RAM"
MACHINE+=" ($(awk -v k="$MEM_AVAIL_KB" 'BEGIN { printf "%.1f GB", k / 1048576 }') available), swap $(awk '/^SwapTotal:/ { print $2 }' /proc/meminfo) kB;"
MACHINE+=" load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "$MACHINE"
echo "work directory: $WORK"

# 1. The input.
echo
SHAPE="icosphere level $SUBDIV"
GEN_ARGS=(--subdiv "$SUBDIV")
if [ -n "$FREQ" ]; then
  SHAPE="geodesic sphere of frequency $FREQ"
  GEN_ARGS=(--frequency "$FREQ")
fi
echo "== generating BIG.ply ($SHAPE) =="
T0="$(now)"
"$GEN" "$BIG" "${GEN_ARGS[@]}" || die "generator failed"
GEN_S="$(sub "$(now)" "$T0")"
BIG_BYTES="$(stat -c %s "$BIG")"

# 2. The run, on a pseudo-terminal, time-stamping each status update.
CMD=("$SODT" smooth "$BIG" "$OUT" --iterations "$ITER" --report "$REPORT")
HAVE_TIME=0
[ -x /usr/bin/time ] && /usr/bin/time -v true >/dev/null 2>&1 && HAVE_TIME=1
[ "$HAVE_TIME" -eq 1 ] && CMD=(/usr/bin/time -v -o "$TIMEV" "${CMD[@]}")
HWM_FILE="$WORK/vmhwm.txt"
if [ "$HAVE_TIME" -eq 0 ]; then
  # No GNU time: the command writes its PID and execs sodt; a poller keeps the
  # last VmHWM (the kernel's peak RSS) it read from /proc while sodt runs.
  echo "(GNU time is not installed: peak RSS is polled from /proc/PID/status every 0.2 s)"
  PID_FILE="$WORK/sodt.pid"
  rm -f "$PID_FILE" "$HWM_FILE"
  CMD=(bash -c 'echo $$ >"$0"; exec "$@"' "$PID_FILE" "${CMD[@]}")
  (
    for _ in $(seq 600); do [ -s "$PID_FILE" ] && break; sleep 0.05; done
    pid="$(cat "$PID_FILE" 2>/dev/null)"
    [ -n "$pid" ] || exit 0
    while [ -r "/proc/$pid/status" ]; do
      v="$(awk '/^VmHWM:/ { print $2 }' "/proc/$pid/status" 2>/dev/null)"
      [ -n "$v" ] && echo "$v" >"$HWM_FILE"
      sleep 0.2
    done
  ) &
  POLLER=$!
fi
# Other programs on the CPU, if asked: busy loops, stopped at the end.
for _ in $(seq "$BUSY"); do
  ( while :; do :; done ) &
  BUSY_PIDS+=($!)
done
[ "$BUSY" -gt 0 ] && echo "($BUSY busy loops running beside the smoother)"
echo
echo "== ${CMD[*]} =="
: >"$TTY"
T0="$(now)"
T0US=${EPOCHREALTIME/./}
# stamp DELIM: reads the run's terminal output in pieces separated by DELIM
# ('\r' on the pseudo-terminal: the status line is redrawn as "\rTEXT" and
# the terminal turns '\n' into '\r\n'), prints every non-blank piece as
# "+SECONDS piece" and appends "MICROSECONDS piece" to TTY. A piece is stamped
# with the arrival of the DELIM before it, i.e. when its text started (a read
# returns only at the DELIM after it, which for "loading ..." comes when the
# loading is over). Builtins only, so the stamps lag by well under a millisecond.
stamp() {
  local delim="$1" piece t tprev=0
  while IFS= read -r -d "$delim" piece || [ -n "$piece" ]; do
    t=$tprev
    tprev=$((${EPOCHREALTIME/./} - T0US))
    piece="${piece//$'\n'/}"
    piece="${piece%"${piece##*[![:space:]]}"}"
    [ -n "$piece" ] || continue
    printf '+%d.%02d %s\n' $((t / 1000000)) $((t % 1000000 / 10000)) "$piece"
    printf '%d %s\n' "$t" "$piece" >>"$TTY"
  done
}
if command -v script >/dev/null; then
  printf -v QCMD '%q ' "${CMD[@]}"
  script -q -e -c "$QCMD" /dev/null </dev/null | stamp $'\r'
  RC=${PIPESTATUS[0]}
else
  echo "(script is not installed: no terminal, so no progress bar)"
  "${CMD[@]}" 2>&1 | stamp $'\n'
  RC=${PIPESTATUS[0]}
fi
WALL_S="$(sub "$(now)" "$T0")"
[ "${#BUSY_PIDS[@]}" -gt 0 ] && kill "${BUSY_PIDS[@]}" 2>/dev/null
BUSY_PIDS=()
[ "$RC" -eq 0 ] || die "sodt smooth exited with status $RC$( [ "$RC" -eq 137 ] && echo ' (killed: out of memory?)')"
[ -s "$OUT" ] && [ -s "$REPORT" ] || die "no output or report written"

# 3. Figures.
# phase_start TEXT: time stamp of the first update containing TEXT.
phase_start() { grep -F -- "$1" "$TTY" | head -n 1 | awk '{ printf "%.6f", $1 / 1e6 }'; }
t_load="$(phase_start "loading $(basename "$BIG")")"
t_meas="$(phase_start "measuring input")"
t_sweep="$(phase_start "S-ODT sweep")"
t_after="$(phase_start "measuring output")"
t_write="$(phase_start "writing $(basename "$OUT")")"
t_end="$(phase_start "sodt smooth: ")"
span() { if [ -n "$1" ] && [ -n "$2" ]; then sub "$2" "$1"; else echo "n/a"; fi; }
json() { sed -nE "s/^ *\"$1\": *([^,]*),?\$/\\1/p" "$REPORT" | head -n 1; }

if [ "$HAVE_TIME" -eq 1 ]; then
  PEAK_KB="$(sed -nE 's/^\s*Maximum resident set size \(kbytes\): ([0-9]+)/\1/p' "$TIMEV")"
  MAJFLT="$(sed -nE 's/^\s*Major \(requiring I\/O\) page faults: ([0-9]+)/\1/p' "$TIMEV")"
  USER_S="$(sed -nE 's/^\s*User time \(seconds\): ([0-9.]+)/\1/p' "$TIMEV")"
  SYS_S="$(sed -nE 's/^\s*System time \(seconds\): ([0-9.]+)/\1/p' "$TIMEV")"
  ELAPSED="$(sed -nE 's/^\s*Elapsed \(wall clock\) time.*: (.*)/\1/p' "$TIMEV")"
else
  wait "$POLLER" 2>/dev/null
  PEAK_KB="$(cat "$HWM_FILE" 2>/dev/null)" MAJFLT="n/a" USER_S="n/a" SYS_S="n/a" ELAPSED="n/a"
fi
OUT_BYTES="$(stat -c %s "$OUT")"
V="$(json vertices)" F="$(json faces)"

# result NAME VALUE: one line of the results, printed and kept for --results.
RESULT_ROWS=()
result() {
  printf '  %-22s %s\n' "$1" "$2"
  RESULT_ROWS+=("| $1 | $2 |")
}
echo
echo "== large input: results =="
result "input" "$V vertices, $F faces ($SHAPE, jittered, closed)"
[ "$BUSY" -gt 0 ] && result "busy loops" "$BUSY beside the run"
result "BIG.ply" "$(mb "$BIG_BYTES") ($BIG_BYTES bytes, binary PLY), generated in ${GEN_S} s"
result "OUT.ply" "$(mb "$OUT_BYTES") ($OUT_BYTES bytes)"
result "load" "$(span "$t_load" "$t_meas") s"
result "measure input + copy" "$(span "$t_meas" "$t_sweep") s"
result "smooth ($ITER sweeps)" "$(span "$t_sweep" "$t_after") s (CLI's own figure: $(json seconds) s)"
result "measure output" "$(span "$t_after" "$t_write") s (angles, Hausdorff, inverted faces)"
result "write OUT + report" "$(span "$t_write" "$t_end") s"
result "total" "$WALL_S s wall (GNU time: $ELAPSED, user $USER_S s, sys $SYS_S s)"
result "min angle" "$(json min_angle_before) -> $(json min_angle_after) deg"
result "Hausdorff (rel.)" "$(json hausdorff_rel); inverted faces $(json inverted_faces)"
if [ -n "$PEAK_KB" ]; then
  PCT="$(awk -v p="$PEAK_KB" -v t="$MEM_TOTAL_KB" 'BEGIN { printf "%.1f", 100 * p / t }')"
  result "peak RSS" "$(awk -v k="$PEAK_KB" 'BEGIN { printf "%.2f GB", k / 1048576 }') ($PEAK_KB kB, $PCT% of RAM); major page faults $MAJFLT"
  result "bytes per face" "$(awk -v k="$PEAK_KB" -v f="$F" 'BEGIN { printf "%.0f", k * 1024 / f }') (peak RSS / faces)"
  if [ "$PEAK_KB" -lt "$MEM_AVAIL_KB" ] && { [ "$MAJFLT" = n/a ] || [ "$MAJFLT" -lt 1000 ]; }; then
    FIT="yes"
  else
    FIT="NO (peak RSS near or above the available memory, or heavy paging)"
  fi
  result "fits in memory" "$FIT (available before the run: $(awk -v k="$MEM_AVAIL_KB" 'BEGIN { printf "%.1f GB", k / 1048576 }'))"
else
  result "peak RSS" "n/a (install GNU time: apt-get install time)"
fi
result "progress updates seen" "$(grep -c 'S-ODT sweep' "$TTY") sweep updates on the terminal"
if [ -n "$RESULTS" ]; then
  CONFIG=(--subdiv "$SUBDIV")
  [ -n "$FREQ" ] && CONFIG=(--frequency "$FREQ")
  CONFIG+=(--iterations "$ITER" --busy "$BUSY")
  {
    echo "$MACHINE"
    echo
    echo "| phase or measure | value |"
    echo "|---|---|"
    printf '%s\n' "${RESULT_ROWS[@]}"
  } | "$HERE/update_results.py" --results "$RESULTS" --section "large_input.sh ${CONFIG[*]//--/}" \
    --command "bench/large_input.sh ${CONFIG[*]}" || die "could not update $RESULTS"
fi
