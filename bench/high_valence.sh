#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Time and peak memory of every command and algorithm on meshes with one
# very high-valence vertex, where a cost that grows with the square of a
# star's size shows at once, against a regular mesh with as many faces:
#   - a closed double fan: two apexes over a rim of N vertices (valence N,
#     2N needle faces), every rim vertex with a random 3-D wobble of up to a
#     sixth of the rim spacing;
#   - an N-gon in an OFF file, which the reader fan-triangulates from its
#     first vertex (N - 2 needles, every vertex on the border), wobbled alike;
#   - the yardstick: a regular closed torus of 100 x N/100 vertices, 2N faces.
# The meshes come from `sodt_make_meshes --valence`. Each command runs with
# its defaults (20 sweeps, the full report) on the machine's cores; the
# plugin runs inside PyMeshLab when a build has it. The target: every run on
# the fan and the N-gon under 30 s and 1 GB at N = 100000, and at most 3
# times the torus's time.
#
# Usage: bench/high_valence.sh [--build DIR] [--n N] [--work DIR] [--keep] [--out FILE]
#   --build DIR   build tree with cli/sodt and tools/sodt_make_meshes (default:
#                 build/ next to this folder; built there first if missing);
#                 its meshlab-2025.07-pymeshlab/ plugin runs the PyMeshLab row
#   --n N         rim size (default 100000)
#   --work DIR    where the meshes and outputs go (default: a new temporary
#                 directory, removed at the end unless --keep)
#   --out FILE    also write the table (Markdown) to FILE
# Prints a Markdown table: per command, wall-clock seconds and peak resident
# memory on each mesh, and the fan's and the N-gon's time over the torus's.
set -u

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="$HERE/../build"
WORK=""
KEEP=0
N=100000
OUT=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) BUILD="$2"; shift 2 ;;
    --n) N="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --keep) KEEP=1; shift ;;
    --out) OUT="$2"; shift 2 ;;
    -h|--help) sed -n '3,/^set -u/{/^#/s/^# \{0,1\}//p}' "$0"; exit 0 ;;
    *) echo "unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

die() { echo "error: $*" >&2; exit 1; }
SODT="$BUILD/cli/sodt"
MAKE="$BUILD/tools/sodt_make_meshes"
if [ ! -x "$SODT" ] || [ ! -x "$MAKE" ]; then
  cmake --build "$BUILD" -j2 --target sodt sodt_make_meshes >/dev/null \
    || die "build failed (configure first: cmake -S . -B build -DCMAKE_BUILD_TYPE=Release)"
fi
/usr/bin/time -v true >/dev/null 2>&1 || die "needs GNU time at /usr/bin/time (Debian: apt-get install time)"
if [ -z "$WORK" ]; then
  WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-valence.XXXXXX")" || die "mktemp failed"
  [ "$KEEP" -eq 1 ] || trap 'rm -rf "$WORK"' EXIT
else
  mkdir -p "$WORK" || die "cannot create $WORK"
fi
PLUGIN="$BUILD/meshlab-2025.07-pymeshlab/filter_sodt/libfilter_sodt.so"
PYML="$("$HERE/../scripts/build-meshlab-2025.sh" --print-dir 2>/dev/null)/pymeshlab"
PYTHON=/usr/bin/python3

# The rows: a label and the command's arguments after the input (OUT is the
# output file, absent for stats); "pymeshlab" runs the plugin instead.
ROWS=(
  "smooth (basic)|smooth OUT"
  "smooth --algorithm feature|smooth OUT --algorithm feature"
  "smooth --algorithm denoise|smooth OUT --algorithm denoise"
  "smooth --algorithm filtered|smooth OUT --algorithm filtered"
  "smooth --flips|smooth OUT --flips"
  "smooth --repair|smooth OUT --repair"
  "smooth --algorithm feature --flips --repair|smooth OUT --algorithm feature --flips --repair"
  "smooth --slide-boundary|smooth OUT --slide-boundary"
  "classify|classify OUT"
  "stats|stats"
  "PyMeshLab plugin (basic)|pymeshlab"
)

# run MESH ARGS: prints "wall peakMB" of one run, or "failed"/"skipped".
run() {
  local mesh="$1" cmd="$2" args
  if [ "$cmd" = pymeshlab ]; then
    [ -f "$PLUGIN" ] && [ -d "$PYML" ] || { echo "skipped"; return; }
    /usr/bin/time -v -o "$WORK/time" "$PYTHON" "$HERE/valence_pymeshlab.py" "$PYML" "$PLUGIN" "$mesh" \
      >"$WORK/log" 2>&1 || { echo "failed"; return; }
  else
    args="${cmd/OUT/$WORK/out.ply}"
    # shellcheck disable=SC2086
    set -- $args
    local sub="$1"
    shift
    /usr/bin/time -v -o "$WORK/time" "$SODT" "$sub" "$mesh" "$@" >"$WORK/log" 2>&1 || { echo "failed"; return; }
  fi
  local wall peak
  wall="$(sed -nE 's/^\s*Elapsed \(wall clock\) time.*: (.*)/\1/p' "$WORK/time" |
    awk -F: '{ s = 0; for (i = 1; i <= NF; ++i) s = s * 60 + $i; printf "%.2f", s }')"
  peak="$(sed -nE 's/^\s*Maximum resident set size \(kbytes\): ([0-9]+)/\1/p' "$WORK/time")"
  echo "$wall $(awk -v k="$peak" 'BEGIN { printf "%.0f", k / 1024 }')"
}

for kind in torus fan polygon; do
  "$MAKE" --valence "$kind" "$N" "$WORK/$kind.off" || die "sodt_make_meshes --valence $kind $N failed"
done

table() {
  echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); N = $N"
  echo
  echo "| command | torus s | torus MB | fan s | fan MB | fan / torus | $N-gon s | $N-gon MB | $N-gon / torus |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  local row label cmd t f p
  for row in "${ROWS[@]}"; do
    label="${row%%|*}"
    cmd="${row#*|}"
    t="$(run "$WORK/torus.off" "$cmd")"
    f="$(run "$WORK/fan.off" "$cmd")"
    p="$(run "$WORK/polygon.off" "$cmd")"
    ratio() { awk -v a="${1% *}" -v b="${2% *}" 'BEGIN { if (b + 0 > 0 && a ~ /^[0-9.]+$/) printf "%.1f", a / b; else printf "-" }'; }
    cell() { case "$1" in failed|skipped) echo "$1 | -" ;; *) echo "${1% *} | ${1#* }" ;; esac; }
    echo "| $label | $(cell "$t") | $(cell "$f") | $(ratio "$f" "$t") | $(cell "$p") | $(ratio "$p" "$t") |"
  done
}
if [ -n "$OUT" ]; then
  table | tee "$OUT"
else
  table
fi
