#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a subset of the defect zoo through Debian's meshlabserver 2020.09 with
# the freshly built libfilter_sodt.so, from a private prefix (as
# tests/plugin/meshlabserver_test.sh does; see MESHLAB-2020.09.md section 5).
#
# Usage: meshlabserver_zoo.sh MODE --plugin SO --script MLX --tool EXE
#                             [--meshlab-lib-dir DIR]
#        meshlabserver_zoo.sh --list
# --list prints every MODE, the name of its ctest test (robustness.plugin.NAME)
# and its labels besides "robustness": tests/robustness/CMakeLists.txt
# registers one test per line.
# --script: filter_sodt/examples/sodt_smoothing.mlx; --tool: sodt_zoo_tool.
# MODE:
#   zoo              every zoo mesh of the plugin subset (non-manifold edge,
#                    pinch, holes, zero-area faces, duplicate faces, flipped
#                    duplicate, inconsistent winding, many components,
#                    polygons, combination, point cloud, empty mesh, a single
#                    degenerate triangle, zero-area faces only). For each:
#                    meshlabserver never crashes or hangs (exit status not
#                    124/134/139/any signal), and either exits 0 with an
#                    output that is finite and keeps the fixed vertices' bits
#                    (sodt_zoo_tool check) and a log that counts the fixed
#                    vertices as the zoo expects, or exits non-zero, writes
#                    no output and logs why. Prints a table of what happened.
#   guard-none-overflow
#                    the flattened zoo sphere with guard "None (paper,
#                    literal)" diverges; regression test that the float
#                    CMeshO never gets +-inf/NaN coordinates. Asserts:
#                    exit 0 with a finite output.
# Set SODT_TEST_KEEP=1 to keep the work directory.
set -u

# Every mode, its test name and its labels (comma-separated): the one list of the cases.
CASES="zoo                  zoo_never_crashes_meshlabserver       plugin,meshlab
guard-none-overflow  regression_guard_none_float_overflow  regression"

MODE="${1:-}"
shift || true
if [ "$MODE" = --list ]; then
  echo "$CASES"
  exit 0
fi
PLUGIN="" SCRIPT="" TOOL=""
MLLIB="/usr/lib/x86_64-linux-gnu/meshlab"
while [ $# -gt 0 ]; do
  case "$1" in
    --plugin) PLUGIN="$2"; shift 2 ;;
    --script) SCRIPT="$2"; shift 2 ;;
    --tool) TOOL="$2"; shift 2 ;;
    --meshlab-lib-dir) MLLIB="$2"; shift 2 ;;
    *) echo "unknown argument '$1'" >&2; exit 2 ;;
  esac
done

fail() { echo "FAIL: $*"; exit 1; }

echo "$CASES" | awk '{print $1}' | grep -qxF -- "$MODE" || { echo "unknown mode '$MODE'" >&2; exit 2; }
[ -f "$PLUGIN" ] || fail "built plugin not found at '$PLUGIN' (build the filter_sodt target first)"
[ -f "$SCRIPT" ] || fail "example script not found at '$SCRIPT'"
[ -x "$TOOL" ] || fail "sodt_zoo_tool not found at '$TOOL'"
command -v Xvfb >/dev/null || fail "Xvfb is not installed (apt-get install xvfb)"
[ -x /usr/bin/meshlabserver ] || fail "/usr/bin/meshlabserver is not installed (apt-get install meshlab)"
[ -f "$MLLIB/libmeshlab-common.so" ] || fail "no libmeshlab-common.so in '$MLLIB'"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/sodt-zoo-plugin.XXXXXX")" || fail "mktemp failed"
XPID=""
cleanup() {
  if [ -n "$XPID" ]; then kill "$XPID" 2>/dev/null; wait "$XPID" 2>/dev/null; fi
  if [ -n "${SODT_TEST_KEEP:-}" ]; then echo "work directory kept: $WORK"; else rm -rf "$WORK"; fi
}
trap cleanup EXIT

# Private prefix: a copied binary in P/bin loads plugins from P/lib/.../plugins only.
P="$WORK/prefix"
L="$P/lib/x86_64-linux-gnu/meshlab"
mkdir -p "$P/bin" "$L/plugins" "$WORK/home" "$WORK/runtime" "$WORK/in" "$WORK/out" || fail "cannot create the prefix"
chmod 700 "$WORK/runtime"
cp /usr/bin/meshlabserver "$P/bin/" || fail "cannot copy meshlabserver"
ln -s "$MLLIB/libmeshlab-common.so" "$L/"
for f in "$MLLIB"/plugins/*.so; do
  [ "$(basename "$f")" = "libfilter_sodt.so" ] && continue
  ln -s "$f" "$L/plugins/"
done
ln -s "$(readlink -f "$PLUGIN")" "$L/plugins/libfilter_sodt.so"
export HOME="$WORK/home" XDG_CONFIG_HOME="$WORK/home/.config" XDG_RUNTIME_DIR="$WORK/runtime"

# One X server for all runs (starting one per run with xvfb-run costs seconds):
# -displayfd picks a free display number and reports it when ready.
exec 3>"$WORK/display"
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp >"$WORK/xvfb.log" 2>&1 &
XPID=$!
exec 3>&-
for _ in $(seq 100); do [ -s "$WORK/display" ] && break; sleep 0.1; done
[ -s "$WORK/display" ] || fail "Xvfb did not start: $(cat "$WORK/xvfb.log")"
export DISPLAY=":$(head -n1 "$WORK/display")"

# run_server NAME ARGS...: one meshlabserver run; sets RC and LOG.
run_server() {
  LOG="$WORK/$1.log"
  shift
  timeout -s KILL 120 "$P/bin/meshlabserver" "$@" >"$LOG" 2>&1
  RC=$?
}

# crash_reason: non-empty when the last run crashed or hung. (meshlabserver
# itself exits 255 when a filter of the script fails.)
crash_reason() {
  if [ "$RC" -eq 137 ]; then echo "timed out (killed after 120 s)"
  elif [ "$RC" -eq 124 ]; then echo "timed out"
  elif [ "$RC" -gt 128 ] && [ "$RC" -lt 193 ]; then echo "died from signal $((RC - 128)) (exit $RC)"
  fi
}

# why_failed: the log lines that explain a non-zero exit.
why_failed() {
  tr '\r' '\n' <"$LOG" | grep -E "LOG: 1|[Ee]rror|[Uu]nable|[Ff]ailed|[Cc]annot|Abort|ssert|not found" \
    | grep -v "S-ODT sweep" | head -n 2 | tr '\n' ' '
}

case "$MODE" in
  zoo)
    "$TOOL" write "$WORK/in" >"$WORK/cases.txt" || fail "sodt_zoo_tool could not write the zoo"
    FAILURES=0
    TABLE=""
    while read -r name file; do
      out="$WORK/out/$name.ply"
      start=$(date +%s.%N)
      run_server "$name" -i "$file" -o "$out" -s "$SCRIPT"
      secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
      crash="$(crash_reason)"
      if [ -n "$crash" ]; then
        verdict="FAIL: $crash"
        FAILURES=$((FAILURES + 1))
      elif [ "$RC" -eq 0 ]; then
        if [ ! -s "$out" ]; then
          verdict="FAIL: exit 0 but no output"
          FAILURES=$((FAILURES + 1))
        elif check="$("$TOOL" check "$name" "$out")"; then
          log="$(tr '\r' '\n' <"$LOG" | grep -o "fixed [0-9]* boundary and [0-9]* non-manifold vertices" | head -n1)"
          expect="$("$TOOL" expect "$name")"
          if [ "${check%MeshLab changed the vertex list*}" = "$check" ] && [ "$log" != "$expect" ]; then
            verdict="FAIL: the filter logged '${log:-nothing}', the zoo expects '$expect'"
            FAILURES=$((FAILURES + 1))
          else
            verdict="ok: exit 0, ${check#*: }; log: ${log:-no S-ODT log line}"
          fi
        else
          verdict="FAIL: exit 0 but the output is bad: ${check#*: }"
          FAILURES=$((FAILURES + 1))
        fi
      else
        reason="$(why_failed)"
        if [ -e "$out" ]; then
          verdict="FAIL: exit $RC but an output was written"
          FAILURES=$((FAILURES + 1))
        elif [ -z "$reason" ]; then
          verdict="FAIL: exit $RC without a log line saying why"
          FAILURES=$((FAILURES + 1))
        else
          verdict="clean failure: exit $RC, no output; log: $reason"
        fi
      fi
      TABLE="$TABLE$(printf '%-28s %5ss  %s' "$name" "$secs" "$verdict")"$'\n'
      if [ "${verdict#FAIL}" != "$verdict" ]; then
        echo "---- meshlabserver log of $name ----"
        tr '\r' '\n' <"$LOG" | grep -v "S-ODT sweep" | tail -n 30
      fi
    done <"$WORK/cases.txt"
    echo "meshlabserver $(basename "$SCRIPT") on the defect zoo (display $DISPLAY):"
    printf '%s' "$TABLE"
    [ "$FAILURES" -eq 0 ] || fail "$FAILURES zoo meshes crashed meshlabserver or gave a bad result"
    echo "PASS: meshlabserver never crashed; every run either succeeded with a finite output or failed cleanly"
    ;;

  guard-none-overflow)
    "$TOOL" write-one flattened "$WORK/in/flattened.ply" || fail "sodt_zoo_tool could not write the mesh"
    sed -E '/name="guard"/ s/value="[^"]*"/value="0"/' "$SCRIPT" >"$WORK/guard_none.mlx"
    grep -E 'name="guard"' "$WORK/guard_none.mlx" | grep -q 'value="0"' || fail "could not set guard=0"
    out="$WORK/out/flattened.ply"
    run_server flattened -i "$WORK/in/flattened.ply" -o "$out" -s "$WORK/guard_none.mlx"
    crash="$(crash_reason)"
    [ -z "$crash" ] || fail "meshlabserver $crash"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC: $(why_failed)"
    check="$("$TOOL" check flattened "$out")" || fail "guard None wrote a bad mesh: $check"
    echo "PASS: $check"
    ;;

  *) fail "mode '$MODE' is in CASES but has no test here" ;;
esac
