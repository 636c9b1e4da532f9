#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Regenerates the seed corpus of fuzz_mesh in fuzz/corpus/ (committed, so
running the fuzzer does not need Python):

    python3 fuzz/make_corpus.py fuzz/corpus

Every seed is one configuration byte (see fuzz_mesh.cpp: bit 0 = OFF, bits 1-2
= algorithm, bit 3 = flips, bit 4 = fold guard, bit 5 = keepBest, bit 6 = float
mesh, bit 7 = selectedOnly) followed by a small PLY, OFF, OBJ or STL file.
"""
import math
import os
import struct
import sys

# --- configuration byte -----------------------------------------------------
OFF = 1
BASIC, FEATURE, DENOISE = 0 << 1, 1 << 1, 2 << 1
OBJ, STL = 3 << 1, 3 << 1 | 1  # basic, the bytes read as .obj or .stl
FLIPS, FOLD, KEEPBEST, FLOAT, SELECTED = 8, 16, 32, 64, 128

# --- meshes -----------------------------------------------------------------
TETRA_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]

OCTA_V = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
OCTA_F = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]


def subdivided_octahedron():
    """Octahedron split once (18 vertices, 32 faces), pushed to the sphere and
    jittered so that the interior vertices have somewhere to move."""
    verts = [list(v) for v in OCTA_V]
    mid = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            p = [(verts[a][k] + verts[b][k]) / 2 for k in range(3)]
            mid[key] = len(verts)
            verts.append(p)
        return mid[key]

    faces = []
    for a, b, c in OCTA_F:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        faces += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    out = []
    for i, p in enumerate(verts):
        n = math.sqrt(sum(x * x for x in p))
        j = 0.08 * math.sin(12.9898 * i + 1.0)
        out.append(tuple(round(x / n * (1 + j), 4) for x in p))
    return out, faces


QUAD_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
QUAD_F = [(0, 1, 2, 3)]

# Three triangles on the edge 0-1: a non-manifold edge.
NONMAN_V = [(0, 0, 0), (1, 0, 0), (0.5, 1, 0), (0.5, -1, 0), (0.5, 0, 1)]
NONMAN_F = [(0, 1, 2), (1, 0, 3), (0, 1, 4)]

# Two tetrahedra sharing vertex 0 only: a pinch (non-manifold vertex).
PINCH_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 0, 0), (0, -1, 0), (0, 0, -1)]
PINCH_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3),
           (0, 5, 4), (0, 4, 6), (0, 6, 5), (4, 5, 6)]


def fmt(x):
    return repr(x) if isinstance(x, float) else str(x)


def ply_ascii(verts, faces, comment=None, extra_vertex=None):
    """extra_vertex: list of (ply type, name, values per vertex)."""
    extra_vertex = extra_vertex or []
    h = ["ply", "format ascii 1.0"]
    if comment:
        h.append("comment " + comment)
    h += ["element vertex %d" % len(verts), "property float x", "property float y", "property float z"]
    h += ["property %s %s" % (t, n) for t, n, _ in extra_vertex]
    h += ["element face %d" % len(faces), "property list uchar int vertex_indices", "end_header"]
    body = []
    for i, v in enumerate(verts):
        body.append(" ".join([fmt(x) for x in v] + [fmt(vals[i]) for _, _, vals in extra_vertex]))
    for f in faces:
        body.append(" ".join([str(len(f))] + [str(i) for i in f]))
    return ("\n".join(h + body) + "\n").encode()


PACK = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f",
        "double": "d"}


def ply_binary(verts, faces, big_endian=False, coord="float", index="int", count="uchar", flags=None,
               extra_vertex=None):
    e = ">" if big_endian else "<"
    cf = {"float": "f", "double": "d"}[coord]
    idf = {"int": "i", "uint": "I", "short": "h", "ushort": "H"}[index]
    cnf = {"uchar": "B", "int": "i"}[count]
    h = ["ply", "format binary_%s_endian 1.0" % ("big" if big_endian else "little"),
         "element vertex %d" % len(verts)]
    h += ["property %s %s" % (coord, c) for c in "xyz"]
    if flags is not None:
        h.append("property int flags")
    for typ, name, _ in extra_vertex or []:
        h.append("property %s %s" % (typ, name))
    h += ["element face %d" % len(faces), "property list %s %s vertex_indices" % (count, index), "end_header"]
    out = ("\n".join(h) + "\n").encode()
    for i, v in enumerate(verts):
        out += struct.pack(e + cf * 3, *v)
        if flags is not None:
            out += struct.pack(e + "i", flags[i])
        for typ, _, values in extra_vertex or []:
            out += struct.pack(e + PACK[typ], values[i])
    for f in faces:
        out += struct.pack(e + cnf + idf * len(f), len(f), *f)
    return out


def off(verts, faces, keyword="OFF", vextra=None, comment=True):
    lines = [keyword]
    if comment:
        lines.append("# sodt fuzz seed")
    lines.append("%d %d 0" % (len(verts), len(faces)))
    for i, v in enumerate(verts):
        lines.append(" ".join([fmt(x) for x in v] + ([str(x) for x in vextra[i]] if vextra else [])))
    for f in faces:
        lines.append(" ".join([str(len(f))] + [str(i) for i in f]))
    return ("\n".join(lines) + "\n").encode()


def obj(verts, faces):
    lines = ["# sodt fuzz seed"] + ["v " + " ".join(fmt(x) for x in v) for v in verts]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return ("\n".join(lines) + "\n").encode()


def stl_binary(verts, faces):
    out = b"binary STL seed".ljust(80, b" ") + struct.pack("<I", len(faces))
    for f in faces:
        out += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *verts[i]) for i in f) + b"\0\0"
    return out


def stl_ascii(verts, faces):
    lines = ["solid seed"]
    for f in faces:
        lines += ["facet normal 0 0 0", " outer loop"] + ["  vertex " + " ".join(fmt(x) for x in verts[i]) for i in f]
        lines += [" endloop", "endfacet"]
    return ("\n".join(lines + ["endsolid seed"]) + "\n").encode()


BOM = b"\xef\xbb\xbf"  # a UTF-8 byte-order mark, which the text readers skip


def far_sphere(verts, radius, centre):
    """The sphere scaled to radius and moved to (centre, centre, centre): far
    from the origin for its size, as in a CAD export in world coordinates."""
    return [tuple(centre + radius * x for x in v) for v in verts]


def seeds():
    sv, sf = subdivided_octahedron()
    yield "tetra_ascii.ply", BASIC, ply_ascii(TETRA_V, TETRA_F)
    yield "tetra_binary_le.ply", FEATURE | FLIPS, ply_binary(TETRA_V, TETRA_F)
    yield "tetra_binary_be_double.ply", BASIC | FLOAT, ply_binary(TETRA_V, TETRA_F, big_endian=True, coord="double")
    yield "octa_binary_be_all_types.ply", FEATURE | FLOAT, ply_binary(
        OCTA_V, OCTA_F, big_endian=True, coord="double",
        extra_vertex=[(t, "p_" + t, [k + 1 for k in range(6)]) for t in PACK] +
                     [("double", "quality", [0.25] * 6), ("uchar", "red", [9] * 6)])
    yield "octa.off", OFF | BASIC, off(OCTA_V, OCTA_F)
    yield "octa_binary_ushort.ply", DENOISE | KEEPBEST, ply_binary(OCTA_V, OCTA_F, index="ushort")
    yield "octa_selected.ply", BASIC | SELECTED, ply_binary(OCTA_V, OCTA_F, flags=[0x20, 0, 0x20, 0, 0x20, 0])
    yield "sphere18.ply", BASIC | FLIPS, ply_binary(sv, sf)
    yield "sphere18_feature_fold.off", OFF | FEATURE | FOLD, off(sv, sf, comment=False)
    yield "sphere18_denoise_float.ply", DENOISE | FLOAT | FLIPS, ply_ascii(sv, sf)
    yield "quad.off", OFF | BASIC, off(QUAD_V, QUAD_F)
    yield "quad_ascii.ply", FEATURE, ply_ascii(QUAD_V, QUAD_F)
    yield "quad_int_count.ply", BASIC, ply_binary(QUAD_V, QUAD_F, count="int", index="uint")
    yield "octa_nan.ply", BASIC, ply_ascii([tuple(v) for v in OCTA_V[:4]] + [(0, "nan", 1), OCTA_V[5]], OCTA_F)
    yield "octa_nan.off", OFF | BASIC, off([OCTA_V[0], (0, 0, "inf")] + OCTA_V[2:], OCTA_F)
    yield "nonmanifold_edge.off", OFF | FEATURE | FLIPS, off(NONMAN_V, NONMAN_F)
    yield "nonmanifold_edge.ply", BASIC, ply_ascii(NONMAN_V, NONMAN_F)
    yield "pinch.off", OFF | DENOISE, off(PINCH_V, PINCH_F)
    yield "pinch_binary.ply", BASIC | FLIPS | FLOAT, ply_binary(PINCH_V, PINCH_F)
    yield "octa_coff.off", OFF | BASIC, off(OCTA_V, OCTA_F, "COFF", [(255, 0, 0, 255)] * 3 + [(0.5, 0.5, 0.5)] * 3)
    yield "octa_noff.off", OFF | FEATURE, off(OCTA_V, OCTA_F, "NOFF", [(0, 0, 1)] * 6)
    yield "octa_stoff.off", OFF | BASIC, off(OCTA_V, OCTA_F, "STOFF", [(0.25, 0.75)] * 6)
    yield "octa_quality_color.ply", FEATURE | KEEPBEST, ply_ascii(
        OCTA_V, OCTA_F, comment="x" * 40,
        extra_vertex=[("float", "quality", [0.5] * 6), ("uchar", "red", [1] * 6),
                      ("uchar", "green", [2] * 6), ("uchar", "blue", [3] * 6)])
    yield "octa.obj", OBJ | FLIPS, obj(OCTA_V, OCTA_F)
    yield "quad_negative.obj", OBJ | FLOAT, b"# quads, relative indices\n" + b"".join(
        b"v %s %s %s\n" % tuple(fmt(x).encode() for x in v) for v in QUAD_V) + b"".join(
        b"f " + b" ".join(b"%d/%d/%d" % (i - len(QUAD_V), 1, 1) for i in f) + b"\n" for f in QUAD_F)
    yield "octa_binary.stl", STL | KEEPBEST, stl_binary(OCTA_V, OCTA_F)
    yield "tetra_ascii.stl", STL | FLOAT, stl_ascii(TETRA_V, TETRA_F)
    yield "tetra_bom.obj", OBJ, BOM + obj(TETRA_V, TETRA_F)
    yield "octa_bom.off", OFF | FEATURE, BOM + off(OCTA_V, OCTA_F)
    yield "tetra_bom_ascii.ply", BASIC | FLOAT, BOM + ply_ascii(TETRA_V, TETRA_F)
    yield "tetra_bom_upper.stl", STL, BOM + stl_ascii(TETRA_V, TETRA_F).upper()
    yield "sphere18_far_double.ply", BASIC | FLIPS, ply_binary(far_sphere(sv, 0.01, 1e6), sf, coord="double")
    yield "points_only.off", OFF | BASIC, off(TETRA_V, [])
    yield "empty.ply", BASIC, b"ply\nformat ascii 1.0\nend_header\n"


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus")
    os.makedirs(out_dir, exist_ok=True)
    total = 0
    for name, cfg, data in seeds():
        blob = bytes([cfg]) + data
        with open(os.path.join(out_dir, name), "wb") as f:
            f.write(blob)
        total += len(blob)
    print("wrote %d seeds, %d bytes, to %s" % (len(list(seeds())), total, out_dir))


if __name__ == "__main__":
    main()
