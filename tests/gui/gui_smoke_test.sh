#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# GUI smoke test: drives Debian's MeshLab 2020.09 GUI, with the freshly built
# libfilter_sodt.so in a private prefix, on a private Xvfb server.
#
# Usage: gui_smoke_test.sh --plugin SO --mesh PLY --sodt EXE [--meshlab-lib-dir DIR]
#   --plugin  the built libfilter_sodt.so ($<TARGET_FILE:filter_sodt>)
#   --mesh    a closed triangle mesh to open (meshes/blobs_mc.ply)
#   --sodt    the project's CLI, used to measure the exported mesh
#
# Scenario (every wait is bounded; the whole run takes about 10 s):
#   1. private prefix: copies of /usr/bin/meshlab and meshlabserver, symlinks to
#      libmeshlab-common and every system plugin except an installed
#      libfilter_sodt.so, plus the built plugin (MESHLAB-2020.09.md section 5);
#   2. Xvfb on a free display (-displayfd, else the first free one of :91..:99);
#      if no X server starts the test is skipped (exit 77, SKIP_RETURN_CODE);
#   3. `meshlab COPY_OF_MESH`; wait for the main window and the "All files
#      opened" log line;
#   4. open the filter by name with MeshLab's filter search (Ctrl+F, type
#      "S-ODT Smoothing", Down, Return: the search lists the actions of the
#      Filters menus; its first hit is the filter whose title matches best);
#   5. the parameter dialog must appear as a window titled exactly
#      "S-ODT Smoothing" (and not the classify filter's);
#   6. click its Apply button (bottom right of the dialog) and wait for the
#      log lines "S-ODT: min angle A -> B deg" and "Applied filter S-ODT
#      Smoothing"; screenshot (import -window root) -> gui-smoke.png;
#   7. File > Export Mesh As (Ctrl+Shift+E): type a path in the file dialog,
#      Return, accept "Choose Saving Options" with Return; wait for "Saved Mesh";
#   8. checks: MeshLab is still running (no crash) and loaded the plugins from
#      the private prefix; the exported file differs from the input; `sodt
#      stats --reference INPUT` on it gives the same vertex and face counts, a
#      closed mesh, no inverted face, and a smallest angle larger than the
#      input's and equal (to 0.01 deg) to B from the filter's log line.
# MeshLab 2020.09 prints its log window's lines as "LOG: <level> <text>" on
# stderr, which is how steps 3, 6 and 7 know what happened.
#
# Environment:
#   SODT_GUI_SCREENSHOT_DIR  copy the screenshots (gui-smoke.png, plus
#                            gui-search.png and, on failure, gui-failure.png) there
#   SODT_TEST_KEEP=1         keep the work directory
# Exit status: 0 pass, 1 fail, 2 usage, 77 skipped (no X server could be started,
# or Xvfb / xdotool is not installed).
set -u

FILTER="S-ODT Smoothing"
SCREEN_W=1920
SCREEN_H=1080

PLUGIN="" MESH="" SODT=""
MLLIB="/usr/lib/x86_64-linux-gnu/meshlab"
while [ $# -gt 0 ]; do
  case "$1" in
    --plugin) PLUGIN="$2"; shift 2 ;;
    --mesh) MESH="$2"; shift 2 ;;
    --sodt) SODT="$2"; shift 2 ;;
    --meshlab-lib-dir) MLLIB="$2"; shift 2 ;;
    *) echo "unknown argument '$1'" >&2; exit 2 ;;
  esac
done

START=$SECONDS
# shellcheck source=gui_common.sh
. "$(dirname "${BASH_SOURCE[0]}")/gui_common.sh"

# ---------------------------------------------------------------------------
# Preconditions
[ -f "$PLUGIN" ] || fail "built plugin not found at '$PLUGIN' (build the filter_sodt target first)"
[ -f "$MESH" ] || fail "test mesh not found at '$MESH'"
[ -x "$SODT" ] || fail "sodt CLI not found at '$SODT'"
[ -x /usr/bin/meshlab ] || fail "/usr/bin/meshlab is not installed (apt-get install meshlab)"
[ -x /usr/bin/meshlabserver ] || fail "/usr/bin/meshlabserver is not installed (apt-get install meshlab)"
[ -f "$MLLIB/libmeshlab-common.so" ] || fail "no libmeshlab-common.so in '$MLLIB'"
command -v Xvfb >/dev/null || skip "Xvfb is not installed (apt-get install xvfb)"
command -v xdotool >/dev/null || skip "xdotool is not installed (apt-get install xdotool)"
command -v import >/dev/null || echo "note: ImageMagick's import is not installed; no screenshots"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-gui-test.XXXXXX")" || fail "mktemp failed"

# ---------------------------------------------------------------------------
# 1. Private prefix (MESHLAB-2020.09.md section 5): a copied binary in P/bin
#    loads plugins from P/lib/x86_64-linux-gnu/meshlab/plugins only.
P="$WORK/prefix"
L="$P/lib/x86_64-linux-gnu/meshlab"
mkdir -p "$P/bin" "$L/plugins" "$WORK/home" "$WORK/runtime" || fail "cannot create the prefix"
chmod 700 "$WORK/runtime"
cp /usr/bin/meshlab /usr/bin/meshlabserver "$P/bin/" || fail "cannot copy the MeshLab binaries"
ln -s "$MLLIB/libmeshlab-common.so" "$L/"
for f in "$MLLIB"/plugins/*.so; do
  # An installed copy of this plugin would register the filter twice.
  [ "$(basename "$f")" = "libfilter_sodt.so" ] && continue
  ln -s "$f" "$L/plugins/"
done
ln -s "$(readlink -f "$PLUGIN")" "$L/plugins/libfilter_sodt.so"

INPUT="$WORK/$(basename "$MESH")"  # keeps the mesh name shown in the GUI
cp "$MESH" "$INPUT" || fail "cannot copy the test mesh"
OUT="$WORK/gui_out.ply"

# ---------------------------------------------------------------------------
# 2. Xvfb on a free display.
start_xvfb

# ---------------------------------------------------------------------------
# 3. MeshLab with the mesh; settings and runtime files stay in WORK.
ML_LOG="$WORK/meshlab.log"
HOME="$WORK/home" XDG_CONFIG_HOME="$WORK/home/.config" XDG_RUNTIME_DIR="$WORK/runtime" \
  "$P/bin/meshlab" "$INPUT" >"$ML_LOG" 2>&1 &
ML_PID=$!

MAIN="$(wait_window '^MeshLab [0-9.]+ - ' 30)"
[ -n "$MAIN" ] || { need_alive "before its main window appeared"; fail "no MeshLab main window within 30 s"; }
wait_log '^LOG: 0 All files opened' 30 || fail "the mesh was not opened within 30 s"
grep -qF "Current Plugins Dir is: $L/plugins" "$ML_LOG" || fail "plugins were not loaded from the private prefix"
log "MeshLab window $MAIN is up and the mesh is loaded"
xdo windowmove "$MAIN" 0 0
xdo windowsize "$MAIN" "$SCREEN_W" $((SCREEN_H - 30))
sleep 0.5

# ---------------------------------------------------------------------------
# 4.-5. Open the filter through the filter search (Ctrl+F). Up to 3 attempts:
#    a key press can be lost while the window is still settling.
by_filter_search() {
  xdo key --clearmodifiers ctrl+f
  sleep 0.5
  xdo type --delay 30 "$FILTER"
  sleep 0.7
  xdo key Down
  sleep 0.3
}
open_dialog "$MAIN" "$FILTER" by_filter_search gui-search.png

# ---------------------------------------------------------------------------
# 6. Apply. The dialog is a floating QDockWidget, taller than the screen (its
#    help text): put its bottom on the screen's bottom edge and the main window
#    to its right, then click Apply, the bottom-right button of its grid.
eval "$(xdo getwindowgeometry --shell "$DIALOG")"
if [ "$WIDTH" -lt $((SCREEN_W - 600)) ]; then
  xdo windowmove "$MAIN" "$WIDTH" 0
  xdo windowsize "$MAIN" $((SCREEN_W - WIDTH)) $((SCREEN_H - 30))
fi
click_apply "$DIALOG"
wait_log "^LOG: 0 Applied filter ${FILTER} in" 60 || fail "no 'Applied filter $FILTER' in the log within 60 s of clicking Apply"
LINE="$(grep -E '^LOG: 2 S-ODT: min angle ' "$ML_LOG" | tail -n 1)"
[ -n "$LINE" ] || fail "the filter's log line 'S-ODT: min angle ...' is missing"
echo "  $LINE"
# "LOG: 2 S-ODT: min angle 0.0278 -> 27.5588 deg, ..."
LOG_BEFORE="$(echo "$LINE" | sed -E 's/.*min angle ([0-9.eE+-]+) -> ([0-9.eE+-]+) deg.*/\1/')"
LOG_AFTER="$(echo "$LINE" | sed -E 's/.*min angle ([0-9.eE+-]+) -> ([0-9.eE+-]+) deg.*/\2/')"
log "filter applied in the GUI"
sleep 1  # let the view redraw the smoothed mesh
shot gui-smoke.png
need_alive "after applying the filter"

# ---------------------------------------------------------------------------
# 7. File > Export Mesh As (Ctrl+Shift+E) to OUT.
export_mesh "$MAIN" "$OUT"

# ---------------------------------------------------------------------------
# 8. The exported mesh is the filter's result.
check_exported "$INPUT" "$OUT" "$SODT" "$LOG_BEFORE" "$LOG_AFTER"
need_alive "at the end"
log "all checks passed"
[ -n "${SODT_GUI_SCREENSHOT_DIR:-}" ] && [ -f "$WORK/gui-smoke.png" ] \
  && echo "  screenshot: $SODT_GUI_SCREENSHOT_DIR/gui-smoke.png"
echo "PASS: '$FILTER' opened by name, applied and exported in the MeshLab GUI (min angle $MIN_IN -> $MIN_OUT deg) in $((SECONDS - START)) s"
exit 0
