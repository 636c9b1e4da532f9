#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# GUI smoke test of the plugin in the MeshLab 2025.07 GUI (built from the
# vendored sources by scripts/build-meshlab-2025.sh), installed as a user
# installs it: into ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07/
# of a private HOME, without root. Driven with xdotool on a private Xvfb server.
#
# Usage: gui2025_smoke_test.sh --meshlab BIN --plugin SO --mesh PLY --sodt EXE
#   --meshlab  the built meshlab binary (its folder holds libmeshlab-common.so and plugins/)
#   --plugin   libfilter_sodt.so built for MeshLab 2025.07 (float)
#   --mesh     a closed triangle mesh to open (meshes/blobs_mc.ply)
#   --sodt     the project's CLI, used to measure the exported mesh
#
# Scenario (every wait is bounded; a run takes about 15 s):
#   1. a private MeshLab: a copy of the binary next to a plugins/ folder that
#      holds only io_base (so the Smoothing menu lists only this plugin's
#      filters, in a known order); a private HOME whose MeshLab settings skip the
#      first-start statistics dialog, and the plugin in its per-user folder;
#   2. Xvfb on a free display; `meshlab COPY_OF_MESH`; wait for the main window
#      and the "All files opened" log line, and check that the plugin was
#      loaded from the per-user folder (no "has different ..." refusal);
#   3. Filters (Alt+L) > Smoothing, Fairing and Deformation (the 7th entry
#      after "Show current filter script") > its first entry, Return: the
#      parameter dialog must be the one titled exactly "S-ODT Smoothing";
#      screenshots of the open menu (gui2025-menu.png) and of the dialog
#      (gui2025-dialog.png);
#   4. click Apply; wait for "S-ODT: min angle A -> B deg" and "Applied
#      filter: S-ODT Smoothing"; screenshot (gui2025-applied.png);
#   5. File > Export Mesh As (Ctrl+Shift+E), file dialog, "Choose Saving
#      Options"; wait for the "Saved Mesh" log line;
#   6. checks: MeshLab still runs; the exported mesh has the input's vertex and
#      face counts, is closed, has no inverted face, and its smallest angle is
#      larger than the input's and equals B (to 0.01 deg).
# MeshLab 2025.07 prints its log window's lines as "LOG: <level> <text>" on
# stderr, which is how the steps know what happened.
#
# Environment: SODT_GUI_SCREENSHOT_DIR (copy the screenshots there),
# SODT_TEST_KEEP=1 (keep the work directory).
# Exit status: 0 pass, 1 fail (also when no X server can be started), 2 usage.
set -u

FILTER="S-ODT Smoothing"
SCREEN_W=1920
SCREEN_H=1080
# Entries of the Filters menu from the first enabled one ("Show current filter
# script") down to "Smoothing, Fairing and Deformation" (MeshLab 2025.07 lists
# every filter class, in a fixed order, whatever plugins are loaded).
SMOOTHING_MENU_DOWNS=7

MESHLAB="" PLUGIN="" MESH="" SODT=""
while [ $# -gt 0 ]; do
  case "$1" in
    --meshlab) MESHLAB="$2"; shift 2 ;;
    --plugin) PLUGIN="$2"; shift 2 ;;
    --mesh) MESH="$2"; shift 2 ;;
    --sodt) SODT="$2"; shift 2 ;;
    *) echo "unknown argument '$1'" >&2; exit 2 ;;
  esac
done

START=$SECONDS
# shellcheck source=gui_common.sh
. "$(dirname "${BASH_SOURCE[0]}")/gui_common.sh"
# Everything it needs is installed by the README's set-up: nothing is skipped.
skip() { fail "$@"; }

# ---------------------------------------------------------------------------
# Preconditions: Xvfb and xdotool are installed by scripts/install-deps.sh,
# so their absence is a failure here, not a skip.
[ -x "$MESHLAB" ] || fail "MeshLab 2025.07 binary not found at '$MESHLAB' (scripts/build-meshlab-2025.sh builds it)"
ML_DIR="$(dirname "$MESHLAB")"
[ -f "$ML_DIR/libmeshlab-common.so" ] || fail "no libmeshlab-common.so next to '$MESHLAB'"
[ -f "$ML_DIR/plugins/libio_base.so" ] || fail "no plugins/libio_base.so next to '$MESHLAB'"
[ -f "$PLUGIN" ] || fail "built plugin not found at '$PLUGIN'"
[ -f "$MESH" ] || fail "test mesh not found at '$MESH'"
[ -x "$SODT" ] || fail "sodt CLI not found at '$SODT'"
command -v Xvfb >/dev/null || fail "Xvfb is not installed (scripts/install-deps.sh)"
command -v xdotool >/dev/null || fail "xdotool is not installed (scripts/install-deps.sh)"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-gui2025-test.XXXXXX")" || fail "mktemp failed"

# ---------------------------------------------------------------------------
# 1. Private MeshLab and HOME. The binary finds libmeshlab-common.so through
#    its RUNPATH and loads plugins from the folder next to itself (resolved, so
#    it is copied, not linked), then from the per-user folder.
P="$WORK/meshlab"
mkdir -p "$P/plugins" "$WORK/home/.config/VCG" "$WORK/runtime" || fail "cannot create the private MeshLab"
chmod 700 "$WORK/runtime"
cp "$MESHLAB" "$P/meshlab" || fail "cannot copy the MeshLab binary"
ln -s "$ML_DIR/plugins/libio_base.so" "$P/plugins/"
printf '[General]\ninformativeShown=true\n' > "$WORK/home/.config/VCG/MeshLab_64bit_fp.conf"
USER_PLUGINS="$WORK/home/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07"
mkdir -p "$USER_PLUGINS"
cp "$PLUGIN" "$USER_PLUGINS/libfilter_sodt.so" || fail "cannot install the plugin into $USER_PLUGINS"

INPUT="$WORK/$(basename "$MESH")"  # keeps the mesh name shown in the GUI
cp "$MESH" "$INPUT" || fail "cannot copy the test mesh"
OUT="$WORK/gui_out.ply"

# ---------------------------------------------------------------------------
# 2. Xvfb and MeshLab with the mesh; settings and runtime files stay in WORK.
start_xvfb
ML_LOG="$WORK/meshlab.log"
HOME="$WORK/home" XDG_CONFIG_HOME="$WORK/home/.config" XDG_DATA_HOME="$WORK/home/.local/share" \
  XDG_RUNTIME_DIR="$WORK/runtime" "$P/meshlab" "$INPUT" >"$ML_LOG" 2>&1 &
ML_PID=$!

MAIN="$(wait_window '^MeshLab 2025\.07 - ' 30)"
[ -n "$MAIN" ] || { need_alive "before its main window appeared"; fail "no MeshLab 2025.07 main window within 30 s"; }
wait_log '^LOG: 0 All files opened' 30 || fail "the mesh was not opened within 30 s"
grep -qaiE 'libfilter_sodt.*(different|not a|does not)' "$ML_LOG" && fail "MeshLab refused the plugin: $(grep -aiE 'libfilter_sodt' "$ML_LOG" | head -n 1)"
log "MeshLab 2025.07 window $MAIN is up and the mesh is loaded"
xdo windowmove "$MAIN" 0 0
xdo windowsize "$MAIN" $((SCREEN_W - 700)) $((SCREEN_H - 30))
sleep 0.5

# ---------------------------------------------------------------------------
# 3. Filters > Smoothing, Fairing and Deformation > its first entry.
from_smoothing_menu() {
  xdo key --clearmodifiers alt+l
  sleep 0.5
  for _ in $(seq "$SMOOTHING_MENU_DOWNS"); do xdo key Down; sleep 0.1; done
  xdo key Right
  sleep 0.6
}
open_dialog "$MAIN" "$FILTER" from_smoothing_menu gui2025-menu.png
sleep 0.5
shot gui2025-dialog.png

# ---------------------------------------------------------------------------
# 4. Apply.
click_apply "$DIALOG"
wait_log "^LOG: 0 Applied filter: ${FILTER} in" 60 || fail "no 'Applied filter: $FILTER' in the log within 60 s of clicking Apply"
LINE="$(grep -aE '^LOG: 2 S-ODT: min angle ' "$ML_LOG" | tail -n 1)"
[ -n "$LINE" ] || fail "the filter's log line 'S-ODT: min angle ...' is missing"
echo "  $LINE"
LOG_BEFORE="$(echo "$LINE" | sed -E 's/.*min angle ([0-9.eE+-]+) -> ([0-9.eE+-]+) deg.*/\1/')"
LOG_AFTER="$(echo "$LINE" | sed -E 's/.*min angle ([0-9.eE+-]+) -> ([0-9.eE+-]+) deg.*/\2/')"
log "filter applied in the GUI"
# Close the dialog (its Close button, left of Apply) so that the mesh is in view.
eval "$(xdo getwindowgeometry --shell "$DIALOG")"
xdo mousemove $((X + WIDTH / 4)) $((Y + HEIGHT - 23))
xdo click 1
sleep 1.5  # let the view redraw the smoothed mesh in its class colours
shot gui2025-applied.png
need_alive "after applying the filter"

# ---------------------------------------------------------------------------
# 5. File > Export Mesh As (Ctrl+Shift+E) to OUT.
export_mesh "$MAIN" "$OUT"

# ---------------------------------------------------------------------------
# 6. The exported mesh is the filter's result.
check_exported "$INPUT" "$OUT" "$SODT" "$LOG_BEFORE" "$LOG_AFTER"
need_alive "at the end"
log "all checks passed"
echo "PASS: '$FILTER' chosen in Filters > Smoothing, Fairing and Deformation of MeshLab 2025.07, applied and exported (min angle $MIN_IN -> $MIN_OUT deg) in $((SECONDS - START)) s"
exit 0
