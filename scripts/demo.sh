#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# One-shot set-up and demo on Debian 12, the first result first:
#   1. installs what the `sodt` command needs (scripts/install-deps.sh --core,
#      with sudo when not root);
#   2. builds the `sodt` command alone, smooths the bundled meshes/blobs_mc.ply
#      with it and prints its summary (steps 1 and 2: a few minutes from a
#      fresh clone on a fresh machine);
#   3. installs the other dependencies (MeshLab 2020.09, Qt, the test tools),
#      builds the plugin for MeshLab 2020.09, installs it and `sodt` (as root)
#      and smooths the same mesh in Debian's meshlabserver 2020.09;
#   4. builds MeshLab 2025.07 and PyMeshLab 2025.7 once per machine
#      (scripts/build-meshlab-2025.sh; the longest step, cached outside the checkout);
#   5. builds the plugin for both and installs it: for the MeshLab 2025.07 GUI in
#      the user's plugin folder, for PyMeshLab 2025.7 in its plugin folder;
#   6. smooths the same mesh from Python through PyMeshLab.
# Each step says what it does and about how long it takes before it starts.
# Neither the tests nor the benchmarks are built: scripts/run-tests.sh builds
# them in the same build folder.
#   SODT_BUILD_DIR  build folder (default build/)
#   SODT_DEMO_OUT   output folder (default out/)
#   SODT_JOBS       parallel build jobs (default: nproc)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SODT_BUILD_DIR:-$ROOT/build}"
OUT="${SODT_DEMO_OUT:-$ROOT/out}"
JOBS="${SODT_JOBS:-$(nproc)}"
MESH="$ROOT/meshes/blobs_mc.ply"
SODT="$BUILD/cli/sodt"
SUDO=()
[ "$(id -u)" -eq 0 ] || SUDO=(sudo)

# step TEXT: announces the next step; the previous one reports its time.
STEP=0
STEP_START=$SECONDS
finish_step() {
  [ "$STEP" -gt 0 ] || return 0
  local s=$((SECONDS - STEP_START))
  printf '(step %d took %dm%02ds)\n' "$STEP" $((s / 60)) $((s % 60))
}
step() {
  finish_step
  STEP=$((STEP + 1))
  STEP_START=$SECONDS
  printf '\n== %d. %s ==\n' "$STEP" "$*"
}

step "installing what the sodt command needs from Debian's archive (scripts/install-deps.sh --core; 1-2 min the first time, seconds after)"
"${SUDO[@]}" "$ROOT/scripts/install-deps.sh" --core

step "building the sodt command (about 3 min on 2 cores from a fresh clone), then smoothing meshes/blobs_mc.ply"
# The plugin (Qt is not installed yet), the tests, the benchmarks and the
# developer tools are left out here; step 3 switches the plugin on,
# scripts/run-tests.sh the rest.
cmake -S "$ROOT" -B "$BUILD" --log-level=WARNING -DCMAKE_BUILD_TYPE=Release -DSODT_BUILD_PLUGIN=OFF \
  -DSODT_BUILD_TESTS=OFF -DSODT_BUILD_BENCH=OFF -DSODT_BUILD_TOOLS=OFF
cmake --build "$BUILD" -j"$JOBS" --target sodt
mkdir -p "$OUT"
echo
echo "-- sodt smooth meshes/blobs_mc.ply (20 sweeps, guard quality) --"
"$SODT" smooth "$MESH" "$OUT/blobs_mc_sodt.ply" --report "$OUT/blobs_mc_report.json"
echo "output: $OUT/blobs_mc_sodt.ply, report: $OUT/blobs_mc_report.json"

step "installing the other dependencies (scripts/install-deps.sh: MeshLab 2020.09, Qt, the test tools; several minutes the first time), building the plugin for MeshLab 2020.09 (about 1-2 min), installing it and sodt (as root), smoothing the mesh in meshlabserver 2020.09"
"${SUDO[@]}" "$ROOT/scripts/install-deps.sh"
cmake -S "$ROOT" -B "$BUILD" --log-level=WARNING -DSODT_BUILD_PLUGIN=ON
cmake --build "$BUILD" -j"$JOBS" --target filter_sodt
"${SUDO[@]}" cmake --install "$BUILD"
echo
echo "-- meshlabserver 2020.09 with filter_sodt/examples/sodt_smoothing.mlx --"
xvfb-run -a -s "-screen 0 1024x768x24" meshlabserver -i "$MESH" \
  -o "$OUT/blobs_mc_meshlab.ply" -s "$ROOT/filter_sodt/examples/sodt_smoothing.mlx" 2>&1 |
  grep -E '^LOG: [0-9] S-ODT' | sed 's/^LOG: [0-9] //'
"$SODT" stats "$OUT/blobs_mc_meshlab.ply" --reference "$MESH" |
  grep -E '"(min_angle|max_angle|frac_below_30|hausdorff_rel|inverted_faces)"'

ML2025="$("$ROOT/scripts/build-meshlab-2025.sh" --print-dir)"
if [ -f "$ML2025/gui/.done" ] && [ -f "$ML2025/pymeshlab/.done" ]; then
  step "MeshLab 2025.07 and PyMeshLab 2025.7: already built in $ML2025"
else
  step "building MeshLab 2025.07 and PyMeshLab 2025.7 once per machine (10-30 min on 2 cores, longer when they are busy), cached in $ML2025"
fi
"$ROOT/scripts/build-meshlab-2025.sh" all

step "building the plugin for the MeshLab 2025.07 GUI and for PyMeshLab 2025.7 (about 3-5 min), installing both"
cmake -S "$ROOT" -B "$BUILD" --log-level=WARNING -DSODT_MESHLAB2025_DIR="$ML2025"
cmake --build "$BUILD" -j"$JOBS" --target filter_sodt_ml2025_gui filter_sodt_ml2025_pymeshlab
# MeshLab 2025.07 loads extra plugins from the user's data folder (no root).
GUI_PLUGINS="${XDG_DATA_HOME:-$HOME/.local/share}/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07"
install -D -m 644 "$BUILD/meshlab-2025.07-gui/filter_sodt/libfilter_sodt.so" "$GUI_PLUGINS/libfilter_sodt.so"
# PyMeshLab loads every plugin of its lib/plugins folder on import.
PYMESHLAB="$ML2025/pymeshlab"
install -m 644 "$BUILD/meshlab-2025.07-pymeshlab/filter_sodt/libfilter_sodt.so" "$PYMESHLAB/pymeshlab/lib/plugins/"
echo "installed: $GUI_PLUGINS/libfilter_sodt.so and $PYMESHLAB/pymeshlab/lib/plugins/libfilter_sodt.so"

step "smoothing the mesh from Python through PyMeshLab 2025.7 (filter_sodt/examples/sodt_pymeshlab.py; seconds)"
PYTHONPATH="$PYMESHLAB" /usr/bin/python3 "$ROOT/filter_sodt/examples/sodt_pymeshlab.py" \
  "$MESH" "$OUT/blobs_mc_pymeshlab.ply"
finish_step

echo
echo "outputs in $OUT"
echo "sodt: $(command -v sodt || echo "$SODT")"
echo "MeshLab 2025.07 (with the plugin in $GUI_PLUGINS): $ML2025/gui/src/distrib/meshlab"
echo "PyMeshLab 2025.7 (with the plugin installed): PYTHONPATH=$PYMESHLAB /usr/bin/python3"
