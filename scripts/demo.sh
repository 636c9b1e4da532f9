#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# One-shot set-up on Debian 12: installs the dependencies, builds, installs the
# MeshLab plugin and the `sodt` tool, then smooths the bundled sliver mesh with
# both (CLI and meshlabserver) and prints the quality report.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SODT_BUILD_DIR:-$ROOT/build}"
OUT="${SODT_DEMO_OUT:-$ROOT/out}"
SUDO=()
[ "$(id -u)" -eq 0 ] || SUDO=(sudo)

"${SUDO[@]}" "$ROOT/scripts/install-deps.sh"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD" -j"$(nproc)"
"${SUDO[@]}" cmake --install "$BUILD"

mkdir -p "$OUT"
echo
echo "== sodt smooth meshes/blobs_mc.ply (20 sweeps, guard quality) =="
sodt smooth "$ROOT/meshes/blobs_mc.ply" "$OUT/blobs_mc_sodt.ply" --report "$OUT/blobs_mc_report.json"
echo "report: $OUT/blobs_mc_report.json"

echo
echo "== meshlabserver with filter_sodt/examples/sodt_smoothing.mlx =="
xvfb-run -a -s "-screen 0 1024x768x24" meshlabserver -i "$ROOT/meshes/blobs_mc.ply" \
  -o "$OUT/blobs_mc_meshlab.ply" -s "$ROOT/filter_sodt/examples/sodt_smoothing.mlx" 2>&1 |
  grep -E '^LOG: [0-9] S-ODT' | sed 's/^LOG: [0-9] //'
sodt stats "$OUT/blobs_mc_meshlab.ply" --reference "$ROOT/meshes/blobs_mc.ply" |
  grep -E '"(min_angle|max_angle|frac_below_30|hausdorff_rel|inverted_faces)"'
echo "outputs in $OUT"
