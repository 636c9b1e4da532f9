#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs the freshly built libfilter_sodt.so in Debian's meshlabserver 2020.09 from
# a private prefix (never a copy installed in the system plugin folder).
#
# Usage: meshlabserver_test.sh MODE --plugin SO --script MLX --mesh PLY
#                              --checker EXE [--examples DIR] [--mesh-dir DIR]
#                              [--meshlab-lib-dir DIR]
#        meshlabserver_test.sh --list
# --list prints every MODE with the name of its ctest test (plugin.NAME):
# tests/plugin/CMakeLists.txt registers one test per line.
# --script/--mesh: the basic smoothing script and its test mesh; --examples:
# the folder of the other example scripts (sodt_feature.mlx, sodt_denoise.mlx,
# sodt_flips.mlx, sodt_classify.mlx); --mesh-dir: the folder of cube_jitter.ply
# and cube_noisy.ply.
# MODE:
#   listed          `meshlabserver -d` lists "S-ODT Smoothing" and "S-ODT:
#                   Classify Feature Vertices" exactly once each, both citing
#                   the paper, loaded from the private prefix.
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
#   classify        sodt_classify.mlx on cube_jitter.ply saved with -m vq vc:
#                   vertices unmoved, every quality a code in {0,1,2}, exactly
#                   the 8 cube corners have code 2, colours are the palette's.
#   classify-select the same with selectFeatures=true saved with -m vq vc vf:
#                   exactly the crease and corner vertices are selected.
#   feature         sodt_feature.mlx on cube_jitter.ply: the 8 corners are
#                   bit-identical, every vertex stays on the cube surface and
#                   every edge vertex on its edge, the smallest angle grows,
#                   and the class output is as in classify.
#   denoise         sodt_denoise.mlx on cube_noisy.ply: exit 0, class codes and
#                   colours written, RMS distance to the cube goes down.
#   bad-epsilon     sodt_feature.mlx and sodt_classify.mlx with epsilon=-1:
#                   each fails like bad-iterations, naming epsilon.
#   flips           sodt_flips.mlx (Basic, edge flips and keep best on) on the
#                   mesh: exit 0, the log reports flips and the returned sweep,
#                   and the checker's --flipped mode passes (same vertex and
#                   face counts, other faces, still closed and oriented, min
#                   angle improved).
#   bad-flips       sodt_flips.mlx with flipMaxDihedral=91, then with
#                   tolerance=-1: each fails like bad-iterations, naming the key;
#                   sodt_flips.mlx on a quad cube (polygonal faces) and on a
#                   tetrahedron with per-wedge texture coordinates fails the
#                   same way, since flips would break them.
#   threads         the shipped script with threads=1 and with threads=2 on the
#                   mesh: both exit 0, log the threads used, and write
#                   byte-identical meshes; threads=1025 fails like
#                   bad-iterations, naming threads.
# Set SODT_TEST_KEEP=1 to keep the work directory for inspection.
set -u

# Every mode and its test name: the one list of the cases.
CASES="listed          listed_in_filter_dump
smooth          smooths_bundled_mesh
selection       face_selection_limits_moves
bad-iterations  negative_iterations_fail_cleanly
classify        classify_writes_codes_and_colours
classify-select classify_selects_features
feature         feature_keeps_cube_corners_and_surface
denoise         denoise_runs_on_noisy_cube
bad-epsilon     negative_epsilon_fails_cleanly
flips           flips_change_connectivity_only
bad-flips       bad_flip_parameters_fail_cleanly
threads         threads_do_not_change_the_result"

FILTER="S-ODT Smoothing"
CLASSIFY_FILTER="S-ODT: Classify Feature Vertices"
MODE="${1:-}"
shift || true
if [ "$MODE" = --list ]; then
  echo "$CASES"
  exit 0
fi
PLUGIN="" SCRIPT="" MESH="" CHECKER="" EXAMPLES="" MESHDIR=""
MLLIB="/usr/lib/x86_64-linux-gnu/meshlab"
while [ $# -gt 0 ]; do
  case "$1" in
    --plugin) PLUGIN="$2"; shift 2 ;;
    --script) SCRIPT="$2"; shift 2 ;;
    --mesh) MESH="$2"; shift 2 ;;
    --checker) CHECKER="$2"; shift 2 ;;
    --examples) EXAMPLES="$2"; shift 2 ;;
    --mesh-dir) MESHDIR="$2"; shift 2 ;;
    --meshlab-lib-dir) MLLIB="$2"; shift 2 ;;
    *) echo "unknown argument '$1'" >&2; exit 2 ;;
  esac
done

fail() { echo "FAIL: $*"; exit 1; }
pass() { echo "PASS: $*"; exit 0; }

echo "$CASES" | awk '{print $1}' | grep -qxF -- "$MODE" || { echo "unknown mode '$MODE'" >&2; exit 2; }
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

# need_file PATH WHAT: fails the test when PATH is not a file.
need_file() { [ -f "$1" ] || fail "$2 not found at '$1'"; }
need_checker() { [ -n "$CHECKER" ] && [ -x "$CHECKER" ] || fail "mesh checker not found at '$CHECKER'"; }

# run_checker ARGS...: runs the mesh checker and fails the test unless it passes.
run_checker() {
  echo "+ $(basename "$CHECKER") $*"
  "$CHECKER" "$@"
  local crc=$?
  [ "$crc" -eq 0 ] || fail "mesh check $1 failed (status $crc)"
}

# set_param IN OUT NAME VALUE: copy of script IN with parameter NAME set to VALUE.
set_param() {
  sed -E "/name=\"$3\"/ s/value=\"[^\"]*\"/value=\"$4\"/" "$1" >"$2"
  grep -E "name=\"$3\"" "$2" | grep -q "value=\"$4\"" || fail "could not set $3=$4 in a copy of $(basename "$1")"
}

# expect_clean_failure WHAT OUT PATTERN: the last run failed without a crash,
# wrote no OUT, and logged PATTERN.
expect_clean_failure() {
  [ "$RC" -ne 0 ] || fail "meshlabserver accepted $1 (exit 0)"
  if [ "$RC" -eq 124 ]; then fail "meshlabserver timed out"; fi
  if [ "$RC" -gt 128 ] && [ "$RC" -lt 193 ]; then fail "meshlabserver died from signal $((RC - 128)) (exit $RC)"; fi
  [ ! -e "$2" ] || fail "an output mesh was written although the filter failed ($1)"
  grep -q "$3" "$LOG" || fail "the log does not name the bad parameter ($1; expected '$3')"
}

CUBE="$MESHDIR/cube_jitter.ply"
NOISY="$MESHDIR/cube_noisy.ply"

case "$MODE" in
  listed)
    run_server -d "$WORK/filters.txt"
    [ "$RC" -eq 0 ] || fail "meshlabserver -d exited with $RC"
    grep -qF "Current Plugins Dir is: $L/plugins" "$LOG" || fail "plugins were not loaded from the private prefix"
    [ -f "$WORK/filters.txt" ] || fail "no filter dump written"
    for f in "$FILTER" "$CLASSIFY_FILTER"; do
      n="$(grep -cE "^\\\\section f[0-9]+ $f *\$" "$WORK/filters.txt")"
      [ "$n" -eq 1 ] || fail "'$f' listed $n times in the filter dump (expected once)"
      grep -A3 -E "^\\\\section f[0-9]+ $f *\$" "$WORK/filters.txt" | grep -q "doi:10.1016/j.gmod.2012.10.007" \
        || fail "the description of '$f' does not cite the paper"
    done
    pass "'$FILTER' and '$CLASSIFY_FILTER' are listed once each by meshlabserver -d"
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

  classify|classify-select)
    need_checker
    need_file "$CUBE" "bundled cube mesh"
    CLS="$EXAMPLES/sodt_classify.mlx"
    need_file "$CLS" "example script sodt_classify.mlx"
    OUT="$WORK/out.ply"
    if [ "$MODE" = classify ]; then
      run_server -i "$CUBE" -o "$OUT" -m vq vc -s "$CLS"
    else
      set_param "$CLS" "$WORK/select.mlx" selectFeatures true
      run_server -i "$CUBE" -o "$OUT" -m vq vc vf -s "$WORK/select.mlx"
    fi
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC"
    [ -s "$OUT" ] || fail "no output mesh written"
    grep -q "LOG: 2 S-ODT classify: epsilon 2, eta 2: " "$LOG" || fail "the class counts were not logged"
    if [ "$MODE" = classify ]; then
      run_checker --classes "$CUBE" "$OUT" --codes 012 --corners 8 --cube-corners --unmoved
      pass "classified $(basename "$CUBE"): 8 corners, codes and colours saved with -m vq vc"
    else
      grep -q "LOG: 2 S-ODT classify: selected [1-9][0-9]* feature" "$LOG" || fail "the selection was not logged"
      run_checker --classes "$CUBE" "$OUT" --codes 012 --corners 8 --unmoved --selected-features
      pass "selectFeatures selected exactly the crease and corner vertices"
    fi
    ;;

  feature)
    need_checker
    need_file "$CUBE" "bundled cube mesh"
    FEAT="$EXAMPLES/sodt_feature.mlx"
    need_file "$FEAT" "example script sodt_feature.mlx"
    OUT="$WORK/out.ply"
    run_server -i "$CUBE" -o "$OUT" -m vq vc -s "$FEAT"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC"
    [ -s "$OUT" ] || fail "no output mesh written"
    grep -q "LOG: 2 S-ODT: algorithm feature," "$LOG" || fail "the log does not show algorithm feature"
    grep -q "LOG: 2 S-ODT: vertex classes: .*; written to vertex quality and colour" "$LOG" \
      || fail "the class counts were not logged"
    run_checker --cube-feature "$CUBE" "$OUT"
    run_checker --classes "$CUBE" "$OUT" --codes 012 --corners 8 --cube-corners
    pass "feature-preserving S-ODT kept the cube's corners and surface and improved its angles"
    ;;

  denoise)
    need_checker
    need_file "$NOISY" "bundled noisy cube mesh"
    DEN="$EXAMPLES/sodt_denoise.mlx"
    need_file "$DEN" "example script sodt_denoise.mlx"
    OUT="$WORK/out.ply"
    run_server -i "$NOISY" -o "$OUT" -m vq vc -s "$DEN"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC"
    [ -s "$OUT" ] || fail "no output mesh written"
    grep -q "LOG: 2 S-ODT: algorithm denoise," "$LOG" || fail "the log does not show algorithm denoise"
    ! grep -q "nearly noise-free" "$LOG" || fail "the noisy cube was taken for a clean mesh"
    run_checker --classes "$NOISY" "$OUT"
    run_checker --cube-denoise "$NOISY" "$OUT"
    # The same script on the clean (tangentially jittered) cube: a warning.
    run_server -i "$CUBE" -o "$WORK/clean_out.ply" -m vq vc -s "$DEN"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC on the clean cube"
    grep -q "S-ODT: the mesh looks nearly noise-free (noise estimated at 0.000 mean edges): denoise" "$LOG" \
      || fail "denoising the clean cube gave no warning"
    pass "denoising S-ODT ran on $(basename "$NOISY") and wrote class codes; it warns on a clean cube"
    ;;

  bad-epsilon)
    need_file "$CUBE" "bundled cube mesh"
    for name in sodt_feature sodt_classify; do
      need_file "$EXAMPLES/$name.mlx" "example script $name.mlx"
      set_param "$EXAMPLES/$name.mlx" "$WORK/bad_$name.mlx" epsilon -1
      OUT="$WORK/out_$name.ply"
      run_server -i "$CUBE" -o "$OUT" -m vq vc -s "$WORK/bad_$name.mlx"
      expect_clean_failure "epsilon=-1 in $name.mlx" "$OUT" "epsilon must be a positive number"
    done
    pass "epsilon=-1 is rejected by both filters without a crash and without output"
    ;;

  flips)
    need_checker
    need_file "$MESH" "bundled test mesh"
    FLIPS="$EXAMPLES/sodt_flips.mlx"
    need_file "$FLIPS" "example script sodt_flips.mlx"
    OUT="$WORK/out.ply"
    run_server -i "$MESH" -o "$OUT" -s "$FLIPS"
    [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC"
    [ -s "$OUT" ] || fail "no output mesh written"
    grep -q "LOG: 2 S-ODT: algorithm basic," "$LOG" || fail "the log does not show algorithm basic"
    grep -q "LOG: 2 S-ODT: edge flips: [1-9][0-9]* (max dihedral 20 deg); the connectivity changed: [1-9][0-9]* faces" "$LOG" \
      || fail "the log does not report a positive number of edge flips"
    grep -q "LOG: 2 S-ODT: returned the state after sweep [0-9]* of [0-9]* run (keep best yes)" "$LOG" \
      || fail "the log does not report the returned sweep with keep best"
    run_checker --flipped "$MESH" "$OUT"
    pass "edge flips changed the connectivity of $(basename "$MESH") and improved its angles"
    ;;

  bad-flips)
    need_file "$MESH" "bundled test mesh"
    need_file "$EXAMPLES/sodt_flips.mlx" "example script sodt_flips.mlx"
    for kv in flipMaxDihedral=91 tolerance=-1; do
      name="${kv%%=*}"
      set_param "$EXAMPLES/sodt_flips.mlx" "$WORK/bad_$name.mlx" "$name" "${kv#*=}"
      OUT="$WORK/out_$name.ply"
      run_server -i "$MESH" -o "$OUT" -s "$WORK/bad_$name.mlx"
      expect_clean_failure "$kv in sodt_flips.mlx" "$OUT" "$name must be in"
    done
    # Flips are refused where they would break per-face data MeshLab keeps.
    cat >"$WORK/quads.ply" <<'PLY'
ply
format ascii 1.0
element vertex 8
property float x
property float y
property float z
element face 6
property list uchar int vertex_indices
end_header
-1 -1 -1
1 -1 -1
1 1 -1
-1 1 -1
-1 -1 1
1 -1 1
1 1 1
-1 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 2 3 7 6
4 1 2 6 5
4 0 4 7 3
PLY
    cat >"$WORK/wedge_tex.ply" <<'PLY'
ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
property list uchar float texcoord
end_header
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1 6 0 0 0 1 1 0
3 0 1 3 6 0 0 1 0 0 1
3 1 2 3 6 1 0 0 1 0 0
3 2 0 3 6 0 1 0 0 0 0
PLY
    run_server -i "$WORK/quads.ply" -o "$WORK/out_quads.ply" -s "$EXAMPLES/sodt_flips.mlx"
    expect_clean_failure "flips on polygonal faces" "$WORK/out_quads.ply" "flips would break the polygonal faces"
    run_server -i "$WORK/wedge_tex.ply" -o "$WORK/out_wedge.ply" -s "$EXAMPLES/sodt_flips.mlx"
    expect_clean_failure "flips with wedge texture coordinates" "$WORK/out_wedge.ply" \
      "flips would scramble the per-wedge texture coordinates"
    pass "bad flip parameters, polygonal faces and wedge texture coordinates are rejected without a crash and without output"
    ;;

  threads)
    need_file "$MESH" "bundled test mesh"
    for n in 1 2; do
      set_param "$SCRIPT" "$WORK/threads_$n.mlx" threads "$n"
      run_server -i "$MESH" -o "$WORK/out_$n.ply" -s "$WORK/threads_$n.mlx"
      [ "$RC" -eq 0 ] || fail "meshlabserver exited with $RC (threads=$n)"
      [ -s "$WORK/out_$n.ply" ] || fail "no output mesh written (threads=$n)"
      suffix=""; [ "$n" -eq 1 ] || suffix="s"
      grep -q "LOG: 2 S-ODT: [0-9]* sweeps over [0-9]* active vertices with $n thread$suffix: " "$LOG" \
        || fail "the log does not report $n thread$suffix used"
    done
    cmp "$WORK/out_1.ply" "$WORK/out_2.ply" || fail "threads=1 and threads=2 wrote different meshes"
    set_param "$SCRIPT" "$WORK/threads_bad.mlx" threads 1025
    run_server -i "$MESH" -o "$WORK/out_bad.ply" -s "$WORK/threads_bad.mlx"
    expect_clean_failure "threads=1025" "$WORK/out_bad.ply" "threads must be in"
    pass "threads=1 and threads=2 wrote byte-identical meshes; threads=1025 is rejected without output"
    ;;

  *) fail "mode '$MODE' is in CASES but has no test here" ;;
esac
