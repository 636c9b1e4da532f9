#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The corpus benchmark of issue 44: runs `sodt smooth` on every mesh of the
real-world corpus (bench/corpus/fetch.sh fetches it) and prints how the final
smallest angles, distances to the input, vertex counts, needles and caps and
times are distributed, then writes the tables as Markdown.

Each mesh is run with the README's algorithm for its kind (feature for CAD
exports, basic for scans, organic models and isosurfaces), 20 sweeps (the
default), the default guard and bound, and:

  flips    --flips                      the sweeps alone (the time reference)
  repair   --flips --repair             the configuration issue 44 measures
  extra    --flips --repair EXTRA       only with --extra "EXTRA" (e.g. "--refine")
  compare  COMPARE                      only with --compare "COMPARE", a whole option
                                        list (e.g. "--flips --refine", without --repair)

Issue 44's targets are evaluated on the repair run, or on the one --targets names.

Needles and caps are counted on the output by CGAL 5.5's definitions (longest /
shortest edge >= 4; an angle >= 160 degrees). The Hausdorff distance is the
report's hausdorff_rel (sampled, symmetric, relative to the input's bounding-box
diagonal) and, in brackets, its hausdorff_edges_rel (the same with points along
every edge too, which finds the farthest points of bent CAD edges). Vertex growth compares the output's vertices with the input's.

Exit status: 0 every run succeeded; 1 a run failed (the results are still
written and the failures listed) or the corpus / sodt is missing; 2 bad
command line.
"""
import argparse
import datetime
import json
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the checkout
import corpus  # noqa: E402
import meshtool  # noqa: E402

HAUSDORFF_LIMIT = 0.15   # percent of the diagonal (issue 44's "done when")
REPORT_ANGLE_BINS = (30, 20, 5, 1)


def find_sodt(arg):
    given = arg or os.environ.get("SODT")
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)):
            raise SystemExit("run.py: error: %s (--sodt or $SODT) is not an executable file" % given)
        return os.path.abspath(given)
    built = os.path.join(ROOT, "build", "cli", "sodt")
    if os.path.isfile(built) and os.access(built, os.X_OK):
        return built
    p = shutil.which("sodt")
    if p:
        return p
    raise SystemExit("run.py: error: no sodt binary: build it (cmake --build build --target sodt) "
                     "or pass --sodt PATH")


def git_describe():
    try:
        return subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def run_one(sodt, mesh, out, report, args):
    cmd = [sodt, "smooth", mesh, out, "--report", report, "--quiet"] + args
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    res = {"cmd": cmd, "exit": p.returncode, "wall": wall}
    # messages name files by their place in the corpus, not by this machine's path
    stderr = p.stderr.replace(os.path.dirname(os.path.dirname(mesh)) + os.sep, "$CORPUS/")
    if p.returncode != 0:
        res["error"] = (stderr.strip().splitlines() or ["(no message)"])[-1]
        return res
    warnings = [l for l in stderr.splitlines() if "warning" in l]
    if warnings:
        res["warnings"] = warnings
    with open(report, encoding="utf-8") as f:
        rep = json.load(f)
    below = rep.get("below_repair_angle") or []
    reasons = {}
    for b in below:
        reasons[b.get("reason", "?")] = reasons.get(b.get("reason", "?"), 0) + 1
    V, F = meshtool.read_mesh(out)
    needle, cap = meshtool.needles_caps(V, F)
    res.update({
        "vertices": rep["vertices"], "faces": rep["faces"],
        "min_angle_before": rep["min_angle_before"], "min_angle": rep["min_angle_after"],
        "max_angle": rep["max_angle_after"],
        "hausdorff_pct": None if rep.get("hausdorff_rel") is None else 100.0 * rep["hausdorff_rel"],
        "hausdorff_edges_pct": None if rep.get("hausdorff_edges_rel") is None else 100.0 * rep["hausdorff_edges_rel"],
        "seconds": rep["seconds"], "below_repair_angle": len(below), "below_reasons": reasons,
        "needles": int(needle.sum()), "caps": int(cap.sum()),
        "frac_below_30": rep["after"]["frac_below_30"],
        "fixed_nonmanifold": rep.get("fixed_nonmanifold", 0),
        "reoriented_faces": rep.get("reoriented_faces", 0),
        "inverted_faces": rep.get("inverted_faces"),
    })
    res["protected_angles"] = rep.get("protected_angles")
    res["min_angle_unprotected"] = rep.get("min_angle_unprotected")
    return res


def median(xs):
    return statistics.median(xs) if xs else float("nan")


def fmt(x, nd=1):
    if x is None or (isinstance(x, float) and x != x):
        return "—"
    return "%.*f" % (nd, x)


def summarize(results, cfg, kinds=None):
    rs = [r for r in results if (kinds is None or r["kind"] in kinds)]
    ok = [r for r in rs if cfg in r["runs"] and r["runs"][cfg]["exit"] == 0]
    s = {"n": len(rs), "ok": len(ok)}
    ang = [r["runs"][cfg]["min_angle"] for r in ok]
    s["median_angle"] = median(ang)
    s["ge30"] = sum(a >= 30 for a in ang)
    s["ge20"] = sum(a >= 20 for a in ang)
    s["lt5"] = sum(a < 5 for a in ang)
    s["lt1"] = sum(a < 1 for a in ang)
    # The targets leave out corners between features sharper than the
    # repair's target (the report's min_angle_unprotected, with the repair).
    unprot = [r["runs"][cfg].get("min_angle_unprotected") for r in ok]
    unprot = [u if u is not None else a for u, a in zip(unprot, ang)]
    s["ge30_u"] = sum(a >= 30 for a in unprot)
    s["ge20_u"] = sum(a >= 20 for a in unprot)
    s["protected_meshes"] = sum(((r["runs"][cfg].get("protected_angles") or {}).get("corners") or 0) > 0 for r in ok)
    hd = [r["runs"][cfg]["hausdorff_pct"] for r in ok if r["runs"][cfg]["hausdorff_pct"] is not None]
    s["hd_median"] = median(hd)
    s["hd_max"] = max(hd) if hd else float("nan")
    s["hd_over"] = sum(h > HAUSDORFF_LIMIT for h in hd)
    he = [r["runs"][cfg].get("hausdorff_edges_pct") for r in ok]
    he = [h for h in he if h is not None]
    s["hde_median"] = median(he)
    s["hde_max"] = max(he) if he else float("nan")
    s["hde_over"] = sum(h > HAUSDORFF_LIMIT for h in he)
    gr = [100.0 * (r["runs"][cfg]["vertices"] / r["vertices_in"] - 1.0) for r in ok]
    s["growth_median"] = median(gr)
    s["growth_max"] = max(gr) if gr else float("nan")
    s["clean"] = sum(r["runs"][cfg]["needles"] == 0 and r["runs"][cfg]["caps"] == 0 for r in ok)
    s["needles"] = sum(r["runs"][cfg]["needles"] for r in ok)
    s["caps"] = sum(r["runs"][cfg]["caps"] for r in ok)
    inv = [r["runs"][cfg].get("inverted_faces") or 0 for r in ok]
    s["inverted_meshes"] = sum(i > 0 for i in inv)
    s["inverted_faces"] = sum(inv)
    s["seconds"] = sum(r["runs"][cfg]["seconds"] for r in ok)
    ratio = [r["runs"][cfg]["seconds"] / r["runs"]["flips"]["seconds"] for r in ok
             if r["runs"].get("flips", {}).get("exit") == 0 and r["runs"]["flips"]["seconds"] > 0]
    s["ratio_median"] = median(ratio)
    s["ratio_max"] = max(ratio) if ratio else float("nan")
    return s


def input_summary(results, kinds=None):
    rs = [r for r in results if (kinds is None or r["kind"] in kinds)]
    ang = [r["in"]["min_angle"] for r in rs]
    return {"n": len(rs), "ok": len(rs), "median_angle": median(ang), "ge30": sum(a >= 30 for a in ang),
            "ge20": sum(a >= 20 for a in ang), "lt5": sum(a < 5 for a in ang), "lt1": sum(a < 1 for a in ang),
            "clean": sum(r["in"]["needles"] == 0 and r["in"]["caps"] == 0 for r in rs),
            "needles": sum(r["in"]["needles"] for r in rs), "caps": sum(r["in"]["caps"] for r in rs)}


def markdown(results, configs, meta, main="repair"):
    L = []
    n = len(results)
    L.append("# Corpus benchmark (issue 44)\n")
    L.append("Generated by `%s` on %s: %s (`%s`), %d meshes of [the corpus](MANIFEST.md)%s, %d cores "
             "(load average %.1f at the start, %.1f at the end: times are only comparable within one run), "
             "%.0f s in all.\n" % (meta["command"], meta["date"], meta["sodt_version"], meta["git"], n,
                                   meta["subset"], meta["cores"], meta["load"], meta["load_end"], meta["wall"]))
    L.append("Each mesh: `sodt smooth IN OUT --algorithm ALG` with 20 sweeps, the default guard and bound (0.1%% "
             "of the diagonal), ALG = `feature` for the %d CAD exports and `basic` for the %d scans, organic "
             "models and isosurfaces (the README's recommendation), and:\n"
             % (sum(r["kind"] == "cad" for r in results), sum(r["kind"] != "cad" for r in results)))
    for key, label, args in configs:
        L.append("- **%s**: `%s`" % (label, " ".join(args)))
    L.append("")
    failed = [(r["name"], key, r["runs"][key]["error"]) for r in results for key, _, _ in configs
              if key in r["runs"] and r["runs"][key]["exit"] != 0]
    if failed:
        L.append("**Failed runs** (counted as not reaching any target):\n")
        for name, key, err in failed:
            L.append("- `%s` (%s): %s" % (name, key, err))
        L.append("")
    s = summarize(results, main)
    L.append("## Issue 44's targets on this corpus (`%s`)\n" % " ".join(dict((k, a) for k, _, a in configs)[main]))
    L.append("The angle targets leave out the corners where features (border edges, or edges between two faces "
             "that are not slivers and turn by more than the feature angle) meet at less than the repair's "
             "target: the report's `min_angle_unprotected`. %d of the %d meshes have such corners.\n"
             % (s["protected_meshes"], s["ok"]))
    L.append("| target | measured | met |")
    L.append("|---|---|:-:|")

    def row(t, m, ok):
        L.append("| %s | %s | %s |" % (t, m, "yes" if ok else "**no**"))
    row("min angle >= 30 degrees (outside protected corners) on at least 80% of the meshes",
        "%d of %d (%.0f%%)" % (s["ge30_u"], n, 100.0 * s["ge30_u"] / n), s["ge30_u"] >= 0.8 * n)
    row(">= 20 degrees on at least 95%", "%d of %d (%.0f%%)" % (s["ge20_u"], n, 100.0 * s["ge20_u"] / n),
        s["ge20_u"] >= 0.95 * n)
    row("no needle or cap (CGAL's definitions) on 90%", "%d of %d (%.0f%%)" % (s["clean"], n, 100.0 * s["clean"] / n),
        s["clean"] >= 0.9 * n)
    row("symmetric Hausdorff <= %.2f%% of the diagonal on all" % HAUSDORFF_LIMIT,
        "%d above, max %s%% (with points along the edges: %d, max %s%%)"
        % (s["hd_over"], fmt(s["hd_max"], 3), s["hde_over"], fmt(s["hde_max"], 3)),
        s["hd_over"] == 0 and s["hde_over"] == 0 and s["ok"] == n)
    row("median vertex growth <= 30%", "%s%%" % fmt(s["growth_median"]), s["growth_median"] <= 30)
    row("the repair never takes more than 10 times the sweeps alone",
        "at most %s times (median %s)" % (fmt(s["ratio_max"]), fmt(s["ratio_median"])), s["ratio_max"] <= 10)
    L.append("")
    L.append("## Distribution\n")
    L.append("Smallest angle of the output, in degrees; Hausdorff distance to the input in %% of the input's "
             "bounding-box diagonal; growth = output vertices / input vertices - 1; a mesh is clean when it has "
             "no needle and no cap; time = the report's `seconds` (smoothing and repair, no I/O; the fastest of up to "
             "%d runs of a mesh that take less than %.0f s together, since on a shared machine a run of a few "
             "milliseconds can take 20 times longer), summed, and its ratio to the `flips` run of the same "
             "mesh.\n" % (meta["max_repeats"], meta["min_time"]))
    cols = [("input", None)] + [(label, key) for key, label, _ in configs]
    for title, kinds in (("all %d meshes" % n, None),
                         ("CAD exports (%d)" % sum(r["kind"] == "cad" for r in results), ("cad",)),
                         ("scans, organic, isosurfaces (%d)" % sum(r["kind"] != "cad" for r in results),
                          ("scan", "organic", "isosurface"))):
        sums = [input_summary(results, kinds) if key is None else summarize(results, key, kinds) for _, key in cols]
        if sums[0]["n"] == 0:
            continue
        L.append("**%s**\n" % title)
        L.append("| | " + " | ".join(c for c, _ in cols) + " |")
        L.append("|---|" + "---:|" * len(cols))

        def line(label, f):
            L.append("| %s | %s |" % (label, " | ".join(f(x, i) for i, x in enumerate(sums))))
        line("runs that succeeded", lambda x, i: "%d of %d" % (x["ok"], x["n"]))
        line("median min angle", lambda x, i: fmt(x["median_angle"]))
        line("min angle >= 30 / >= 20", lambda x, i: "%d / %d" % (x["ge30"], x["ge20"]))
        line("min angle < 5 / < 1", lambda x, i: "%d / %d" % (x["lt5"], x["lt1"]))
        line("meshes without needles and caps", lambda x, i: "%d" % x["clean"])
        line("needles / caps in all", lambda x, i: "%d / %d" % (x["needles"], x["caps"]))
        line("Hausdorff median / max (%)", lambda x, i: "—" if i == 0 else "%s / %s" % (fmt(x["hd_median"], 3), fmt(x["hd_max"], 3)))
        line("Hausdorff > %.2f%%" % HAUSDORFF_LIMIT, lambda x, i: "—" if i == 0 else "%d" % x["hd_over"])
        line("with points along the edges: median / max (%)",
             lambda x, i: "—" if i == 0 else "%s / %s" % (fmt(x["hde_median"], 3), fmt(x["hde_max"], 3)))
        line("with points along the edges: > %.2f%%" % HAUSDORFF_LIMIT,
             lambda x, i: "—" if i == 0 else "%d" % x["hde_over"])
        line("faces facing away from the input: meshes / faces",
             lambda x, i: "—" if i == 0 else "%d / %d" % (x["inverted_meshes"], x["inverted_faces"]))
        line("vertex growth median / max (%)", lambda x, i: "—" if i == 0 else "%s / %s" % (fmt(x["growth_median"]), fmt(x["growth_max"])))
        line("time (s)", lambda x, i: "—" if i == 0 else fmt(x["seconds"], 1))
        line("time / flips: median, max", lambda x, i: "—" if i == 0 or cols[i][1] == "flips" else "%s, %s" % (fmt(x["ratio_median"], 2), fmt(x["ratio_max"], 2)))
        L.append("")
    L.append("## Per mesh\n")
    L.append("Min angle: input → each configuration. Hausdorff, growth, needles/caps and *left* (triangles the "
             "repair left below its angle, by reason: p pinned, b bound, n non-manifold, g budget, r rounds) are those of "
             "the `%s` run; time: seconds of `flips` / `%s` and their ratio.\n" % (main, main))
    hdr = "| mesh | kind | V in | min angle: in → " + " → ".join(label for _, label, _ in configs) + \
          " | Hausdorff % (along edges) | growth % | needles / caps | left | time (s) | input notes |"
    L.append(hdr)
    L.append("|---|---|---:|---|---:|---:|---:|---|---|---|")
    for r in results:
        angles = [fmt(r["in"]["min_angle"], 2)]
        for key, _, _ in configs:
            x = r["runs"].get(key)
            angles.append("fail" if x is None or x["exit"] != 0 else fmt(x["min_angle"], 2))
        m = r["runs"].get(main)
        if m and m["exit"] == 0:
            hd = fmt(m["hausdorff_pct"], 3)
            if m["hausdorff_pct"] is not None and m["hausdorff_pct"] > HAUSDORFF_LIMIT:
                hd = "**%s**" % hd
            if m.get("hausdorff_edges_pct") is not None:
                hd += " (%s)" % fmt(m["hausdorff_edges_pct"], 3)
            gr = fmt(100.0 * (m["vertices"] / r["vertices_in"] - 1.0))
            nc = "%d / %d" % (m["needles"], m["caps"])
            left = " ".join("%d%s" % (v, {"pinned": "p", "bound": "b", "non-manifold": "n", "budget": "g", "rounds": "r"}.get(k, k))
                            for k, v in sorted(m["below_reasons"].items())) or "0"
            f = r["runs"].get("flips")
            tm = "%s / %s (%s×)" % (fmt(f["seconds"], 2), fmt(m["seconds"], 2), fmt(m["seconds"] / f["seconds"], 1)) \
                if f and f["exit"] == 0 and f["seconds"] > 0 else fmt(m["seconds"], 2)
        else:
            hd = gr = nc = left = tm = "—"
        notes = []
        f = r["runs"].get("flips") or m or {}
        if f.get("fixed_nonmanifold"):
            notes.append("%d vertices fixed (non-manifold)" % f["fixed_nonmanifold"])
        if f.get("reoriented_faces"):
            notes.append("%d faces reoriented" % f["reoriented_faces"])
        pa = (m or {}).get("protected_angles") or {}
        if pa.get("corners"):
            notes.append("%d corners sharper than the target between features (smallest %s°); min angle elsewhere %s°"
                         % (pa["corners"], fmt(pa.get("smallest_deg"), 2), fmt(m.get("min_angle_unprotected"), 2)))
        if r.get("repeated_index_faces"):
            notes.append("%d faces with a repeated vertex" % r["repeated_index_faces"])
        L.append("| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s |" % (
            r["name"], r["kind"], r["vertices_in"], " → ".join(angles), hd, gr, nc, left, tm, "; ".join(notes)))
    L.append("")
    return "\n".join(L)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", default=corpus.default_dir(), help="the corpus cache of fetch.sh (default: %(default)s)")
    ap.add_argument("--sodt", help="the sodt binary (default: $SODT, else build/cli/sodt of this checkout, else PATH)")
    ap.add_argument("--quick", action="store_true", help="only the meshes marked quick in corpus.tsv")
    ap.add_argument("--only", help="only these meshes (comma-separated names)")
    ap.add_argument("--extra", help='a third configuration: --flips --repair and these options, e.g. "--refine"')
    ap.add_argument("--extra-label", help="its name in the tables (default: the options)")
    ap.add_argument("--compare", help='another configuration given whole, e.g. "--flips --refine"')
    ap.add_argument("--compare-label", help="its name in the tables (default: the options)")
    ap.add_argument("--targets", choices=("repair", "extra", "compare"), default="repair",
                    help="the configuration whose issue-44 targets are checked (default: %(default)s)")
    ap.add_argument("--no-reference", action="store_true",
                    help="skip the --flips run (no time ratio; the tables lose that column)")
    ap.add_argument("--out", help="the Markdown results (default: bench/corpus/RESULTS.md for the whole corpus, "
                                  "WORK/RESULTS.md for --quick or --only)")
    ap.add_argument("--work", help="folder for outputs and reports (default: DIR/work)")
    ap.add_argument("--min-time", type=float, default=2.0,
                    help="run a mesh's configuration again until its runs took this many seconds in all "
                         "(at most --max-repeats runs) and count the fastest (default: %(default)s)")
    ap.add_argument("--max-repeats", type=int, default=5, help="(default: %(default)s)")
    ap.add_argument("--keep", action="store_true", help="keep the output meshes (default: only the reports)")
    # `--extra --refine` : the value starts with a dash, which argparse would take for an option
    raw = list(sys.argv[1:] if argv is None else argv)
    fixed = []
    while raw:
        a = raw.pop(0)
        if a in ("--extra", "--compare") and raw:
            a = a + "=" + raw.pop(0)
        fixed.append(a)
    args = ap.parse_args(fixed)

    sodt = find_sodt(args.sodt)
    try:
        index = corpus.read_index(args.dir)
    except FileNotFoundError as err:
        print("run.py: error: %s" % err, file=sys.stderr)
        return 1
    rows = corpus.read_list()
    if args.only:
        names = args.only.split(",")
        unknown = [n for n in names if n not in {r["name"] for r in rows}]
        if unknown:
            ap.error("--only: not in corpus.tsv: %s" % ", ".join(unknown))
        rows = [r for r in rows if r["name"] in names]
    if args.quick:
        rows = [r for r in rows if r["quick"] == "1"]
    missing = [r["name"] for r in rows if r["name"] not in index or not os.path.isfile(index[r["name"]]["file"])]
    if missing:
        print("run.py: error: not fetched: %s; run bench/corpus/fetch.sh%s" % (
            ", ".join(missing), " --quick" if args.quick else ""), file=sys.stderr)
        return 1
    work = os.path.abspath(args.work or os.path.join(args.dir, "work"))
    os.makedirs(work, exist_ok=True)
    subset = bool(args.quick or args.only)
    out_md = args.out or (os.path.join(work, "RESULTS.md") if subset else os.path.join(HERE, "RESULTS.md"))

    configs = []
    if not args.no_reference:
        configs.append(("flips", "flips", ["--flips"]))
    configs.append(("repair", "flips + repair", ["--flips", "--repair"]))
    if args.extra:
        extra = shlex.split(args.extra)
        configs.append(("extra", args.extra_label or "flips + repair " + args.extra, ["--flips", "--repair"] + extra))
    if args.compare:
        configs.append(("compare", args.compare_label or args.compare, shlex.split(args.compare)))
    if args.targets not in [k for k, _, _ in configs]:
        ap.error("--targets %s: that configuration is not run (give --%s)" % (args.targets, args.targets))
    for key, _, opts in configs:
        if "--algorithm" in opts or any(o.startswith("--algorithm=") for o in opts):
            ap.error("the algorithm follows the mesh's kind; --extra and --compare may not set --algorithm")

    version = subprocess.run([sodt, "--version"], capture_output=True, text=True).stdout.strip() or "?"
    print("run.py: %s (%s), %d meshes, work folder %s" % (sodt, version, len(rows), work))
    load_start = os.getloadavg()[0]
    t_start = time.monotonic()
    results = []
    for i, r in enumerate(rows, 1):
        name, kind = r["name"], r["kind"]
        mesh = index[name]["file"]
        alg = corpus.algorithm_for(kind)
        st = corpus.read_stats(args.dir, name)
        rec = {"name": name, "kind": kind, "algorithm": alg, "file": mesh, "vertices_in": st["vertices"],
               "repeated_index_faces": st["repeated_index_faces"],
               "faces_in": st["faces"], "in": {"min_angle": st["min_angle"], "needles": st["needles"],
                                               "caps": st["caps"]}, "runs": {}}
        for key, _, opts in configs:
            out = os.path.join(work, "%s.%s.off" % (name, key))
            rep = os.path.join(work, "%s.%s.json" % (name, key))
            res = run_one(sodt, mesh, out, rep, ["--algorithm", alg] + opts)
            # Small meshes are timed again (the same output, bit for bit) and the fastest run
            # counts: on a shared machine one run of a few milliseconds can take 20 times longer.
            times = [res.get("seconds")]
            spent = res["wall"]
            while res["exit"] == 0 and spent < args.min_time and len(times) < args.max_repeats:
                again = run_one(sodt, mesh, out, rep + ".again", ["--algorithm", alg] + opts)
                if again["exit"] != 0:
                    break
                times.append(again["seconds"])
                spent += again["wall"]
            if os.path.exists(rep + ".again"):
                os.remove(rep + ".again")
            if res["exit"] == 0:
                res["seconds_all"] = times
                res["seconds"] = min(times)
            if not args.keep and os.path.exists(out):
                os.remove(out)
            rec["runs"][key] = res
        # the input's vertex count as sodt reads it (STL welded), from a run without repair
        ref = rec["runs"].get("flips")
        if ref and ref["exit"] == 0:
            rec["vertices_in"] = ref["vertices"]
            rec["in"]["min_angle"] = ref["min_angle_before"]
        results.append(rec)
        parts = []
        for key, _, _ in configs:
            x = rec["runs"][key]
            parts.append("%s %s" % (key, "FAILED: " + x["error"] if x["exit"] else
                                    "%.2f° H %.3f%% V %+d %.2fs" % (x["min_angle"], x["hausdorff_pct"] or 0,
                                                                   x["vertices"] - rec["vertices_in"], x["seconds"])))
        print("[%2d/%d] %-22s %-10s %6.2f° -> %s" % (i, len(rows), name, kind, st["min_angle"], " | ".join(parts)),
              flush=True)
    wall = time.monotonic() - t_start
    meta = {"command": "bench/corpus/run.py" + ("".join(" " + shlex.quote(a) for a in (argv or sys.argv[1:]))),
            "date": datetime.date.today().isoformat(), "sodt_version": version, "git": git_describe(),
            "subset": " (subset: %s)" % ("--quick" if args.quick else "--only") if subset else "",
            "cores": os.cpu_count() or 0, "wall": wall, "load": load_start,
            "min_time": args.min_time, "max_repeats": args.max_repeats,
            "load_end": os.getloadavg()[0]}
    with open(os.path.join(work, "results.json"), "w", encoding="utf-8") as f:
        json.dump({"meta": meta, "configs": configs, "results": results}, f, indent=1)
    md = markdown(results, configs, meta, args.targets)
    with open(out_md, "w", encoding="utf-8") as f:
        f.write(md + "\n")
    # the summary on the terminal
    start = md.index("## Issue 44")
    end = md.index("## Per mesh")
    print()
    print(md[start:end].rstrip())
    print("\nrun.py: wrote %s and %s (%.0f s)" % (out_md, os.path.join(work, "results.json"), wall))
    failed = sum(x["exit"] != 0 for r in results for x in r["runs"].values())
    if failed:
        print("run.py: error: %d runs failed (listed in %s)" % (failed, out_md), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
