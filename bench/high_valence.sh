#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Time and peak memory of `sodt smooth` (20 default sweeps, the full report)
# on meshes with one very high-valence vertex, where a cost that grows with
# the square of a star's size shows at once:
#   - closed double fans: two apexes over a rim of N vertices (valence N,
#     2N needle faces), N = 10k, 20k, 40k, 100k;
#   - a planar 100000-gon in an OFF file, which the reader fan-triangulates
#     from its first vertex (99998 needles, every vertex on the boundary).
# The target is under 10 s and 1 GB for the 100k fan and the 100000-gon.
#
# Usage: bench/high_valence.sh [--build DIR] [--work DIR] [--keep]
#   --build DIR   build tree with cli/sodt (default: build/ next to this
#                 folder; built there first if missing)
#   --work DIR    where the meshes and outputs go (default: a new temporary
#                 directory, removed at the end unless --keep)
# Prints a Markdown table: mesh, vertices, faces, wall-clock seconds, the
# report's smoothing seconds, peak resident memory.
set -u

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="$HERE/../build"
WORK=""
KEEP=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) BUILD="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --keep) KEEP=1; shift ;;
    -h|--help) sed -n '3,19p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

die() { echo "error: $*" >&2; exit 1; }
SODT="$BUILD/cli/sodt"
if [ ! -x "$SODT" ]; then
  cmake --build "$BUILD" -j2 --target sodt >/dev/null \
    || die "build failed (configure first: cmake -S . -B build -DCMAKE_BUILD_TYPE=Release)"
fi
/usr/bin/time -v true >/dev/null 2>&1 || die "needs GNU time at /usr/bin/time (Debian: apt-get install time)"
if [ -z "$WORK" ]; then
  WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-valence.XXXXXX")" || die "mktemp failed"
  [ "$KEEP" -eq 1 ] || trap 'rm -rf "$WORK"' EXIT
else
  mkdir -p "$WORK" || die "cannot create $WORK"
fi

# make_mesh KIND N OUT: KIND fan (closed double fan, apexes at z = +-0.3 over
# a unit rim) or polygon (one N-gon). The rim is regular, with a small
# deterministic wobble (a fifth of the rim spacing) so that nothing is exactly
# symmetric.
make_mesh() {
  awk -v kind="$1" -v n="$2" 'BEGIN {
    pi = atan2(0, -1); h = 2 * pi / n
    if (kind == "fan") printf "OFF\n%d %d 0\n0 0 0.3\n0 0 -0.3\n", n + 2, 2 * n
    else printf "OFF\n%d 1 0\n", n
    for (k = 0; k < n; ++k) {
      a = k * h; r = 1 + 0.2 * h * sin(12.9898 * k); z = 0.2 * h * sin(78.233 * k)
      printf "%.17g %.17g %.17g\n", r * cos(a), r * sin(a), z
    }
    if (kind == "fan") {
      for (k = 0; k < n; ++k) printf "3 0 %d %d\n", 2 + k, 2 + (k + 1) % n
      for (k = 0; k < n; ++k) printf "3 1 %d %d\n", 2 + (k + 1) % n, 2 + k
    } else {
      printf "%d", n
      for (k = 0; k < n; ++k) printf " %d", k
      printf "\n"
    }
  }' >"$3"
}

echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| mesh | vertices | faces | wall s | smoothing s | peak MB |"
echo "|---|---:|---:|---:|---:|---:|"
for c in fan:10000 fan:20000 fan:40000 fan:100000 polygon:100000; do
  kind="${c%%:*}"
  n="${c##*:}"
  in="$WORK/${kind}_$n.off"
  make_mesh "$kind" "$n" "$in"
  /usr/bin/time -v -o "$WORK/time" "$SODT" smooth "$in" "$WORK/out.ply" >"$WORK/report" 2>&1 \
    || die "sodt smooth $in failed: $(tail -n 3 "$WORK/report")"
  wall="$(sed -nE 's/^\s*Elapsed \(wall clock\) time.*: (.*)/\1/p' "$WORK/time" |
    awk -F: '{ s = 0; for (i = 1; i <= NF; ++i) s = s * 60 + $i; printf "%.2f", s }')"
  peak="$(sed -nE 's/^\s*Maximum resident set size \(kbytes\): ([0-9]+)/\1/p' "$WORK/time")"
  mesh="$(sed -nE 's/^\s*mesh\s+([0-9]+) vertices, ([0-9]+) triangles.*/\1 \2/p' "$WORK/report")"
  smooth="$(sed -nE 's/^\s*smoothing\s+([0-9.]+) s.*/\1/p' "$WORK/report")"
  label="double fan, rim $n"
  [ "$kind" = polygon ] && label="$n-gon (OFF)"
  echo "| $label | ${mesh% *} | ${mesh#* } | $wall | $smooth | $(awk -v k="$peak" 'BEGIN { printf "%.0f", k / 1024 }') |"
done
