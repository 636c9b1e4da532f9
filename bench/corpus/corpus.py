#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The corpus list (corpus.tsv) and the fetched cache (index.tsv, stats/).

    corpus.py manifest [--dir DIR] [--out MANIFEST.md]   rewrite the manifest
"""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
LIST = os.path.join(HERE, "corpus.tsv")
FIELDS = ["name", "kind", "package", "member", "transform", "sha256", "license", "quick", "note"]
KINDS = ("cad", "scan", "organic", "isosurface")


def default_dir():
    if os.environ.get("SODT_CORPUS_DIR"):
        return os.environ["SODT_CORPUS_DIR"]
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache, "sodt", "corpus-r1")


def algorithm_for(kind):
    """The README's recommendation: feature for CAD parts, basic for organic,
    scanned and isosurface meshes."""
    return "feature" if kind == "cad" else "basic"


def read_list(path=LIST):
    rows = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if line.startswith("#") or line.startswith("name\t") or not line.strip():
                continue
            parts = line.rstrip("\n").split("\t")
            if len(parts) != len(FIELDS):
                raise SystemExit("corpus.py: %s:%d has %d fields, %d expected" % (path, n, len(parts), len(FIELDS)))
            row = dict(zip(FIELDS, parts))
            if row["kind"] not in KINDS:
                raise SystemExit("corpus.py: %s:%d: kind %r is not one of %s" % (path, n, row["kind"], ", ".join(KINDS)))
            rows.append(row)
    return rows


def read_index(cache):
    """name -> {file (absolute), package, version, member} of the fetched meshes."""
    path = os.path.join(cache, "index.tsv")
    if not os.path.isfile(path):
        raise FileNotFoundError("%s is missing: run bench/corpus/fetch.sh first" % path)
    out = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            name, kind, rel, pkg, ver, member = line.rstrip("\n").split("\t")
            out[name] = {"kind": kind, "file": os.path.join(cache, rel), "package": pkg, "version": ver,
                         "member": member}
    return out


def read_stats(cache, name):
    with open(os.path.join(cache, "stats", name + ".json"), encoding="utf-8") as f:
        return json.load(f)


def manifest(cache, out):
    rows = read_list()
    index = read_index(cache)
    missing = [r["name"] for r in rows if r["name"] not in index]
    if missing:
        raise SystemExit("corpus.py: not fetched: %s (run bench/corpus/fetch.sh without --only/--quick)"
                         % ", ".join(missing))
    counts = {k: sum(r["kind"] == k for r in rows) for k in KINDS}
    pkgs = {}
    for r in rows:
        i = index[r["name"]]
        pkgs.setdefault(r["package"], (i["version"], r["license"], []))[2].append(r["name"])
    L = []
    L.append("# The real-world corpus (issue 44, item 7)\n")
    L.append("%d meshes from Debian 12 packages, none of them in `shared/meshes`: %s. "
             "Not committed: `bench/corpus/fetch.sh` downloads the packages with `apt-get download` and "
             "extracts the files into `${SODT_CORPUS_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/sodt/corpus-r1}`; "
             "`bench/corpus/run.py` runs the benchmark on them ([RESULTS.md](RESULTS.md)).\n"
             % (len(rows), ", ".join("%d %s" % (counts[k], k) for k in KINDS)))
    L.append("- **List**: `corpus.tsv` (name, kind, package, path inside the package, how the file is made, "
             "its SHA-256, licence, quick subset). `fetch.sh` fails when a file's checksum differs, so a "
             "new package version that changes a mesh is noticed. This file is generated from the list and "
             "the fetched meshes by `fetch.sh --manifest`.")
    L.append("- **Kind** decides the algorithm of the benchmark, as the README's table recommends: `feature` for "
             "`cad` (CAD exports: STL/OFF/OBJ tessellations of parts, printer parts, CFD geometries, OpenSCAD "
             "renders), `basic` for `scan`, `organic` (characters and animals) and `isosurface` "
             "(marching-cubes-like). The packages do not state where most of CGAL's sample meshes come from; "
             "their kind is judged from the shape and the triangulation.")
    L.append("- **Files as shipped**: `.gz` files are gunzipped; OpenSCAD examples (CC0 sources) are rendered by "
             "Debian's `openscad` 2021.01 and their facets sorted into one order (OpenSCAD writes the same "
             "triangles in a different order from run to run). Nothing is repaired: STL corners are welded by "
             "`sodt` itself when it reads them.")
    L.append("- **Counts** below are measured by `meshtool.py stats` (STL welded by equal coordinates, polygons "
             "fan-triangulated): V = vertices used by faces, border = edges with one face, NM = edges with "
             "three or more faces, parts = connected components, needles / caps by CGAL 5.5's definitions "
             "(longest/shortest edge >= 4; an angle >= 160 degrees).\n")
    L.append("## Packages\n")
    L.append("| package | version | licence (its copyright file) | meshes |")
    L.append("|---|---|---|---:|")
    for p in sorted(pkgs):
        ver, lic, names = pkgs[p]
        L.append("| `%s` | %s | %s | %d |" % (p, ver, lic, len(names)))
    L.append("")
    L.append("## Meshes\n")
    L.append("| name | kind | package: path | V | F | border | NM | parts | min / max angle | needles | caps | quick | note |")
    L.append("|---|---|---|---:|---:|---:|---:|---:|---|---:|---:|:-:|---|")
    for r in rows:
        s = read_stats(cache, r["name"])
        how = {"file": "", "gunzip": " (gunzipped)", "scad": " (rendered)"}[r["transform"]]
        L.append("| %s | %s | `%s`: `%s`%s | %d | %d | %d | %d | %d | %.2f / %.1f | %d | %d | %s | %s |" % (
            r["name"], r["kind"], r["package"], r["member"], how, s["vertices"], s["faces"], s["border_edges"],
            s["nonmanifold_edges"], s["components"], s["min_angle"], s["max_angle"], s["needles"], s["caps"],
            "yes" if r["quick"] == "1" else "", r["note"]))
    L.append("")
    closed = sum(read_stats(cache, r["name"])["closed"] for r in rows)
    nm = sum(read_stats(cache, r["name"])["nonmanifold_edges"] > 0 for r in rows)
    deg = [r["name"] for r in rows if read_stats(cache, r["name"])["repeated_index_faces"] > 0]
    L.append("%d of %d meshes are closed; %d have non-manifold edges; %d have faces with a repeated vertex once "
             "welded (%s: their min / max angle is 0 / 180).\n"
             % (closed, len(rows), nm, len(deg), ", ".join(deg) or "none"))
    with open(out, "w", encoding="utf-8") as f:
        f.write("\n".join(L))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("manifest", help="rewrite MANIFEST.md from corpus.tsv and the fetched meshes")
    m.add_argument("--dir", default=default_dir(), help="the corpus cache (default: %(default)s)")
    m.add_argument("--out", default=os.path.join(HERE, "MANIFEST.md"))
    args = ap.parse_args(argv)
    try:
        manifest(args.dir, args.out)
    except (OSError, KeyError, ValueError) as err:
        print("corpus.py: %s" % err, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
