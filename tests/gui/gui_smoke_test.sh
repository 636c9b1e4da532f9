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
SKIP=77
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
WORK="" XVFB_PID="" ML_PID="" DISPLAY_NUM=""
log() { echo "[$((SECONDS - START))s] $*"; }
# Every xdotool call is bounded, in case the X server hangs.
xdo() { timeout 10 xdotool "$@"; }

# Kill a process we started: TERM, up to 3 s grace, then KILL.
stop_pid() {
  local pid="$1"
  [ -n "$pid" ] || return 0
  kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null
  for _ in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  kill -KILL "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
}
cleanup() {
  stop_pid "$ML_PID"
  stop_pid "$XVFB_PID"
  if [ -n "$WORK" ]; then
    if [ -n "${SODT_TEST_KEEP:-}" ]; then echo "work directory kept: $WORK"; else rm -rf "$WORK"; fi
  fi
}
trap cleanup EXIT
trap 'echo "interrupted"; exit 1' INT TERM HUP

# shot NAME: screenshot of the whole screen into WORK (and the screenshot dir).
shot() {
  [ -n "$DISPLAY_NUM" ] && command -v import >/dev/null || return 0
  timeout 10 import -display ":$DISPLAY_NUM" -window root "$WORK/$1" 2>/dev/null || return 0
  if [ -n "${SODT_GUI_SCREENSHOT_DIR:-}" ]; then
    mkdir -p "$SODT_GUI_SCREENSHOT_DIR" && cp "$WORK/$1" "$SODT_GUI_SCREENSHOT_DIR/"
  fi
}
fail() {
  echo "FAIL: $*"
  if [ -n "$WORK" ] && [ -f "$WORK/meshlab.log" ]; then
    shot gui-failure.png
    echo "--- last lines of the MeshLab log ---"
    tail -n 25 "$WORK/meshlab.log"
  fi
  exit 1
}
skip() { echo "SKIP: $*"; exit "$SKIP"; }

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
# x_alive: the server on DISPLAY_NUM answers.
x_alive() { DISPLAY=":$DISPLAY_NUM" timeout 5 xdotool getdisplaygeometry >/dev/null 2>&1; }

start_xvfb_displayfd() {
  : >"$WORK/display"
  Xvfb -displayfd 3 -screen 0 "${SCREEN_W}x${SCREEN_H}x24" -nolisten tcp -noreset \
    3>"$WORK/display" >"$WORK/xvfb.log" 2>&1 &
  XVFB_PID=$!
  for _ in $(seq 100); do  # up to 10 s
    if [ -s "$WORK/display" ]; then
      DISPLAY_NUM="$(tr -dc '0-9' <"$WORK/display")"
      [ -n "$DISPLAY_NUM" ] && x_alive && return 0
    fi
    kill -0 "$XVFB_PID" 2>/dev/null || break
    sleep 0.1
  done
  stop_pid "$XVFB_PID"; XVFB_PID="" DISPLAY_NUM=""
  return 1
}
start_xvfb_fixed() {
  local n
  for n in 91 92 93 94 95 96 97 98 99; do
    [ -e "/tmp/.X$n-lock" ] || [ -e "/tmp/.X11-unix/X$n" ] && continue
    Xvfb ":$n" -screen 0 "${SCREEN_W}x${SCREEN_H}x24" -nolisten tcp -noreset >"$WORK/xvfb.log" 2>&1 &
    XVFB_PID=$!
    DISPLAY_NUM=$n
    for _ in $(seq 50); do  # up to 5 s
      kill -0 "$XVFB_PID" 2>/dev/null || break
      x_alive && return 0
      sleep 0.1
    done
    stop_pid "$XVFB_PID"; XVFB_PID="" DISPLAY_NUM=""
  done
  return 1
}
start_xvfb_displayfd || start_xvfb_fixed \
  || skip "no X server could be started (Xvfb -displayfd and :91..:99 failed; see below)
$(tail -n 5 "$WORK/xvfb.log" 2>/dev/null)"
export DISPLAY=":$DISPLAY_NUM"
log "Xvfb is running on $DISPLAY (${SCREEN_W}x${SCREEN_H})"

# ---------------------------------------------------------------------------
# 3. MeshLab with the mesh; settings and runtime files stay in WORK.
ML_LOG="$WORK/meshlab.log"
HOME="$WORK/home" XDG_CONFIG_HOME="$WORK/home/.config" XDG_RUNTIME_DIR="$WORK/runtime" \
  "$P/bin/meshlab" "$INPUT" >"$ML_LOG" 2>&1 &
ML_PID=$!

alive() { kill -0 "$ML_PID" 2>/dev/null; }
need_alive() {
  alive && return 0
  wait "$ML_PID" 2>/dev/null
  local rc=$?
  ML_PID=""
  if [ "$rc" -gt 128 ]; then fail "MeshLab died from signal $((rc - 128)) $1"; fi
  fail "MeshLab exited with status $rc $1"
}
# wait_log PATTERN SECONDS: waits until the MeshLab log has a line matching
# the extended regex PATTERN; fails if MeshLab dies first.
wait_log() {
  local i
  for i in $(seq $(($2 * 10))); do
    grep -qE "$1" "$ML_LOG" && return 0
    need_alive "while waiting for the log line /$1/"
    sleep 0.1
  done
  return 1
}
# wait_window REGEX SECONDS: prints the id of the first visible window whose
# title matches REGEX, waiting up to SECONDS.
wait_window() {
  timeout "$2" xdotool search --sync --onlyvisible --name "$1" 2>/dev/null | head -n 1
}
# focus WID: pointer into the window and keyboard focus on it (there is no
# window manager, so nothing else gives a window the focus).
focus() {
  local X Y WIDTH HEIGHT SCREEN WINDOW
  eval "$(xdo getwindowgeometry --shell "$1")"
  xdo mousemove $((X + WIDTH / 2)) $((Y + 12 > 0 ? Y + 12 : 5))
  timeout 3 xdotool windowfocus --sync "$1" 2>/dev/null || xdo windowfocus "$1"
  sleep 0.3
}

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
DIALOG=""
for attempt in 1 2 3; do
  focus "$MAIN"
  xdo key --clearmodifiers ctrl+f
  sleep 0.5
  xdo type --delay 30 "$FILTER"
  sleep 0.7
  [ "$attempt" -eq 1 ] && shot gui-search.png
  xdo key Down
  sleep 0.3
  xdo key Return
  DIALOG="$(wait_window "^${FILTER}\$" 8)"
  [ -n "$DIALOG" ] && break
  need_alive "after selecting the filter"
  log "attempt $attempt: no '$FILTER' dialog yet; retrying"
  xdo key Escape
  sleep 0.5
done
[ -n "$DIALOG" ] || fail "the '$FILTER' parameter dialog did not appear (searched via Ctrl+F)"
xdo search --onlyvisible --name '^S-ODT: Classify' >/dev/null 2>&1 && fail "the classify filter's dialog opened instead"
log "the '$FILTER' dialog (window $DIALOG) is open"

# ---------------------------------------------------------------------------
# 6. Apply. The dialog is a floating QDockWidget, taller than the screen (its
#    help text): put its bottom on the screen's bottom edge and the main window
#    to its right, then click Apply, the bottom-right button of its grid.
eval "$(xdo getwindowgeometry --shell "$DIALOG")"
DW=$WIDTH DH=$HEIGHT
DY=0
[ "$DH" -gt "$SCREEN_H" ] && DY=$((SCREEN_H - DH))
xdo windowmove "$DIALOG" 0 "$DY"
if [ "$DW" -lt $((SCREEN_W - 600)) ]; then
  xdo windowmove "$MAIN" "$DW" 0
  xdo windowsize "$MAIN" $((SCREEN_W - DW)) $((SCREEN_H - 30))
fi
sleep 0.7
eval "$(xdo getwindowgeometry --shell "$DIALOG")"
xdo mousemove $((X + WIDTH * 3 / 4)) $((Y + HEIGHT - 23))
sleep 0.2
xdo click 1
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
focus "$MAIN"
xdo key --clearmodifiers ctrl+shift+e
SAVE="$(wait_window '^Save ".*" Layer$' 10)"
[ -n "$SAVE" ] || fail "the Export Mesh As file dialog did not appear"
focus "$SAVE"
xdo key --clearmodifiers ctrl+a
xdo type --delay 15 "$OUT"
sleep 0.3
xdo key Return
MASK="$(wait_window '^Choose Saving Options' 10)"
[ -n "$MASK" ] || fail "the 'Choose Saving Options' dialog did not appear after the file dialog"
focus "$MASK"
xdo key Return
wait_log "^LOG: 0 Saved Mesh ${OUT} in" 20 || fail "no 'Saved Mesh $OUT' in the log within 20 s"
[ -s "$OUT" ] || fail "MeshLab reports saving '$OUT' but the file is missing or empty"
log "mesh exported to $(basename "$OUT")"
sleep 0.5
need_alive "after exporting the mesh"

# ---------------------------------------------------------------------------
# 8. The exported mesh is the filter's result.
cmp -s "$MESH" "$OUT" && fail "the exported mesh is identical to the input"
"$SODT" stats "$INPUT" --json "$WORK/in.json" || fail "sodt stats failed on the input"
"$SODT" stats "$OUT" --reference "$INPUT" --json "$WORK/out.json" || fail "sodt stats failed on the exported mesh"
# json_val FILE KEY: the scalar value of "KEY": in the JSON FILE (one key per line).
json_val() { sed -nE "s/^ *\"$2\": *([^,]*),?\$/\\1/p" "$1" | head -n 1; }
for k in vertices faces; do
  a="$(json_val "$WORK/in.json" $k)" b="$(json_val "$WORK/out.json" $k)"
  [ -n "$a" ] && [ "$a" = "$b" ] || fail "$k changed: input $a, exported $b"
done
[ "$(json_val "$WORK/out.json" closed)" = true ] || fail "the exported mesh is not closed"
[ "$(json_val "$WORK/out.json" inverted_faces)" = 0 ] || fail "the exported mesh has inverted faces: $(json_val "$WORK/out.json" inverted_faces)"
MIN_IN="$(json_val "$WORK/in.json" min_angle)"
MIN_OUT="$(json_val "$WORK/out.json" min_angle)"
echo "  sodt stats: min angle $MIN_IN (input) -> $MIN_OUT (exported); filter log: $LOG_BEFORE -> $LOG_AFTER"
awk -v a="$MIN_IN" -v b="$MIN_OUT" 'BEGIN { exit !(b > a) }' || fail "the smallest angle did not grow ($MIN_IN -> $MIN_OUT)"
awk -v a="$MIN_OUT" -v b="$LOG_AFTER" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d < 0.01) }' \
  || fail "the exported mesh's smallest angle $MIN_OUT differs from the filter's log ($LOG_AFTER)"
awk -v a="$MIN_IN" -v b="$LOG_BEFORE" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d < 0.01) }' \
  || fail "the input's smallest angle $MIN_IN differs from the filter's log ($LOG_BEFORE)"
need_alive "at the end"
log "all checks passed"
[ -n "${SODT_GUI_SCREENSHOT_DIR:-}" ] && [ -f "$WORK/gui-smoke.png" ] \
  && echo "  screenshot: $SODT_GUI_SCREENSHOT_DIR/gui-smoke.png"
echo "PASS: '$FILTER' opened by name, applied and exported in the MeshLab GUI (min angle $MIN_IN -> $MIN_OUT deg) in $((SECONDS - START)) s"
exit 0
