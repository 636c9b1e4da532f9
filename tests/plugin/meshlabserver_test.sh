#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs the freshly built libfilter_sodt.so in Debian's meshlabserver 2020.09 from
# a private prefix (never a copy installed in the system plugin folder).
#
# Usage: meshlabserver_test.sh MODE --plugin SO --script MLX --mesh PLY
#                              --checker EXE [--meshlab-lib-dir DIR]
# MODE:
#   listed          `meshlabserver -d` lists "S-ODT Smoothing" exactly once,
#                   loaded from the private prefix.
#   smooth          the shipped script on the mesh: exit 0, output written, the
#                   filter's log line printed, and the checker passes (same
#                   vertices and faces, coordinates moved, min angle improved).
#   selection       the shipped script with selectedOnly=true on a copy of the
#                   mesh whose left half of the faces is selected (face flags
#                   only): the face selection is converted and no vertex
#                   outside it moves.
#   bad-iterations  the shipped script with iterations=-5: meshlabserver exits
#                   non-zero without a crash (no signal), writes no output, and
#                   the log names the bad parameter.
# Set SODT_TEST_KEEP=1 to keep the work directory for inspection.
set -u

FILTER="S-ODT Smoothing"
MODE="${1:-}"
shift || true
PLUGIN="" SCRIPT="" MESH="" CHECKER=""
MLLIB="/usr/lib/x86_64-linux-gnu/meshlab"
while [ $# -gt 0 ]; do
  case "$1" in
    --plugin) PLUGIN="$2"; shift 2 ;;
    --script) SCRIPT="$2"; shift 2 ;;
    --mesh) MESH="$2"; shift 2 ;;
    --checker) CHECKER="$2"; shift 2 ;;
    --meshlab-lib-dir) MLLIB="$2"; shift 2 ;;
    *) echo "unknown argument '$1'" >&2; exit 2 ;;
  esac
done

fail() { echo "FAIL: $*"; exit 1; }
pass() { echo "PASS: $*"; exit 0; }

case "$MODE" in listed|smooth|selection|bad-iterations) ;; *) echo "unknown mode '$MODE'" >&2; exit 2 ;; esac
[ -f "$PLUGIN" ] || fail "built plugin not found at '$PLUGIN' (build the filter_sodt target first)"
[ -f "$SCRIPT" ] || fail "example script not found at '$SCRIPT'"
command -v xvfb-run >/dev/null || fail "xvfb-run is not installed (apt-get install xvfb xauth)"
[ -x /usr/bin/meshlabserver ] || fail "/usr/bin/meshlabserver is not installed (apt-get install meshlab)"
[ -f "$MLLIB/libmeshlab-common.so" ] || fail "no libmeshlab-common.so in '$MLLIB'"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-plugin-test.XXXXXX")" || fail "mktemp failed"
cleanup() { if [ -n "${SODT_TEST_KEEP:-}" ]; then echo "work directory kept: $WORK"; else rm -rf "$WORK"; fi; }
trap cleanup EXIT

# Private prefix (MESHLAB-2020.09.md section 5): a copied binary in P/bin looks
# for plugins in P/lib/x86_64-linux-gnu/meshlab/plugins only.
P="$WORK/prefix"
L="$P/lib/x86_64-linux-gnu/meshlab"
mkdir -p "$P/bin" "$L/plugins" "$WORK/home" "$WORK/runtime" || fail "cannot create the prefix"
chmod 700 "$WORK/runtime"
cp /usr/bin/meshlabserver "$P/bin/" || fail "cannot copy meshlabserver"
ln -s "$MLLIB/libmeshlab-common.so" "$L/"
for f in "$MLLIB"/plugins/*.so; do
  # A previously installed copy of this plugin would register the filter twice.
  [ "$(basename "$f")" = "libfilter_sodt.so" ] && continue
  ln -s "$f" "$L/plugins/"
done
ln -s "$(readlink -f "$PLUGIN")" "$L/plugins/libfilter_sodt.so"

# Keep MeshLab's QSettings and runtime files out of the user's home.
export HOME="$WORK/home" XDG_CONFIG_HOME="$WORK/home/.config" XDG_RUNTIME_DIR="$WORK/runtime"

LOG="$WORK/meshlabserver.log"
run_server() {
  echo "+ meshlabserver $*"
  timeout 240 xvfb-run -a -s "-screen 0 1024x768x24" "$P/bin/meshlabserver" "$@" >"$LOG" 2>&1
  RC=$?
  # The progress text has no newlines; make the log readable.
  tr '\r' '\n' <"$LOG" | sed 's/S-ODT sweep [0-9]*\/[0-9]*//g'
  echo "meshlabserver exit status: $RC"
}

case "$MODE" in
  listed)
    run_server -d "$WORK/filters.txt"
    [ "$RC" -eq 0 ] || fail "meshlabserver -d exited with $RC"
    grep -qF "Current Plugins Dir is: $L/plugins" "$LOG" || fail "plugins were not loaded from the private prefix"
    [ -f "$WORK/filters.txt" ] || fail "no filter dump written"
    n="$(grep -cE "^\\\\section f[0-9]+ $FILTER *\$" "$WORK/filters.txt")"
    [ "$n" -eq 1 ] || fail "'$FILTER' listed $n times in the filter dump (expected once)"
    grep -A3 -E "^\\\\section f[0-9]+ $FILTER" "$WORK/filters.txt" | grep -q "doi:10.1016/j.gmod.2012.10.007" \
      || fail "the filter description does not cite the paper"
    pass "'$FILTER' is listed once by meshlabserver -d"
    ;;

  smooth)
    [ -n "$CHECKER" ] && [ -x "$CHECKER" ] || fail "mesh checker not found at '$CHECKER'"
    [ -f "$MESH" ] || fail "bundled test mesh '$MESH' is missing (it belongs in the repository's meshes/ folder)"
    OUT="$WORK/out.ply"
    run_server -i "$MESH" -o "$OUT" -s "$SCRIPT"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC"
    grep -qF "Current Plugins Dir is: $L/plugins" "$LOG" || fail "plugins were not loaded from the private prefix"
    [ -s "$OUT" ] || fail "no output mesh written"
    grep -q "LOG: 2 S-ODT: min angle" "$LOG" || fail "the filter's log line 'S-ODT: min angle ...' is missing"
    echo "+ $(basename "$CHECKER") $MESH $OUT"
    "$CHECKER" "$MESH" "$OUT"
    crc=$?
    [ "$crc" -eq 0 ] || fail "mesh check failed (status $crc)"
    pass "meshlabserver smoothed $(basename "$MESH") with '$FILTER'"
    ;;

  selection)
    [ -n "$CHECKER" ] && [ -x "$CHECKER" ] || fail "mesh checker not found at '$CHECKER'"
    [ -f "$MESH" ] || fail "bundled test mesh '$MESH' is missing (it belongs in the repository's meshes/ folder)"
    SEL="$WORK/selected.ply"
    "$CHECKER" --select-half "$MESH" "$SEL" || fail "could not write the face-selected copy"
    SELSCRIPT="$WORK/selected_only.mlx"
    sed -E '/name="selectedOnly"/ s/value="[^"]*"/value="true"/' "$SCRIPT" >"$SELSCRIPT"
    grep -E 'name="selectedOnly"' "$SELSCRIPT" | grep -q 'value="true"' || fail "could not set selectedOnly=true in a copy of the script"
    OUT="$WORK/out.ply"
    run_server -i "$SEL" -o "$OUT" -s "$SELSCRIPT"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC"
    [ -s "$OUT" ] || fail "no output mesh written"
    grep -q "LOG: 2 S-ODT: converted the face selection to" "$LOG" || fail "the face selection was not converted"
    echo "+ $(basename "$CHECKER") --selection $MESH $OUT"
    "$CHECKER" --selection "$MESH" "$OUT"
    crc=$?
    [ "$crc" -eq 0 ] || fail "selection check failed (status $crc)"
    pass "with a face selection only the vertices inside it moved"
    ;;

  bad-iterations)
    [ -f "$MESH" ] || fail "bundled test mesh '$MESH' is missing (it belongs in the repository's meshes/ folder)"
    BAD="$WORK/bad_iterations.mlx"
    sed -E '/name="iterations"/ s/value="[^"]*"/value="-5"/' "$SCRIPT" >"$BAD"
    grep -E 'name="iterations"' "$BAD" | grep -q 'value="-5"' || fail "could not set iterations=-5 in a copy of the script"
    OUT="$WORK/out.ply"
    run_server -i "$MESH" -o "$OUT" -s "$BAD"
    [ "$RC" -ne 0 ] || fail "meshlabserver accepted iterations=-5 (exit 0)"
    if [ "$RC" -eq 124 ]; then fail "meshlabserver timed out"; fi
    if [ "$RC" -gt 128 ] && [ "$RC" -lt 193 ]; then fail "meshlabserver died from signal $((RC - 128)) (exit $RC)"; fi
    [ ! -e "$OUT" ] || fail "an output mesh was written although the filter failed"
    grep -q "iterations must be in" "$LOG" || fail "the log does not name the bad parameter"
    pass "iterations=-5 is rejected with exit status $RC and no output"
    ;;
esac
