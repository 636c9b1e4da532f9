#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads triangle meshes (STL, OFF, OBJ, PLY) and measures what the corpus
benchmark reports about them: counts, borders, non-manifold edges, angles, and
needles and caps by the definitions of CGAL 5.5's
Polygon_mesh_processing::is_needle_triangle_face / is_cap_triangle_face.

STL corners with equal coordinates are welded into one vertex, as `sodt` does;
polygons are fan-triangulated. Only numpy (Debian's python3-numpy) is needed.

    meshtool.py stats MESH [--json]     one mesh's measures
    meshtool.py canon-stl IN OUT        ASCII STL with its facets in a canonical order

OpenSCAD 2021.01 writes the same triangles in a different order from one run to
the next; canon-stl sorts them (each facet starting at its smallest corner, the
coordinates' text kept as written), so that a render has one checksum.
"""
import argparse
import gzip
import json
import math
import struct
import sys

import numpy as np

# CGAL's remove_almost_degenerate_faces defaults: a needle's longest edge is at
# least 4 times its shortest (or an edge has length 0); a cap has an angle of at
# least 160 degrees (and no zero-length edge).
NEEDLE_RATIO = 4.0
CAP_ANGLE_DEG = 160.0


class MeshError(Exception):
    pass


def _open(path):
    if path.endswith(".gz"):
        return gzip.open(path, "rb")
    return open(path, "rb")


def _ext(path):
    p = path.lower()
    if p.endswith(".gz"):
        p = p[:-3]
    return p.rsplit(".", 1)[-1]


def _fan(polys):
    tris = []
    for poly in polys:
        for i in range(1, len(poly) - 1):
            tris.append((poly[0], poly[i], poly[i + 1]))
    return tris


def read_stl(data):
    if len(data) >= 84:
        (n,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=n, offset=84)
            corners = rec["v"].reshape(-1, 3).astype(np.float64)
            return _weld(corners)
    text = data.decode("latin-1")
    if not text.lstrip().lower().startswith("solid"):
        raise MeshError("neither binary STL (size does not match the triangle count) nor ASCII STL")
    vals = []
    for line in text.splitlines():
        t = line.split()
        if len(t) == 4 and t[0].lower() == "vertex":
            vals.append((float(t[1]), float(t[2]), float(t[3])))
    if not vals or len(vals) % 3:
        raise MeshError("ASCII STL with %d vertex lines (not a positive multiple of 3)" % len(vals))
    # ASCII coordinates are parsed as doubles; sodt welds equal coordinates too.
    return _weld(np.array(vals, dtype=np.float64))


def _weld(corners):
    uniq, inv = np.unique(corners, axis=0, return_inverse=True)
    return uniq, inv.reshape(-1, 3).astype(np.int64)


def read_off(data):
    tok = []
    for line in data.decode("latin-1").splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            tok.append(line.split())
    if not tok or not tok[0][0].endswith("OFF"):
        raise MeshError("no OFF header")
    head = tok[0][1:] if len(tok[0]) > 1 else None
    rows = tok[1:]
    if head is None:
        head, rows = rows[0], rows[1:]
    nv, nf = int(head[0]), int(head[1])
    if len(rows) < nv + nf:
        raise MeshError("OFF: %d vertices and %d faces announced, %d lines found" % (nv, nf, len(rows)))
    V = np.array([[float(x) for x in r[:3]] for r in rows[:nv]], dtype=np.float64)
    polys = []
    for r in rows[nv:nv + nf]:
        k = int(r[0])
        polys.append([int(x) for x in r[1:1 + k]])
    return V, np.array(_fan(polys), dtype=np.int64).reshape(-1, 3)


def read_obj(data):
    V, polys = [], []
    for line in data.decode("latin-1").splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            V.append((float(t[1]), float(t[2]), float(t[3])))
        elif t[0] == "f":
            idx = []
            for c in t[1:]:
                i = int(c.split("/")[0])
                idx.append(i - 1 if i > 0 else len(V) + i)
            polys.append(idx)
    return np.array(V, dtype=np.float64).reshape(-1, 3), np.array(_fan(polys), dtype=np.int64).reshape(-1, 3)


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply(data):
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise MeshError("no PLY header")
    nl = data.find(b"\n", end)
    header = data[:nl].decode("latin-1").splitlines()
    body = data[nl + 1:]
    fmt, elements = None, []
    for line in header:
        t = line.split()
        if not t:
            continue
        if t[0] == "format":
            fmt = t[1]
        elif t[0] == "element":
            elements.append((t[1], int(t[2]), []))
        elif t[0] == "property":
            if t[1] == "list":
                elements[-1][2].append((t[4], "list", _PLY_TYPES[t[2]], _PLY_TYPES[t[3]]))
            else:
                elements[-1][2].append((t[2], _PLY_TYPES[t[1]]))
    V, F = None, []
    if fmt == "ascii":
        toks = body.decode("latin-1").split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if len(p) == 4:
                        k = int(toks[pos]); pos += 1
                        row[p[0]] = [int(x) for x in toks[pos:pos + k]]; pos += k
                    else:
                        row[p[0]] = float(toks[pos]); pos += 1
                rows.append(row)
            if name == "vertex":
                V = np.array([[r["x"], r["y"], r["z"]] for r in rows], dtype=np.float64)
            elif name == "face":
                key = "vertex_indices" if props and "vertex_indices" in rows[0] else "vertex_index"
                F = [r[key] for r in rows]
    elif fmt in ("binary_little_endian", "binary_big_endian"):
        e = "<" if fmt == "binary_little_endian" else ">"
        pos = 0
        for name, count, props in elements:
            if all(len(p) == 2 for p in props):
                dt = np.dtype([(p[0], e + p[1]) for p in props])
                arr = np.frombuffer(body, dtype=dt, count=count, offset=pos)
                pos += dt.itemsize * count
                if name == "vertex":
                    V = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
                continue
            rows = []
            for _ in range(count):
                row = None
                for p in props:
                    if len(p) == 4:
                        ct, it = np.dtype(e + p[2]), np.dtype(e + p[3])
                        k = int(np.frombuffer(body, dtype=ct, count=1, offset=pos)[0]); pos += ct.itemsize
                        vals = np.frombuffer(body, dtype=it, count=k, offset=pos); pos += it.itemsize * k
                        if p[0] in ("vertex_indices", "vertex_index"):
                            row = [int(x) for x in vals]
                    else:
                        pos += np.dtype(p[1]).itemsize
                rows.append(row)
            if name == "face":
                F = rows
    else:
        raise MeshError("PLY format %r not supported" % fmt)
    if V is None:
        raise MeshError("PLY without a vertex element")
    return V, np.array(_fan(F), dtype=np.int64).reshape(-1, 3)


def read_mesh(path):
    """Returns (V, F): float64 coordinates and int64 triangles."""
    with _open(path) as f:
        data = f.read()
    ext = _ext(path)
    readers = {"stl": read_stl, "off": read_off, "obj": read_obj, "ply": read_ply}
    if ext not in readers:
        raise MeshError("unknown extension %r" % ext)
    try:
        V, F = readers[ext](data)
    except (ValueError, IndexError, KeyError, struct.error) as err:
        raise MeshError("%s: cannot parse: %s" % (path, err))
    if len(F) == 0:
        raise MeshError("%s: no triangles" % path)
    if F.min() < 0 or F.max() >= len(V):
        raise MeshError("%s: a face index is out of range" % path)
    return V, F


def needles_caps(V, F):
    """Per-face boolean arrays (needle, cap) by CGAL 5.5's definitions."""
    P = V[F]                                              # (m, 3 corners, 3)
    e = [P[:, 1] - P[:, 0], P[:, 2] - P[:, 1], P[:, 0] - P[:, 2]]
    sq = np.stack([np.einsum("ij,ij->i", x, x) for x in e], axis=1)
    mn, mx = sq.min(axis=1), sq.max(axis=1)
    needle = (mn == 0) | (mx >= NEEDLE_RATIO * NEEDLE_RATIO * mn)
    c = math.cos(math.radians(CAP_ANGLE_DEG))
    cap = np.zeros(len(F), dtype=bool)
    for k in range(3):
        # angle at corner k+1 (between edges e[k] reversed and e[k+1])
        a, b = -e[k], e[(k + 1) % 3]
        dot = np.einsum("ij,ij->i", a, b)
        sa, sb = sq[:, k], sq[:, (k + 1) % 3]
        cap |= (dot <= 0) & (dot * dot >= c * c * sa * sb)
    cap &= mn > 0
    return needle, cap


def angles_deg(V, F):
    P = V[F]
    out = np.empty((len(F), 3))
    for k in range(3):
        a = P[:, (k + 1) % 3] - P[:, k]
        b = P[:, (k + 2) % 3] - P[:, k]
        cr = np.linalg.norm(np.cross(a, b), axis=1)
        out[:, k] = np.degrees(np.arctan2(cr, np.einsum("ij,ij->i", a, b)))
    return out


def stats(V, F):
    used = np.unique(F)
    Vu = V[used]
    diag = float(np.linalg.norm(Vu.max(axis=0) - Vu.min(axis=0)))
    repeated = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    edges = edges[edges[:, 0] != edges[:, 1]]
    _, counts = np.unique(edges, axis=0, return_counts=True)
    # components: union-find over the faces' vertices
    parent = np.arange(len(V))

    def find(x):
        r = x
        while parent[r] != r:
            r = parent[r]
        while parent[x] != r:
            parent[x], x = r, parent[x]
        return r
    for a, b, c in F:
        ra, rb, rc = find(a), find(b), find(c)
        parent[rb] = ra
        parent[find(rc)] = ra
    comps = len({find(int(v)) for v in used})
    ang = angles_deg(V, F)
    needle, cap = needles_caps(V, F)
    return {
        "vertices": int(len(used)),
        "faces": int(len(F)),
        "border_edges": int((counts == 1).sum()),
        "nonmanifold_edges": int((counts > 2).sum()),
        "closed": bool((counts == 1).sum() == 0),
        "components": comps,
        "repeated_index_faces": int(repeated.sum()),
        # a face with a repeated vertex (after welding) counts as 0 and 180 degrees, as in sodt
        "min_angle": 0.0 if repeated.any() else float(ang.min()),
        "max_angle": 180.0 if repeated.any() else float(ang.max()),
        "needles": int(needle.sum()),
        "caps": int(cap.sum()),
        "bbox_diag": diag,
    }


def canon_stl(src, dst, name="canonical"):
    facets, normal, corners = [], None, []
    with open(src, "r", encoding="latin-1") as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "facet":
                if len(t) != 5 or t[1] != "normal":
                    raise MeshError("%s: bad facet line %r" % (src, line.strip()))
                normal, corners = t[2:5], []
            elif t[0] == "vertex":
                if len(t) != 4:
                    raise MeshError("%s: bad vertex line %r" % (src, line.strip()))
                corners.append(t[1:4])
            elif t[0] == "endfacet":
                if normal is None or len(corners) != 3:
                    raise MeshError("%s: a facet without a normal and 3 vertices" % src)
                key = [tuple(float(x) for x in c) + tuple(c) for c in corners]
                k = key.index(min(key))
                order = [k, (k + 1) % 3, (k + 2) % 3]
                facets.append((tuple(key[i] for i in order), normal, [corners[i] for i in order]))
                normal = None
    if not facets:
        raise MeshError("%s: no facets (not an ASCII STL?)" % src)
    facets.sort(key=lambda x: x[0])
    with open(dst, "w", encoding="latin-1") as out:
        out.write("solid %s\n" % name)
        for _, n, cs in facets:
            out.write("  facet normal %s %s %s\n    outer loop\n" % tuple(n))
            for c in cs:
                out.write("      vertex %s %s %s\n" % tuple(c))
            out.write("    endloop\n  endfacet\n")
        out.write("endsolid %s\n" % name)
    return len(facets)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("stats", help="print a mesh's measures")
    s.add_argument("mesh")
    s.add_argument("--json", action="store_true", help="print JSON")
    c = sub.add_parser("canon-stl", help="write an ASCII STL with its facets sorted")
    c.add_argument("src")
    c.add_argument("dst")
    c.add_argument("--name", default="canonical", help="the solid's name")
    args = ap.parse_args(argv)
    try:
        if args.cmd == "canon-stl":
            n = canon_stl(args.src, args.dst, args.name)
            print("%d facets" % n)
            return 0
        V, F = read_mesh(args.mesh)
    except (OSError, MeshError) as err:
        print("meshtool: %s" % err, file=sys.stderr)
        return 1
    st = stats(V, F)
    if args.json:
        print(json.dumps(st))
    else:
        for k, v in st.items():
            print("%-22s %s" % (k, v))
    return 0


if __name__ == "__main__":
    sys.exit(main())
