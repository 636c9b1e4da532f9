#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of bench/corpus/ without the network: meshtool's readers, its needle and
# cap counts (CGAL 5.5's definitions) and canon-stl; the command lines and
# loud failures of fetch.sh and run.py.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
C="$ROOT/bench/corpus"
PY=/usr/bin/python3
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
fails=0
check() { # check NAME EXPECTED ACTUAL
  if [ "$2" = "$3" ]; then echo "ok   $1"; else echo "FAIL $1: expected '$2', got '$3'"; fails=$((fails + 1)); fi
}
field() { "$PY" -c 'import json,sys; print(json.load(sys.stdin)[sys.argv[1]])' "$1"; }

# A tetrahedron as OFF, OBJ (quads fan-triangulated: a square pyramid) and ASCII PLY.
cat > "$T/tet.off" <<'EOF'
OFF
# comment
4 4 0
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
EOF
s="$("$PY" "$C/meshtool.py" stats "$T/tet.off" --json)"
check "off faces" 4 "$(field faces <<<"$s")"
check "off closed" True "$(field closed <<<"$s")"
check "off needles" 0 "$(field needles <<<"$s")"
cat > "$T/pyr.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 0.5 1
f 4/1/1 3/1/1 2/1/1 1/1/1
f 1 2 5
f 2 3 5
f 3 4 5
f -2 -5 -1
EOF
s="$("$PY" "$C/meshtool.py" stats "$T/pyr.obj" --json)"
check "obj faces (quad split)" 6 "$(field faces <<<"$s")"
check "obj closed" True "$(field closed <<<"$s")"
cat > "$T/tet.ply" <<'EOF'
ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property uchar red
element face 4
property list uchar int vertex_indices
end_header
0 0 0 1
1 0 0 1
0 1 0 1
0 0 1 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
EOF
check "ply faces" 4 "$(field faces <<<"$("$PY" "$C/meshtool.py" stats "$T/tet.ply" --json)")"

# Needles and caps around the thresholds: edges 1 and 4.1 (a needle), 1.2 and 3.9 (not); an angle of 170 degrees (a cap), of 150 (not); a zero-length
# edge (a needle, not a cap).
"$PY" -B - "$C" <<'EOF'
import math, sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import meshtool
def tri(a, b, c):
    return np.array([a, b, c], float), np.array([[0, 1, 2]])
def apex(deg):  # isosceles, apex angle deg at vertex 2
    h = math.cos(math.radians(deg / 2)); w = math.sin(math.radians(deg / 2))
    return tri((-w, 0, 0), (w, 0, 0), (0, h, 0))
cases = [("ratio 4.1", tri((0, 0, 0), (4, 0, 0), (4, 1, 0)), (True, False)),
         ("ratio 3.9", tri((0, 0, 0), (3.7, 0, 0), (3.7, 1.2, 0)), (False, False)),
         ("apex 170", apex(170), (False, True)),
         ("apex 150", apex(150), (False, False)),
         ("zero edge", tri((0, 0, 0), (0, 0, 0), (1, 0, 0)), (True, False))]
bad = 0
for name, (V, F), want in cases:
    n, c = meshtool.needles_caps(V, F)
    got = (bool(n[0]), bool(c[0]))
    print(("ok  " if got == want else "FAIL") + " needle/cap %s: %s" % (name, got))
    bad += got != want
sys.exit(bad)
EOF
[ $? -eq 0 ] || fails=$((fails + 1))

# Binary STL: two triangles sharing an edge weld into 4 vertices.
"$PY" - "$T/two.stl" <<'EOF'
import struct, sys
tris = [((0, 0, 0), (1, 0, 0), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (0, 1, 0))]
with open(sys.argv[1], "wb") as f:
    f.write(b"\0" * 80 + struct.pack("<I", len(tris)))
    for t in tris:
        f.write(struct.pack("<3f", 0, 0, 1))
        for v in t:
            f.write(struct.pack("<3f", *v))
        f.write(b"\0\0")
EOF
s="$("$PY" "$C/meshtool.py" stats "$T/two.stl" --json)"
check "binary stl welded vertices" 4 "$(field vertices <<<"$s")"
check "binary stl border edges" 4 "$(field border_edges <<<"$s")"

# canon-stl: the same facets in another order and rotation give the same file.
cat > "$T/a.stl" <<'EOF'
solid a
  facet normal 0 0 1
    outer loop
      vertex 1 0 0
      vertex 0 1 0
      vertex 0 0 0
    endloop
  endfacet
  facet normal 0 0 1
    outer loop
      vertex 1 0 0
      vertex 1 1 0
      vertex 0 1 0
    endloop
  endfacet
endsolid a
EOF
cat > "$T/b.stl" <<'EOF'
solid b
facet normal 0 0 1
outer loop
vertex 0 1 0
vertex 1 0 0
vertex 1 1 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 1 0
endloop
endfacet
endsolid b
EOF
"$PY" "$C/meshtool.py" canon-stl "$T/a.stl" "$T/a2.stl" --name x >/dev/null
"$PY" "$C/meshtool.py" canon-stl "$T/b.stl" "$T/b2.stl" --name x >/dev/null
check "canon-stl order-independent" same "$(cmp -s "$T/a2.stl" "$T/b2.stl" && echo same || echo differ)"

# Unreadable input: exit 1 with a message.
printf 'solid x\nendsolid x\n' > "$T/empty.stl"
set +e
"$PY" "$C/meshtool.py" stats "$T/empty.stl" > /dev/null 2> "$T/err"; rc=$?
set -e
check "meshtool empty STL exit" 1 "$rc"

# fetch.sh and run.py: help, bad arguments, missing corpus.
set +e
"$C/fetch.sh" --help > /dev/null; check "fetch --help" 0 $?
"$C/fetch.sh" --bogus > /dev/null 2>&1; check "fetch unknown option" 2 $?
"$C/fetch.sh" --dir "$T/cache" --only no_such_mesh > /dev/null 2> "$T/err"; check "fetch --only unknown" 1 $?
grep -q "no_such_mesh" "$T/err"; check "fetch names the unknown mesh" 0 $?
"$C/run.py" --help > /dev/null; check "run --help" 0 $?
"$C/run.py" --dir "$T/nowhere" --sodt /bin/true > /dev/null 2> "$T/err"; check "run without corpus" 1 $?
grep -q "fetch.sh" "$T/err"; check "run says to fetch" 0 $?
"$C/run.py" --sodt "$T/nothing" > /dev/null 2>&1; check "run with a missing sodt" 1 $?
set -e

if [ "$fails" -ne 0 ]; then echo "$fails checks failed"; exit 1; fi
echo "all checks passed"
