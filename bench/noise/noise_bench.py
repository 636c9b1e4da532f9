#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Noise benchmark: denoisers against the clean mesh.

Makes noisy variants of clean meshes (Gaussian noise along the area-weighted
vertex normals, sigma = k x the clean mesh's mean edge length, k in 0.1, 0.2,
0.3, 0.5; fixed seeds; same vertices and faces), runs every method on each
and scores its output against the CLEAN mesh:

  * mean and Hausdorff distance to the clean surface (`sodt stats OUT
    --reference CLEAN`: sampled both ways, fixed seed, relative to the clean
    mesh's bounding-box diagonal), and the mean as a ratio to the noisy
    input's;
  * mean face-normal error in degrees, face by face (same connectivity);
  * dihedral error on the clean mesh's sharp edges (the normals of the two
    faces differ by more than 60 degrees): mean absolute difference of that
    angle, edge by edge;
  * min angle, share of angles below 30 degrees, faces turned by more than
    90 degrees against the clean mesh (`sodt stats`).

Methods: `sodt smooth --algorithm denoise` and `--algorithm filtered`
(defaults), PyMeshLab 2025.7's
Taubin, TwoStep and HC Laplacian smoothing (their defaults) and MeshDenoiser
(Debian's meshsdfilter-tools) with the default options of its upstream
(DenoisingOptions.txt, see MESHDENOISER_OPTIONS).

Clean meshes: the bundled cube (meshes/cube_noisy.ply snapped back to its
lattice, see meshes/README.md) and torus.off (smooth but coarse), a unit
icosphere made here (smooth, the scan-like case), and when ../shared/meshes
exists beside the checkout also fandisk.ply, spot.ply (scan-like) and the
shared fandisk_noise0.2.ply against fandisk.ply.

  bench/noise/noise_bench.py [--out build/noise-bench] [--results docs/RESULTS.md]

writes results.md, results.json and distance.svg to --out, the noisy inputs
and every output mesh under it; with --results also the section "Noise
benchmark" of docs/RESULTS.md (between its markers) and its figure. The
tables open with the targets of `sodt filtered`: at sigma 0.2-0.5 mean
distance <= 0.5x the input's and no worse than the best of Taubin and
MeshDenoiser, sharp dihedral error no worse than theirs, min angle >= 20
degrees, no inverted face; on the shared noisy fandisk <= 0.4x.
"""

import argparse
import datetime
import json
import math
import os
import shutil
import subprocess
import sys
import time
import zlib

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench", "compare"))
import pymeshlab_compare as pc  # noqa: E402  (the project's PyMeshLab helpers)

SIGMAS = (0.1, 0.2, 0.3, 0.5)
SHARP_DEG = 60.0
SODT = "sodt_denoise"
SODT_FILTERED = "sodt_filtered"
SODT_ALGORITHMS = {SODT: "denoise", SODT_FILTERED: "filtered"}
# MeshDenoiser's options: those of DenoisingOptions.txt, the example option
# file of MeshSDFilter (in Debian's meshsdfilter source package; the binary
# package ships none). An empty option file would leave the library's
# built-in values (Lambda 10, Eta 1, Mu 1, Nu 1), which push the noisy
# cube (sigma 0.2) out to +-1.25 (clean: +-1): not meant as defaults.
MESHDENOISER_OPTIONS = (("Lambda", 2), ("Eta", 1.5), ("Mu", 1.5), ("Nu", 0.3),
                        ("MeshUpdateClosenessWeight", 0.001), ("MeshUpdateIterations", 20),
                        ("OuterIterations", 5))
PYMESHLAB_KEYS = ("taubin", "two_steps", "hc_laplacian")
MESHES = ("cube", "torus", "sphere", "fandisk", "spot")
METHODS = (SODT, SODT_FILTERED) + PYMESHLAB_KEYS + ("meshdenoiser",)
LABELS = {"input": "noisy input", SODT: "sodt denoise", SODT_FILTERED: "sodt filtered", "taubin": "Taubin",
          "two_steps": "TwoStep", "hc_laplacian": "HC Laplacian", "meshdenoiser": "MeshDenoiser"}


def log(msg):
    print(f"[noise_bench] {msg}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------- geometry

def face_normals(V, F):
    """Unit face normals (zero for a face without area)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    length = np.linalg.norm(n, axis=1)
    return n / np.where(length > 0, length, 1.0)[:, None]


def vertex_normals(V, F):
    """Area-weighted vertex normals (the sum of the faces' cross products)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    vn = np.zeros_like(V)
    for k in range(3):
        np.add.at(vn, F[:, k], n)
    length = np.linalg.norm(vn, axis=1)
    return vn / np.where(length > 0, length, 1.0)[:, None]


def interior_edges(F):
    """Edges with exactly two faces: (vertex pairs, the two faces), and the
    number of unique edges."""
    he = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    face = np.tile(np.arange(len(F)), 3)
    he.sort(axis=1)
    order = np.lexsort((he[:, 1], he[:, 0]))
    he, face = he[order], face[order]
    new = np.ones(len(he), bool)
    new[1:] = np.any(he[1:] != he[:-1], axis=1)
    start = np.flatnonzero(new)
    count = np.diff(np.append(start, len(he)))
    two = start[count == 2]
    return he[two], np.stack([face[two], face[two + 1]], axis=1), len(start)


def mean_edge_length(V, F):
    he = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    he.sort(axis=1)
    e = np.unique(he, axis=0)
    return float(np.linalg.norm(V[e[:, 0]] - V[e[:, 1]], axis=1).mean())


def normal_angles(N, pairs):
    """Angle in degrees between the normals of each pair of faces."""
    c = np.einsum("ij,ij->i", N[pairs[:, 0]], N[pairs[:, 1]])
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


class Clean:
    """A clean mesh, its sharp edges and the file the measures refer to."""

    def __init__(self, name, kind, V, F, path):
        self.name, self.kind, self.V, self.F, self.path = name, kind, V, F, path
        self.N = face_normals(V, F)
        _, pairs, _ = interior_edges(F)
        angle = normal_angles(self.N, pairs)
        sharp = angle > SHARP_DEG
        self.sharp_pairs, self.sharp_angle = pairs[sharp], angle[sharp]
        self.mean_edge = mean_edge_length(V, F)


def shape_errors(clean, V, F):
    """Mean face-normal error and mean dihedral error on the clean mesh's
    sharp edges, in degrees; None when the connectivity differs."""
    if F.shape != clean.F.shape or not np.array_equal(F, clean.F) or V.shape != clean.V.shape:
        return None, None
    N = face_normals(V, F)
    c = np.einsum("ij,ij->i", N, clean.N)
    normal = float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))).mean())
    if len(clean.sharp_pairs) == 0:
        return normal, None
    dihedral = float(np.abs(normal_angles(N, clean.sharp_pairs) - clean.sharp_angle).mean())
    return normal, dihedral


# ---------------------------------------------------------------- mesh I/O (PyMeshLab)

def load(pm, path):
    ms = pm.MeshSet()
    ms.load_new_mesh(path)
    m = ms.current_mesh()
    return np.array(m.vertex_matrix(), dtype=np.float64), np.array(m.face_matrix(), dtype=np.int64)


def save(pm, path, V, F):
    """Double-precision binary PLY, coordinates and faces only."""
    ms = pm.MeshSet()
    ms.add_mesh(pm.Mesh(vertex_matrix=V, face_matrix=F.astype(np.int32)))
    ms.save_current_mesh(path, binary=True, save_vertex_quality=False, save_vertex_color=False,
                         save_face_color=False, save_face_quality=False)


def icosphere(levels):
    """The unit icosphere: an icosahedron split 1-to-4 `levels` times, every
    new vertex projected onto the sphere (as vcglib's tri::Sphere)."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                mid[key] = len(V) - 1
            return mid[key]
        G = []
        for a, b, c in F:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            G += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = G
    return np.array(V), np.array(F, dtype=np.int64)


def clean_meshes(pm, shared, folder, only):
    """The clean meshes, each saved to folder as NAME_clean.ply; and the given
    noisy variants (shared fandisk_noise0.2) as (clean name, path)."""
    out, given = [], []

    def add(name, kind, V, F):
        if only and name not in only:
            return
        path = os.path.join(folder, f"{name}_clean.ply")
        save(pm, path, V, F)
        out.append(Clean(name, kind, V, F, path))

    # cube_noisy.ply moves every lattice coordinate -1 + k/6 by less than half
    # a step (meshes/README.md): rounding gives the exact cube back, with the
    # same vertices and faces, right isosceles triangles and 144 sharp edges.
    V, F = load(pm, os.path.join(ROOT, "meshes", "cube_noisy.ply"))
    h = 1.0 / 6.0
    cube = -1.0 + np.round((V + 1.0) / h) * h
    if np.abs(cube - V).max() > 0.5 * h or not np.all(np.abs(cube).max(axis=1) == 1.0):
        raise RuntimeError("meshes/cube_noisy.ply no longer snaps to the cube's lattice")
    add("cube", "CAD", cube, F)
    add("torus", "smooth, coarse", *load(pm, os.path.join(ROOT, "meshes", "torus.off")))
    add("sphere", "smooth, scan-like", *icosphere(4))
    if shared and os.path.isdir(shared):
        for name, kind in (("fandisk", "CAD"), ("spot", "smooth, scan-like")):
            path = os.path.join(shared, f"{name}.ply")
            if os.path.isfile(path):
                add(name, kind, *load(pm, path))
        noisy = os.path.join(shared, "fandisk_noise0.2.ply")
        if os.path.isfile(noisy) and any(c.name == "fandisk" for c in out):
            given.append(("fandisk", noisy))
    else:
        log(f"no shared meshes in {shared}: the bundled cube and torus and the icosphere only")
    return out, given


def add_noise(clean, k):
    """The noisy variant for noise level k: its vertices, seed and the
    realised RMS displacement in mean edges."""
    seed = zlib.crc32(f"{clean.name}:{k}".encode())
    rng = np.random.default_rng(seed)
    d = rng.standard_normal(len(clean.V)) * k * clean.mean_edge
    V = clean.V + d[:, None] * vertex_normals(clean.V, clean.F)
    return V, seed, float(np.sqrt(np.mean(d * d)) / clean.mean_edge)


# ---------------------------------------------------------------- methods

def run_sodt(sodt, noisy, out, threads, algorithm="denoise"):
    report = out + ".report.json"
    start = time.perf_counter()
    subprocess.run([sodt, "smooth", noisy, out, "--algorithm", algorithm, "--threads", str(threads),
                    "--distance", "off", "--report", report, "--quiet"], check=True,
                   capture_output=True, text=True)
    seconds = time.perf_counter() - start
    with open(report, encoding="utf-8") as f:
        r = json.load(f)
    return seconds, {"classes": r["classes"], "smoothing_seconds": r["seconds"]}


def run_meshdenoiser(exe, options, noisy, out):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    start = time.perf_counter()
    subprocess.run([exe, options, noisy, out], check=True, capture_output=True, text=True, env=env)
    return time.perf_counter() - start, {}


def corner_share(sodt, mesh, work):
    """The share of vertices `sodt smooth --algorithm denoise` classifies as
    corners (corners never move), from a run without sweeps."""
    out = os.path.join(work, "classes_" + os.path.basename(mesh))
    subprocess.run([sodt, "smooth", mesh, out, "--algorithm", "denoise", "--iterations", "0",
                    "--distance", "off", "--report", out + ".json", "--quiet"], check=True,
                   capture_output=True, text=True)
    with open(out + ".json", encoding="utf-8") as f:
        c = json.load(f)["classes"]
    os.remove(out)
    os.remove(out + ".json")
    return c["corner"] / max(1, sum(c.values()))


# ---------------------------------------------------------------- one case

def measure(pm, sodt, clean, path, before=None):
    """The scores of one mesh; with `before` (the noisy input's vertices) also
    the share of vertices that did not move and their share of the summed
    distances from each vertex to its clean position."""
    st = pc.sodt_stats(sodt, path, clean.path)
    V, F = load(pm, path)
    normal, dihedral = shape_errors(clean, V, F)
    r = {"mean_rel": st["mean_distance_rel"], "hausdorff_rel": st["hausdorff_rel"],
         "normal_err_deg": normal, "sharp_dihedral_err_deg": dihedral,
         "min_angle": st["min_angle"], "frac_below_30": st["frac_below_30"],
         "inverted": st["inverted_faces"], "noise_estimate": st.get("noise_estimate")}
    if before is not None and normal is not None:
        still = np.all(V == before, axis=1)
        err = np.linalg.norm(V - clean.V, axis=1)
        r["unmoved_share"] = float(still.mean())
        r["unmoved_error_share"] = float(err[still].sum() / err.sum()) if err.sum() > 0 else 0.0
    return r


def run_case(a, pm, clean, noisy, sigma, seed, rms, methods, folder):
    """Every method on one noisy file; rows of the results (input first)."""
    base = os.path.splitext(os.path.basename(noisy))[0]
    case = {"mesh": clean.name, "kind": clean.kind, "sigma": sigma, "seed": seed,
            "noise_rms_edges": rms, "input_file": os.path.relpath(noisy, a.out)}
    inp = measure(pm, a.sodt, clean, noisy)
    before = load(pm, noisy)[0]
    corners_in = corner_share(a.sodt, noisy, folder)
    rows = [dict(case, method="input", **inp, corner_share=corners_in, seconds=None)]
    by_key = {m.key: m for m in pc.builtin_methods()}
    for key in methods:
        out = os.path.join(folder, f"{base}_{key}.ply")
        extra, error = {}, ""
        try:
            if key in SODT_ALGORITHMS:
                seconds, extra = run_sodt(a.sodt, noisy, out, a.threads, SODT_ALGORITHMS[key])
                extra["corner_share"] = extra["classes"]["corner"] / max(1, sum(extra["classes"].values()))
            elif key == "meshdenoiser":
                seconds, extra = run_meshdenoiser(a.meshdenoiser, a.meshdenoiser_options, noisy, out)
            else:
                # The project's PyMeshLab run (fresh MeshSet, save as double PLY),
                # with the filter's own defaults rather than the comparison's
                # matched step count.
                m = by_key[key]
                m = pc.Method(m.key, m.label, m.filter, {}, True)
                r = pc.run_method(pm, a.sodt, noisy, m, folder)
                if r.error:
                    raise RuntimeError(r.error)
                seconds, out = r.seconds, r.output
            scores = measure(pm, a.sodt, clean, out, before)
        except (subprocess.CalledProcessError, RuntimeError, OSError) as e:
            error = getattr(e, "stderr", None) or str(e)
            error = error.strip().splitlines()[-1] if error.strip() else type(e).__name__
            scores, seconds = {}, None
            log(f"  {key} failed: {error}")
        row = dict(case, method=key, seconds=seconds, output=os.path.relpath(out, a.out), **scores,
                   **extra)
        if error:
            row["error"] = error
        elif inp["mean_rel"]:
            row["mean_ratio"] = row["mean_rel"] / inp["mean_rel"]
        rows.append(row)
        if not error:
            log(f"  {LABELS[key]:<13} mean {row['mean_ratio']:.2f}x input, min angle "
                f"{row['min_angle']:.1f}, {seconds:.2f} s")
    return rows


# ---------------------------------------------------------------- reports

def fmt(x, spec, none="–"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return none
    return format(x, spec)


def pivot(rows, cases, methods, cell, title, note, with_input=None):
    """A table with a row per case and a column per method."""
    head = "| mesh | σ | " + ("input | " if with_input else "") + " | ".join(LABELS[m] for m in methods) + " |"
    out = [f"**{title}** {note}", "", head,
           "|---|---:|" + ("---:|" if with_input else "") + "---:|" * len(methods)]
    for mesh, sigma in cases:
        r = {x["method"]: x for x in rows if x["mesh"] == mesh and x["sigma"] == sigma}
        cells = [cell(r[m]) if m in r and "error" not in r[m] else "failed" if m in r else ""
                 for m in methods]
        lead = [with_input(r["input"])] if with_input else []
        out.append(f"| {mesh} | {sigma} | " + " | ".join(lead + cells) + " |")
    return out


def best_marked(rows, cases, methods, key):
    """cell function marking the smallest value of key among the methods in bold."""
    best = {}
    for mesh, sigma in cases:
        vals = [x[key] for x in rows if x["mesh"] == mesh and x["sigma"] == sigma
                and x["method"] in methods and x.get(key) is not None and "error" not in x]
        best[(mesh, sigma)] = min(vals) if vals else None
    return best


def distinct(a, b, digits):
    """a and b as text with `digits` decimals, or with as many more as it
    takes (up to 4) to tell them apart when they differ."""
    d = digits
    while d < digits + 4 and a != b and f"{a:.{d}f}" == f"{b:.{d}f}":
        d += 1
    return f"{a:.{d}f}", f"{b:.{d}f}"


TARGET_SIGMAS = (0.2, 0.3, 0.5)
TARGET_RIVALS = ("taubin", "meshdenoiser")
RESULTS_BEGIN = "<!-- noise-benchmark:begin -->"
RESULTS_END = "<!-- noise-benchmark:end -->"


def target_checks(rows, method=SODT_FILTERED):
    """The denoiser's targets, case by case: at sigma 0.2-0.5, mean distance
    <= 0.5x the input's and <= the best of Taubin and MeshDenoiser, sharp
    dihedral error <= theirs, min angle >= 20 degrees, no inverted face; on
    the shared noisy fandisk, mean distance <= 0.4x. A list of (mesh, sigma,
    [(label, value text, met or None when not measurable)])."""
    out = []
    cases = []
    for x in rows:
        if (x["mesh"], x["sigma"]) not in cases:
            cases.append((x["mesh"], x["sigma"]))
    for mesh, sigma in cases:
        if sigma not in TARGET_SIGMAS and sigma != "shared":
            continue
        r = {x["method"]: x for x in rows if x["mesh"] == mesh and x["sigma"] == sigma and "error" not in x}
        if method not in r:
            continue
        me = r[method]
        checks = []
        if sigma == "shared":
            checks.append(("mean ≤ 0.4×", f"{me['mean_ratio']:.2f}×", me["mean_ratio"] <= 0.4))
        else:
            checks.append(("mean ≤ 0.5×", f"{me['mean_ratio']:.2f}×", me["mean_ratio"] <= 0.5))
            rivals = [r[m] for m in TARGET_RIVALS if m in r]
            if rivals:
                best = min(x["mean_ratio"] for x in rivals)
                a, b = distinct(me["mean_ratio"], best, 2)
                checks.append(("mean ≤ best rival", f"{a}× vs {b}×", me["mean_ratio"] <= best))
                dh = [x["sharp_dihedral_err_deg"] for x in rivals if x.get("sharp_dihedral_err_deg") is not None]
                if me.get("sharp_dihedral_err_deg") is not None and dh:
                    a, b = distinct(me["sharp_dihedral_err_deg"], min(dh), 1)
                    checks.append(("dihedral ≤ best rival", f"{a}° vs {b}°", me["sharp_dihedral_err_deg"] <= min(dh)))
            checks.append(("min angle ≥ 20°", f"{me['min_angle']:.1f}°", me["min_angle"] >= 20))
            checks.append(("no inverted face", f"{me['inverted']}", me["inverted"] == 0))
        out.append((mesh, sigma, checks))
    return out


def targets_markdown(rows, method=SODT_FILTERED):
    """The target checks as a table, and a count."""
    checks = target_checks(rows, method)
    if not checks:
        return []
    met = sum(ok for _m, _s, cs in checks for _l, _v, ok in cs)
    total = sum(len(cs) for _m, _s, cs in checks)
    out = [f"**The targets of `{LABELS[method]}`** (rivals: the best of "
           f"{' and '.join(LABELS[m] for m in TARGET_RIVALS)} on the same input; ✓ met, ✗ not met): "
           f"{met} of {total} met.", "",
           "| mesh | σ | " + " | ".join(lbl for lbl, _v, _ok in checks[0][2]) + " |",
           "|---|---:|" + "---|" * len(checks[0][2])]
    for mesh, sigma, cs in checks:
        by = {lbl: (v, ok) for lbl, v, ok in cs}
        cells = []
        for lbl, _v, _ok in checks[0][2]:
            v, ok = by.get(lbl, ("–", None))
            cells.append("–" if ok is None else f"{'✓' if ok else '✗'} {v}")
        if sigma == "shared":
            cells = [f"{'✓' if cs[0][2] else '✗'} {cs[0][1]} (target ≤ 0.4×)"] + ["–"] * (len(checks[0][2]) - 1)
        out.append(f"| {mesh} | {sigma} | " + " | ".join(cells) + " |")
    return out


def markdown(rows, meta, methods):
    cases = []
    for x in rows:
        if (x["mesh"], x["sigma"]) not in cases:
            cases.append((x["mesh"], x["sigma"]))
    best_ratio = best_marked(rows, cases, methods, "mean_ratio")
    best_dihedral = best_marked(rows, cases, methods, "sharp_dihedral_err_deg")

    def bold_if(x, key, best, spec):
        v = x.get(key)
        s = fmt(v, spec)
        return f"**{s}**" if v is not None and v == best[(x["mesh"], x["sigma"])] else s

    out = ["# Noise benchmark", "",
           f"Generated {meta['date']} by `{meta['command']}` ({meta['processor']}; sodt "
           f"{meta['sodt_version']}, PyMeshLab {meta['pymeshlab_version']}, meshsdfilter-tools "
           f"{meta['meshsdfilter_version']}; {meta['minutes']:.1f} min).", "",
           "σ: the noise's standard deviation in mean edge lengths of the clean mesh (\"shared\": "
           "`../shared/meshes/fandisk_noise0.2.ply` as it is). Distances are relative to the clean "
           "mesh's bounding-box diagonal; normal and dihedral errors are face by face and edge by "
           "edge against the clean mesh (same connectivity); bold: the best method of the row.", ""]
    if SODT_FILTERED in methods:
        out += targets_markdown(rows) + [""]
    out += pivot(rows, cases, methods,
                 lambda x: bold_if(x, "mean_ratio", best_ratio, ".2f"),
                 "Mean distance to the clean mesh,", "× the noisy input's (input column: % of the "
                 "diagonal; the denoiser's target: ≤ 0.5×):",
                 with_input=lambda x: fmt(100 * x["mean_rel"], ".3f") + "%")
    out.append("")
    out += pivot(rows, cases, methods,
                 lambda x: fmt(100 * x["hausdorff_rel"], ".2f") + "%",
                 "Hausdorff distance to the clean mesh,", "% of the diagonal:",
                 with_input=lambda x: fmt(100 * x["hausdorff_rel"], ".2f") + "%")
    out.append("")
    out += pivot(rows, cases, methods,
                 lambda x: fmt(x["normal_err_deg"], ".1f") + " / " +
                 bold_if(x, "sharp_dihedral_err_deg", best_dihedral, ".1f"),
                 "Face-normal error / sharp-edge dihedral error,", "mean degrees (\"–\": the clean "
                 "mesh has no edge sharper than 60°):",
                 with_input=lambda x: fmt(x["normal_err_deg"], ".1f") + " / " +
                 fmt(x["sharp_dihedral_err_deg"], ".1f"))
    out.append("")
    out += pivot(rows, cases, methods,
                 lambda x: f"{fmt(x['min_angle'], '.1f')}° / {fmt(100 * x['frac_below_30'], '.1f')}%"
                 f" / {fmt(x['inverted'], 'd')}",
                 "Min angle / angles below 30° / inverted faces", "(turned by more than 90° against "
                 "the clean mesh; target: ≥ 20°, 0 inverted):",
                 with_input=lambda x: f"{fmt(x['min_angle'], '.1f')}° / "
                 f"{fmt(100 * x['frac_below_30'], '.1f')}% / {fmt(x['inverted'], 'd')}")
    out.append("")
    out += ["**The noise, as made and as `sodt stats` estimates it** (`noise_estimate`, mean edges), "
            "**the vertices `sodt smooth --algorithm denoise` classifies as corners** (corners never "
            "move), the vertices it leaves where they were and their share of the summed distances "
            "from each vertex to its clean position, and the seconds of each method (whole call):", "",
            "| mesh | σ | noise RMS (edges) | estimated | corners, clean | corners, noisy | sodt: unmoved | "
            "their error share | " + " | ".join(f"s {LABELS[m]}" for m in methods) + " |",
            "|---|---:|---:|---:|---:|---:|---:|---:|" + "---:|" * len(methods)]
    for mesh, sigma in cases:
        r = {x["method"]: x for x in rows if x["mesh"] == mesh and x["sigma"] == sigma}
        out.append(f"| {mesh} | {sigma} | {fmt(r['input']['noise_rms_edges'], '.3f')} | "
                   f"{fmt(r['input'].get('noise_estimate'), '.3f')} | "
                   f"{100 * meta['clean_corner_share'][mesh]:.2f}% | "
                   f"{100 * r['input']['corner_share']:.1f}% | " +
                   " | ".join(fmt(100 * r[SODT][k], ".1f") + "%" if SODT in r and k in r[SODT] else "–"
                              for k in ("unmoved_share", "unmoved_error_share")) + " | " +
                   " | ".join(fmt(r[m].get("seconds") if m in r else None, ".2f") for m in methods) + " |")
    return "\n".join(out) + "\n"


def figure(rows, path, methods):
    import matplotlib
    matplotlib.use("Agg")
    matplotlib.rcParams.update({"svg.hashsalt": "noise-bench", "svg.fonttype": "none"})
    import matplotlib.pyplot as plt
    meshes = []
    for x in rows:
        if x["mesh"] not in meshes:
            meshes.append(x["mesh"])
    fig, axes = plt.subplots(1, len(meshes), figsize=(3.4 * len(meshes), 3.2), squeeze=False)
    for ax, mesh in zip(axes[0], meshes):
        for m in ("input",) + tuple(methods):
            pts = sorted((x["sigma"], 100 * x["mean_rel"]) for x in rows
                         if x["mesh"] == mesh and x["method"] == m and isinstance(x["sigma"], float)
                         and x.get("mean_rel") is not None)
            if pts:
                ax.plot(*zip(*pts), marker="o", ms=3, label=LABELS[m],
                        linestyle="--" if m == "input" else "-", color="black" if m == "input" else None)
        ax.set_title(mesh)
        ax.set_yscale("log")
        ax.set_xlabel("noise σ (mean edges)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("mean distance to clean (% diagonal)")
    axes[0][-1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, metadata={"Date": None})
    plt.close(fig)


def results_section(md, figure_rel):
    """The benchmark's markdown as a section of docs/RESULTS.md, between
    markers, with the figure."""
    lines = md.rstrip("\n").split("\n")
    assert lines[0] == "# Noise benchmark"
    body = lines[1:]
    at = next((i for i, x in enumerate(body) if x.startswith("Generated ")), 0) + 1
    fig = ["", f"![Mean distance to the clean mesh against the noise level, per mesh and method]({figure_rel})",
           "", "*Mean distance to the clean mesh (% of its diagonal, log scale) against σ; dashed: the noisy "
           "input.*"]
    return "\n".join([RESULTS_BEGIN, "", "## Noise benchmark: denoisers against the clean mesh"] +
                      body[:at] + fig + body[at:] + ["", RESULTS_END]) + "\n"


def replace_results(path, section):
    """Writes section into the RESULTS.md at path: in place of the old one
    between the markers, or appended."""
    pc.replace_section(path, section, RESULTS_BEGIN, RESULTS_END)


def package_version(name):
    r = subprocess.run(["dpkg-query", "-W", "-f=${Version}", name], capture_output=True, text=True)
    return r.stdout.strip() or "unknown"


# ---------------------------------------------------------------- main

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "noise-bench"),
                    help="output folder (default: build/noise-bench of this checkout)")
    ap.add_argument("--sodt", default=os.path.join(ROOT, "build", "cli", "sodt"),
                    help="the sodt command (default: build/cli/sodt of this checkout)")
    ap.add_argument("--pymeshlab", help="folder holding PyMeshLab's pymeshlab/ (default: the one "
                    "scripts/build-meshlab-2025.sh builds)")
    ap.add_argument("--meshdenoiser", default=shutil.which("MeshDenoiser") or "MeshDenoiser",
                    help="MeshDenoiser of Debian's meshsdfilter-tools (default: on PATH)")
    ap.add_argument("--meshdenoiser-options", help="its option file (default: upstream's "
                    "DenoisingOptions.txt values, written to the output folder)")
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(ROOT), "shared", "meshes"),
                    help="the shared meshes (default: ../shared/meshes beside the checkout; "
                    "skipped when missing)")
    ap.add_argument("--sigmas", default=",".join(map(str, SIGMAS)),
                    help="noise levels in mean edge lengths (default: %(default)s)")
    ap.add_argument("--meshes", help="comma-separated subset of " + ",".join(MESHES))
    ap.add_argument("--methods", default=",".join(METHODS), help="comma-separated subset of "
                    "%(default)s")
    ap.add_argument("--threads", type=int, default=1, help="threads of sodt (default 1; the "
                    "result is the same for any count)")
    ap.add_argument("--results", help="also write the tables and the figure as the noise "
                    "benchmark section of this RESULTS.md (docs/RESULTS.md; the figure goes to "
                    "figures/noise-distance.svg beside it)")
    a = ap.parse_args(argv)
    started = time.perf_counter()
    methods = [m for m in a.methods.split(",") if m]
    for m in methods:
        if m not in METHODS:
            ap.error(f"unknown method '{m}' (one of {', '.join(METHODS)})")
    sigmas = [float(s) for s in a.sigmas.split(",") if s]
    only = set(a.meshes.split(",")) if a.meshes else None
    if only and not only <= set(MESHES):
        ap.error(f"unknown mesh in --meshes (known: {', '.join(MESHES)})")
    if not os.path.isfile(a.sodt):
        ap.error(f"--sodt {a.sodt} does not exist (build it: cmake --build build --target sodt)")
    if "meshdenoiser" in methods and not shutil.which(a.meshdenoiser):
        ap.error(f"MeshDenoiser not found ({a.meshdenoiser}): install Debian's meshsdfilter-tools "
                 "or leave meshdenoiser out of --methods")
    if not a.pymeshlab:
        a.pymeshlab = os.path.join(subprocess.run(
            ["bash", os.path.join(ROOT, "scripts", "build-meshlab-2025.sh"), "--print-dir"],
            check=True, capture_output=True, text=True).stdout.strip(), "pymeshlab")
    sys.path.insert(0, pc.pristine_pymeshlab(a.pymeshlab))
    import pymeshlab as pm

    a.out = os.path.abspath(a.out)
    inputs, outputs = os.path.join(a.out, "inputs"), os.path.join(a.out, "outputs")
    os.makedirs(inputs, exist_ok=True)
    os.makedirs(outputs, exist_ok=True)
    if not a.meshdenoiser_options:
        a.meshdenoiser_options = os.path.join(a.out, "DenoisingOptions.txt")
        with open(a.meshdenoiser_options, "w", encoding="utf-8") as f:
            f.write("# MeshSDFilter's example DenoisingOptions.txt (bench/noise/noise_bench.py)\n")
            f.writelines(f"{k} {v}\n" for k, v in MESHDENOISER_OPTIONS)

    cleans, given = clean_meshes(pm, a.shared, inputs, only)
    meta = {"date": datetime.date.today().isoformat(),
            "command": "bench/noise/noise_bench.py" + "".join(" " + x for x in (argv or sys.argv[1:])),
            "processor": pc.processor_name(),
            "sodt_version": subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"],
                                           capture_output=True, text=True).stdout.strip() or "unknown",
            "pymeshlab_version": getattr(pm, "__version__", "2025.7"),
            "meshsdfilter_version": package_version("meshsdfilter-tools"),
            "meshdenoiser_options": open(a.meshdenoiser_options, encoding="utf-8").read(),
            "sigmas": sigmas, "sharp_deg": SHARP_DEG, "methods": methods,
            "clean": {c.name: {"kind": c.kind, "vertices": len(c.V), "faces": len(c.F),
                               "mean_edge": c.mean_edge, "sharp_edges": len(c.sharp_pairs)}
                      for c in cleans},
            "clean_corner_share": {c.name: corner_share(a.sodt, c.path, outputs) for c in cleans}}
    rows = []
    by_name = {c.name: c for c in cleans}
    cases = [(c, k) for c in cleans for k in sigmas] + [(by_name[n], p) for n, p in given]
    for i, (clean, k) in enumerate(cases, 1):
        if isinstance(k, str):
            noisy, sigma, seed, rms = k, "shared", None, None
            log(f"[{i}/{len(cases)}] {os.path.basename(noisy)} (shared) against {clean.name}")
        else:
            V, seed, rms = add_noise(clean, k)
            noisy = os.path.join(inputs, f"{clean.name}_s{k}.ply")
            save(pm, noisy, V, clean.F)
            sigma = k
            log(f"[{i}/{len(cases)}] {clean.name}, sigma {k} mean edges (seed {seed})")
        rows += run_case(a, pm, clean, noisy, sigma, seed, rms, methods, outputs)

    meta["minutes"] = (time.perf_counter() - started) / 60
    with open(os.path.join(a.out, "results.json"), "w", encoding="utf-8") as f:
        json.dump({"meta": meta, "rows": rows}, f, indent=1)
    with open(os.path.join(a.out, "results.md"), "w", encoding="utf-8") as f:
        f.write(markdown(rows, meta, methods))
    figure(rows, os.path.join(a.out, "distance.svg"), methods)
    log(f"wrote results.md, results.json and distance.svg to {a.out} in {meta['minutes']:.1f} min")
    if a.results:
        figures = os.path.join(os.path.dirname(os.path.abspath(a.results)), "figures")
        os.makedirs(figures, exist_ok=True)
        shutil.copyfile(os.path.join(a.out, "distance.svg"), os.path.join(figures, "noise-distance.svg"))
        replace_results(a.results, results_section(markdown(rows, meta, methods), "figures/noise-distance.svg"))
        log(f"wrote the noise benchmark section of {a.results} and figures/noise-distance.svg beside it")
    return 0


if __name__ == "__main__":
    sys.exit(main())
