# SPDX-License-Identifier: GPL-3.0-or-later
# Helpers shared by the GUI smoke tests (sourced, not run): a private Xvfb
# server, bounded xdotool calls, screenshots, waiting for windows and log
# lines of a MeshLab process, and clean-up.
#
# The sourcing script sets SCREEN_W, SCREEN_H and START ($SECONDS at its
# start), then WORK (a fresh work directory) and ML_LOG (MeshLab's stderr)
# before it uses the helpers that need them; ML_PID and XVFB_PID are set
# here and by the caller.

WORK="" XVFB_PID="" ML_PID="" DISPLAY_NUM="" ML_LOG=""
SKIP=77
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

# shot NAME: screenshot of the whole screen into WORK (and SODT_GUI_SCREENSHOT_DIR).
shot() {
  [ -n "$DISPLAY_NUM" ] && command -v import >/dev/null || return 0
  timeout 10 import -display ":$DISPLAY_NUM" -window root "$WORK/$1" 2>/dev/null || return 0
  if [ -n "${SODT_GUI_SCREENSHOT_DIR:-}" ]; then
    mkdir -p "$SODT_GUI_SCREENSHOT_DIR" && cp "$WORK/$1" "$SODT_GUI_SCREENSHOT_DIR/"
  fi
}
fail() {
  echo "FAIL: $*"
  if [ -n "$WORK" ] && [ -n "$ML_LOG" ] && [ -f "$ML_LOG" ]; then
    shot gui-failure.png
    echo "--- last lines of the MeshLab log ---"
    tail -n 25 "$ML_LOG"
  fi
  exit 1
}
skip() { echo "SKIP: $*"; exit "$SKIP"; }

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
# start_xvfb: a private X server on a free display; exports DISPLAY.
start_xvfb() {
  start_xvfb_displayfd || start_xvfb_fixed \
    || skip "no X server could be started (Xvfb -displayfd and :91..:99 failed; see below)
$(tail -n 5 "$WORK/xvfb.log" 2>/dev/null)"
  export DISPLAY=":$DISPLAY_NUM"
  log "Xvfb is running on $DISPLAY (${SCREEN_W}x${SCREEN_H})"
}

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
    grep -qaE "$1" "$ML_LOG" && return 0
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
# open_dialog WINDOW TITLE HOW SHOT: focuses WINDOW, runs the shell function HOW
# (the keys that pick the filter; a screenshot SHOT of its first attempt is
# taken before Return), presses Return and waits for a window titled exactly
# TITLE. Up to 3 attempts: a key press can be lost while the window is still
# settling. Sets DIALOG to that window's id, or fails.
open_dialog() {
  local attempt
  DIALOG=""
  for attempt in 1 2 3; do
    focus "$1"
    "$3"
    [ "$attempt" -eq 1 ] && shot "$4"
    xdo key Return
    DIALOG="$(wait_window "^${2}\$" 8)"
    [ -n "$DIALOG" ] && break
    need_alive "after choosing the filter"
    xdo search --onlyvisible --name '^S-ODT: Classify' >/dev/null 2>&1 && fail "the classify filter's dialog opened instead"
    log "attempt $attempt: no '$2' dialog yet; retrying"
    xdo key Escape Escape Escape
    sleep 0.5
  done
  [ -n "$DIALOG" ] || fail "the '$2' parameter dialog did not appear ($3)"
  xdo search --onlyvisible --name '^S-ODT: Classify' >/dev/null 2>&1 && fail "the classify filter's dialog opened instead"
  log "the '$2' dialog (window $DIALOG) is open ($3)"
}

# click_apply DIALOG: the dialog is taller than the screen (its help text):
# put its bottom on the screen's bottom edge, then click Apply, the
# bottom-right button of its button grid.
click_apply() {
  local X Y WIDTH HEIGHT SCREEN WINDOW DY=0
  eval "$(xdo getwindowgeometry --shell "$1")"
  [ "$HEIGHT" -gt "$SCREEN_H" ] && DY=$((SCREEN_H - HEIGHT))
  xdo windowmove "$1" 0 "$DY"
  sleep 0.7
  eval "$(xdo getwindowgeometry --shell "$1")"
  xdo mousemove $((X + WIDTH * 3 / 4)) $((Y + HEIGHT - 23))
  sleep 0.2
  xdo click 1
}

# export_mesh WINDOW OUT: File > Export Mesh As (Ctrl+Shift+E) in the main
# window WINDOW: the file name OUT into the file dialog, Return, then Return
# in "Choose Saving Options"; waits for MeshLab's "Saved Mesh OUT" log line.
export_mesh() {
  local save mask
  focus "$1"
  xdo key --clearmodifiers ctrl+shift+e
  save="$(wait_window '^Save ".*" Layer$' 10)"
  [ -n "$save" ] || fail "the Export Mesh As file dialog did not appear"
  focus "$save"
  xdo key --clearmodifiers ctrl+a
  xdo type --delay 15 "$2"
  sleep 0.3
  xdo key Return
  mask="$(wait_window '^Choose Saving Options' 10)"
  [ -n "$mask" ] || fail "the 'Choose Saving Options' dialog did not appear after the file dialog"
  focus "$mask"
  xdo key Return
  wait_log "^LOG: 0 Saved Mesh ${2} in" 20 || fail "no 'Saved Mesh $2' in the log within 20 s"
  [ -s "$2" ] || fail "MeshLab reports saving '$2' but the file is missing or empty"
  log "mesh exported to $(basename "$2")"
  sleep 0.5
  need_alive "after exporting the mesh"
}

# json_val FILE KEY: the scalar value of "KEY": in the JSON FILE (one key per line).
json_val() { sed -nE "s/^ *\"$2\": *([^,]*),?\$/\\1/p" "$1" | head -n 1; }

# check_exported INPUT OUT SODT LOG_BEFORE LOG_AFTER: the exported mesh is the
# filter's result: other bytes than the input, same vertex and face counts, closed,
# no inverted face, a larger smallest angle equal (to 0.01 deg) to the log's.
check_exported() {
  local input="$1" out="$2" sodt="$3" before="$4" after="$5" a b k
  cmp -s "$input" "$out" && fail "the exported mesh is identical to the input"
  "$sodt" stats "$input" --json "$WORK/in.json" || fail "sodt stats failed on the input"
  "$sodt" stats "$out" --reference "$input" --json "$WORK/out.json" || fail "sodt stats failed on the exported mesh"
  for k in vertices faces; do
    a="$(json_val "$WORK/in.json" $k)" b="$(json_val "$WORK/out.json" $k)"
    [ -n "$a" ] && [ "$a" = "$b" ] || fail "$k changed: input $a, exported $b"
  done
  [ "$(json_val "$WORK/out.json" closed)" = true ] || fail "the exported mesh is not closed"
  [ "$(json_val "$WORK/out.json" inverted_faces)" = 0 ] ||
    fail "the exported mesh has inverted faces: $(json_val "$WORK/out.json" inverted_faces)"
  MIN_IN="$(json_val "$WORK/in.json" min_angle)"
  MIN_OUT="$(json_val "$WORK/out.json" min_angle)"
  echo "  sodt stats: min angle $MIN_IN (input) -> $MIN_OUT (exported); filter log: $before -> $after"
  awk -v a="$MIN_IN" -v b="$MIN_OUT" 'BEGIN { exit !(b > a) }' || fail "the smallest angle did not grow ($MIN_IN -> $MIN_OUT)"
  awk -v a="$MIN_OUT" -v b="$after" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d < 0.01) }' \
    || fail "the exported mesh's smallest angle $MIN_OUT differs from the filter's log ($after)"
  awk -v a="$MIN_IN" -v b="$before" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d < 0.01) }' \
    || fail "the input's smallest angle $MIN_IN differs from the filter's log ($before)"
}
