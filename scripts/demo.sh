#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# One-shot set-up on Debian 12: installs the dependencies, builds MeshLab
# 2025.07 and PyMeshLab 2025.7 once per machine (scripts/build-meshlab-2025.sh),
# builds sodt, installs
#   - the `sodt` tool and the plugin for MeshLab 2020.09 (Debian's, as root),
#   - the plugin for the MeshLab 2025.07 GUI in the user's plugin folder,
#   - the plugin for PyMeshLab 2025.7 in that pymeshlab's plugin folder,
# then smooths the bundled sliver mesh with the CLI, with meshlabserver 2020.09
# and from Python through PyMeshLab, and prints the quality reports.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SODT_BUILD_DIR:-$ROOT/build}"
OUT="${SODT_DEMO_OUT:-$ROOT/out}"
SUDO=()
[ "$(id -u)" -eq 0 ] || SUDO=(sudo)

"${SUDO[@]}" "$ROOT/scripts/install-deps.sh"
"$ROOT/scripts/build-meshlab-2025.sh" all
ML2025="$("$ROOT/scripts/build-meshlab-2025.sh" --print-dir)"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DSODT_MESHLAB2025_DIR="$ML2025"
cmake --build "$BUILD" -j"$(nproc)"
"${SUDO[@]}" cmake --install "$BUILD"

# MeshLab 2025.07 loads extra plugins from the user's data folder (no root).
GUI_PLUGINS="${XDG_DATA_HOME:-$HOME/.local/share}/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07"
install -D -m 644 "$BUILD/meshlab-2025.07-gui/filter_sodt/libfilter_sodt.so" "$GUI_PLUGINS/libfilter_sodt.so"
# PyMeshLab loads every plugin of its lib/plugins folder on import.
PYMESHLAB="$ML2025/pymeshlab"
install -m 644 "$BUILD/meshlab-2025.07-pymeshlab/filter_sodt/libfilter_sodt.so" "$PYMESHLAB/pymeshlab/lib/plugins/"

mkdir -p "$OUT"
echo
echo "== sodt smooth meshes/blobs_mc.ply (20 sweeps, guard quality) =="
sodt smooth "$ROOT/meshes/blobs_mc.ply" "$OUT/blobs_mc_sodt.ply" --report "$OUT/blobs_mc_report.json"
echo "report: $OUT/blobs_mc_report.json"

echo
echo "== meshlabserver 2020.09 with filter_sodt/examples/sodt_smoothing.mlx =="
xvfb-run -a -s "-screen 0 1024x768x24" meshlabserver -i "$ROOT/meshes/blobs_mc.ply" \
  -o "$OUT/blobs_mc_meshlab.ply" -s "$ROOT/filter_sodt/examples/sodt_smoothing.mlx" 2>&1 |
  grep -E '^LOG: [0-9] S-ODT' | sed 's/^LOG: [0-9] //'
sodt stats "$OUT/blobs_mc_meshlab.ply" --reference "$ROOT/meshes/blobs_mc.ply" |
  grep -E '"(min_angle|max_angle|frac_below_30|hausdorff_rel|inverted_faces)"'

echo
echo "== PyMeshLab 2025.7: filter_sodt/examples/sodt_pymeshlab.py =="
PYTHONPATH="$PYMESHLAB" /usr/bin/python3 "$ROOT/filter_sodt/examples/sodt_pymeshlab.py" \
  "$ROOT/meshes/blobs_mc.ply" "$OUT/blobs_mc_pymeshlab.ply"

echo
echo "outputs in $OUT"
echo "MeshLab 2025.07 (with the plugin in $GUI_PLUGINS): $ML2025/gui/src/distrib/meshlab"
echo "PyMeshLab 2025.7 (with the plugin installed): PYTHONPATH=$PYMESHLAB /usr/bin/python3"
