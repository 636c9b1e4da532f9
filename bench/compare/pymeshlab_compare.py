#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""S-ODT through PyMeshLab against PyMeshLab's own smoothers and remeshers.

Every method starts from the same file in one PyMeshLab MeshSet, and every
output is saved (double-precision PLY) and measured alike: the project's
metrics (`sodt stats OUT --reference IN`: angles, symmetric sampled Hausdorff
distance to the input, inverted faces) and PyMeshLab's own measures where
they fit (get_topological_measures: two-manifoldness, holes;
get_geometric_measures: enclosed volume).

As a module it gives the runs and measures to tests/pymeshlab; as a command
it writes the PyMeshLab section of docs/RESULTS.md (the command is quoted
there), after scripts/run-tests.sh or scripts/demo.sh have built PyMeshLab
and the plugin:

  bench/compare/pymeshlab_compare.py --results docs/RESULTS.md MESH[:ALGORITHM] ...

--pymeshlab defaults to the folder scripts/build-meshlab-2025.sh fills,
--plugin and --sodt to the build in build/.
"""

import argparse
import atexit
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

# Marks the part of RESULTS.md this command owns; sodt_compare keeps it.
BEGIN_MARK = "<!-- pymeshlab-comparison:begin -->"
END_MARK = "<!-- pymeshlab-comparison:end -->"

ITERATIONS = 20
SODT_FILTER = "apply_coord_sodt_smoothing"


def pristine_pymeshlab(parent):
    """A temporary folder whose pymeshlab/ mirrors parent/pymeshlab with
    symlinks, leaving out a libfilter_sodt.so installed in its plugin folder,
    so that the plugin loaded is the one asked for (removed at exit)."""
    src = os.path.join(parent, "pymeshlab")
    if not os.path.isfile(os.path.join(src, "__init__.py")):
        raise RuntimeError(f"no pymeshlab package in '{parent}'")
    top = tempfile.mkdtemp(prefix="sodt-pymeshlab-")
    atexit.register(shutil.rmtree, top, True)
    for root, _dirs, files in os.walk(src):
        rel = os.path.relpath(root, src)
        os.makedirs(os.path.join(top, "pymeshlab", rel), exist_ok=True)
        for f in files:
            if f == "libfilter_sodt.so" and os.path.basename(root) == "plugins":
                continue
            os.symlink(os.path.join(root, f), os.path.join(top, "pymeshlab", rel, f))
    return top


@dataclass
class Method:
    key: str              # short id, used in file names
    label: str            # table row
    filter: str           # PyMeshLab filter name
    params: dict          # keyword arguments (besides the defaults)
    moves_vertices_only: bool  # same connectivity as the input
    sodt: bool = False
    # Parameters that depend on the mesh (e.g. a target length): mesh -> dict.
    mesh_params: object = None


def builtin_methods(iterations=ITERATIONS):
    """PyMeshLab 2025.7's smoothers (filter_unsharp), planar flipping
    (filter_trioptimize) and isotropic remeshing (filter_meshing): their
    defaults, with the step count matched to `iterations` where the filter
    has one."""
    return [
        Method("laplacian", "Laplacian", "apply_coord_laplacian_smoothing",
               {"stepsmoothnum": iterations}, True),
        Method("hc_laplacian", "HC Laplacian (one pass, no step count)",
               "apply_coord_hc_laplacian_smoothing", {}, True),
        Method("taubin", "Taubin", "apply_coord_taubin_smoothing",
               {"stepsmoothnum": iterations}, True),
        Method("two_steps", "TwoStep", "apply_coord_two_steps_smoothing",
               {"stepsmoothnum": iterations}, True),
        Method("surface_preserving", "Laplacian, surface preserving",
               "apply_coord_laplacian_smoothing_surface_preserving",
               {"iterations": iterations}, True),
        Method("planar_flip", "Planar edge flips", "meshing_edge_flip_by_planar_optimization",
               {}, False),
        Method("isotropic", "Isotropic remeshing (default target)",
               "meshing_isotropic_explicit_remeshing", {}, False),
        Method("isotropic_mean_edge", "Isotropic remeshing (target = mean edge)",
               "meshing_isotropic_explicit_remeshing", {}, False,
               mesh_params=lambda pm, ms: {
                   "targetlen": pm.PureValue(ms.get_geometric_measures()["avg_edge_length"])}),
        # Each local operation kept within S-ODT's deviation bound.
        Method("isotropic_mean_edge_dist", "Isotropic remeshing (target = mean edge, surface distance 0.1%)",
               "meshing_isotropic_explicit_remeshing", {"checksurfdist": True}, False,
               mesh_params=lambda pm, ms: {
                   "targetlen": pm.PureValue(ms.get_geometric_measures()["avg_edge_length"]),
                   "maxsurfdist": pm.PureValue(0.001 * ms.current_mesh().bounding_box().diagonal())}),
    ]


def sodt_methods(algorithm, iterations=ITERATIONS):
    """S-ODT through the plugin: the algorithm with its defaults, with flips,
    and with flips and the local repair (which adds and removes vertices)."""
    base = {"algorithm": algorithm, "iterations": iterations}
    return [
        Method("sodt", f"**S-ODT {algorithm}** (plugin)", SODT_FILTER, dict(base), True, sodt=True),
        Method("sodt_flips", f"**S-ODT {algorithm} + flips** (plugin)", SODT_FILTER,
               dict(base, flips=True), False, sodt=True),
        Method("sodt_flips_repair", f"**S-ODT {algorithm} + flips + repair** (plugin)", SODT_FILTER,
               dict(base, flips=True, repair=True), False, sodt=True),
    ]


@dataclass
class Row:
    method: Method
    min_angle: float = float("nan")
    max_angle: float = float("nan")
    frac_below_30: float = float("nan")
    hausdorff_rel: float = float("nan")
    inverted_faces: object = None      # None when the connectivity changed
    vertices: int = 0
    faces: int = 0
    two_manifold: bool = False
    holes: int = 0
    volume_change: object = None       # None for open meshes
    seconds: float = 0.0
    report: dict = field(default_factory=dict)  # the filter's returned dict
    output: str = ""
    error: str = ""


def sodt_stats(sodt_cli, path, reference=None):
    """`sodt stats PATH [--reference REF]` as a dict (the project's metrics)."""
    cmd = [sodt_cli, "stats", path]
    if reference:
        cmd += ["--reference", reference]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def run_method(pm, sodt_cli, mesh, method, work):
    """Runs one method on a fresh copy of `mesh`, saves and measures it."""
    row = Row(method)
    ms = pm.MeshSet()
    ms.load_new_mesh(mesh)
    closed = ms.get_topological_measures()["boundary_edges"] == 0
    vol_in = ms.get_geometric_measures().get("mesh_volume") if closed else None
    params = dict(method.params)
    if method.mesh_params:
        params.update(method.mesh_params(pm, ms))
    name = os.path.splitext(os.path.basename(mesh))[0]
    row.output = os.path.join(work, f"{name}_{method.key}.ply")
    start = time.perf_counter()
    try:
        row.report = ms.apply_filter(method.filter, **params) or {}
    except pm.PyMeshLabException as e:
        row.error = str(e).strip().splitlines()[-1]
        return row
    row.seconds = time.perf_counter() - start
    topo = ms.get_topological_measures()
    row.two_manifold = bool(topo["is_mesh_two_manifold"])
    row.holes = int(topo["number_holes"])
    if vol_in and topo["boundary_edges"] == 0:
        row.volume_change = ms.get_geometric_measures()["mesh_volume"] / vol_in - 1.0
    ms.save_current_mesh(row.output, binary=True, save_vertex_quality=False,
                         save_vertex_color=False, save_face_color=False)
    st = sodt_stats(sodt_cli, row.output, mesh)
    row.min_angle = st["min_angle"]
    row.max_angle = st["max_angle"]
    row.frac_below_30 = st["frac_below_30"]
    row.hausdorff_rel = st["hausdorff_rel"]
    row.vertices = st["vertices"]
    row.faces = st["faces"]
    if method.moves_vertices_only and row.report.get("faces_changed", 0) == 0:
        row.inverted_faces = st["inverted_faces"]
    return row


def compare_mesh(pm, sodt_cli, mesh, algorithm, work, iterations=ITERATIONS):
    """The input's measures and a row per S-ODT and built-in method for one
    mesh; `pm` must have the plugin loaded."""
    inp = sodt_stats(sodt_cli, mesh)
    rows = [run_method(pm, sodt_cli, mesh, m, work)
            for m in sodt_methods(algorithm, iterations) + builtin_methods(iterations)]
    return inp, rows


def beaten_by(rows):
    """The vertex-moving built-ins that S-ODT does not beat: a larger or equal
    min angle with a Hausdorff distance to the input no larger than S-ODT's."""
    sodt = next(r for r in rows if r.method.key == "sodt")
    return [r for r in rows
            if not r.method.sodt and r.method.moves_vertices_only and not r.error
            and r.hausdorff_rel <= sodt.hausdorff_rel and r.min_angle >= sodt.min_angle]


def repair_verdict(inp, rows):
    """The local repair against isotropic remeshing at the input's mean edge
    length: (beats, why not, repair's vertex changes, remesher's). The
    repair's changes are exact (vertices added + removed, from the filter's
    report); the remesher's, |V_out - V_in|, are a lower bound, since it
    resamples the whole surface. None when either row is missing or failed."""
    by_key = {r.method.key: r for r in rows if not r.error}
    rep, iso = by_key.get("sodt_flips_repair"), by_key.get("isotropic_mean_edge")
    if rep is None or iso is None:
        return None
    rep_changed = rep.report["vertices_added"] + rep.report["vertices_removed"]
    iso_changed = abs(iso.vertices - inp["vertices"])
    why = []
    if not rep.min_angle > iso.min_angle:
        why.append("min angle not larger")
    if not rep.hausdorff_rel <= iso.hausdorff_rel + 1e-6:
        why.append("larger Hausdorff")
    if not rep_changed < iso_changed:
        why.append("not fewer vertices changed")
    return not why, why, rep_changed, iso_changed


def processor_name():
    """The processor's model name (timings from other processors are not comparable)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _fmt(x, spec, none="–"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return none
    return format(x, spec)


def markdown_section(results, command):
    """The RESULTS.md section: set-up and one table per mesh."""
    out = [BEGIN_MARK, "", "## PyMeshLab 2025.7: S-ODT as a plugin against PyMeshLab's filters", "",
           "<!-- Generated by bench/compare/pymeshlab_compare.py. Do not edit: rerun the command below. -->",
           "", "Generated by one command from the repository root, after `scripts/run-tests.sh` "
           "(or `scripts/demo.sh`) has built PyMeshLab 2025.7, the plugin and `sodt` "
           "(`sodt_compare` above keeps this section when it rewrites the file):", "", "```sh", command,
           "```", "",
           "* **Same input, same session.** Each method runs on a fresh copy of the mesh, loaded by "
           "PyMeshLab 2025.7 (double precision) with the S-ODT plugin loaded by `pymeshlab.load_plugin`. "
           f"S-ODT runs `{SODT_FILTER}` with its defaults (guard quality, Laplacian fallback, deviation "
           f"bound 0.1 % of the diagonal, all cores) and `iterations` = {ITERATIONS}; \"+ flips\" adds "
           "`flips=True`, \"+ flips + repair\" also `repair=True` (local repair after the sweeps where a "
           "triangle's smallest angle is below `repair_angle`, default 30°; its V / F cell adds the vertices "
           "added and removed, from the filter's report). PyMeshLab's filters run with their defaults, the step count set to "
           f"{ITERATIONS} where they have one (`stepsmoothnum`, `iterations` of the surface-preserving "
           "Laplacian); isotropic remeshing also runs with its target edge length set to the input's "
           "mean edge length.",
           "* **Measures.** Every output is saved as a double-precision PLY and measured by "
           "`sodt stats OUT --reference IN` (the project's metrics): corner angles, the share below "
           "30°, the symmetric sampled Hausdorff distance to the input relative to its bounding-box "
           "diagonal, and faces turned by more than 90° against the same face of the input (only when "
           "the connectivity is unchanged, \"–\" otherwise). PyMeshLab's own measures: "
           "`get_topological_measures` (two-manifold, holes) and `get_geometric_measures` (enclosed "
           "volume, for the change of closed meshes). Time: the `apply_filter` call alone, one run "
           f"({processor_name()}, {os.cpu_count()} hardware threads).",
           "* **Rule the tests check** (`tests/pymeshlab/test_comparison.py`): S-ODT inverts no face, and "
           "its min angle is larger than that of every vertex-moving built-in whose Hausdorff distance "
           "to the input is no larger. Flips and remeshing change the connectivity and are listed for "
           "reference.",
           "* **Local repair against remeshing** (the line under each table): \"beats\" means a larger min "
           "angle than isotropic remeshing at the mean edge length, a Hausdorff distance no larger, and "
           "fewer vertices changed. The repair's count is exact (vertices added + removed); the remesher's, "
           "|V_out − V_in|, is a lower bound, since it resamples the whole surface.", ""]
    for mesh, algorithm, inp, rows in results:
        name = os.path.basename(mesh)
        out += [f"### `{name}` ({inp['vertices']} vertices, {inp['faces']} faces; S-ODT `{algorithm}`)", "",
                "| method | min angle | max angle | < 30° | Hausdorff to input | volume change | "
                "inverted | V / F | 2-manifold, holes | time |",
                "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
                f"| input | {inp['min_angle']:.2f}° | {inp['max_angle']:.2f}° | "
                f"{100 * inp['frac_below_30']:.2f}% | | | | {inp['vertices']} / {inp['faces']} | | |"]
        for r in rows:
            if r.error:
                out.append(f"| {r.method.label} | failed: {r.error} | | | | | | | | |")
                continue
            vf = f"{r.vertices} / {r.faces}"
            if r.method.params.get("repair"):
                vf += f" (+{r.report['vertices_added']} / −{r.report['vertices_removed']})"
            out.append(
                f"| {r.method.label} | {r.min_angle:.2f}° | {r.max_angle:.2f}° | "
                f"{100 * r.frac_below_30:.2f}% | {100 * r.hausdorff_rel:.3f}% | "
                f"{_fmt(r.volume_change, '+.1e')} | {_fmt(r.inverted_faces, 'd')} | "
                f"{vf} | {'yes' if r.two_manifold else 'no'}, {r.holes} | "
                f"{r.seconds:.2f} s |")
        lost = beaten_by(rows)
        sodt = next(r for r in rows if r.method.key == "sodt")
        verdict = ("S-ODT's min angle is the largest among the vertex-moving methods that stay as close "
                   "to the input" if not lost else
                   f"S-ODT ({sodt.min_angle:.2f}° at {100 * sodt.hausdorff_rel:.3f}%) does not beat, at no "
                   "larger Hausdorff distance: " +
                   ", ".join(f"{r.method.label} ({r.min_angle:.2f}° at {100 * r.hausdorff_rel:.3f}%)"
                             for r in lost))
        out += ["", verdict + "."]
        rv = repair_verdict(inp, rows)
        if rv is not None:
            beats, why, rep_changed, iso_changed = rv
            out += ["", "Local repair against isotropic remeshing (target = mean edge): "
                    + ("beats it" if beats else "does not beat it (" + ", ".join(why) + ")")
                    + f"; vertices changed: {rep_changed} by the repair, at least {iso_changed} by "
                    "the remesher."]
        out.append("")
    out.append(END_MARK)
    return "\n".join(out) + "\n"


def replace_section(results_md, section, begin=BEGIN_MARK, end=END_MARK):
    """RESULTS.md with the section between the markers begin and end (by
    default the PyMeshLab one) replaced, or appended when absent. Atomic (a
    temporary file renamed)."""
    text = open(results_md, encoding="utf-8").read() if os.path.exists(results_md) else ""
    b, e = text.find(begin), text.find(end)
    if b >= 0 and e > b:
        text = text[:b] + section + text[e + len(end):].lstrip("\n")
    else:
        text = text.rstrip("\n") + ("\n\n" if text else "") + section
    tmp = results_md + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, results_md)


def main(argv=None):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pymeshlab", help="folder holding PyMeshLab's pymeshlab/ (default: the one "
                    "scripts/build-meshlab-2025.sh builds)")
    ap.add_argument("--plugin", default=os.path.join(root, "build/meshlab-2025.07-pymeshlab/filter_sodt/libfilter_sodt.so"),
                    help="libfilter_sodt.so built for PyMeshLab (double); default: the one in build/")
    ap.add_argument("--sodt", default=os.path.join(root, "build/cli/sodt"),
                    help="the sodt command that measures the outputs; default: the one in build/")
    ap.add_argument("--results", help="RESULTS.md whose PyMeshLab section is rewritten "
                    "(default: print the section)")
    ap.add_argument("--work", help="folder for the output meshes (default: a temporary one)")
    ap.add_argument("meshes", nargs="+", help="MESH or MESH:ALGORITHM (basic, feature, denoise)")
    a = ap.parse_args(argv)
    if not a.pymeshlab:
        a.pymeshlab = os.path.join(subprocess.run(
            ["bash", os.path.join(root, "scripts/build-meshlab-2025.sh"), "--print-dir"],
            check=True, capture_output=True, text=True).stdout.strip(), "pymeshlab")
    for what, path in (("plugin", a.plugin), ("sodt", a.sodt)):
        if not os.path.isfile(path):
            ap.error(f"--{what} {path} does not exist (build first: scripts/run-tests.sh or scripts/demo.sh)")
    sys.path.insert(0, pristine_pymeshlab(a.pymeshlab))
    import pymeshlab as pm
    pm.load_plugin(a.plugin)
    work = a.work or tempfile.mkdtemp(prefix="sodt-pymeshlab-work-")
    os.makedirs(work, exist_ok=True)
    results = []
    for spec in a.meshes:
        mesh, _, algorithm = spec.partition(":")
        algorithm = algorithm or "basic"
        print(f"[pymeshlab_compare] {mesh} ({algorithm})", file=sys.stderr)
        inp, rows = compare_mesh(pm, a.sodt, mesh, algorithm, work)
        results.append((mesh, algorithm, inp, rows))
    command = " ".join(["bench/compare/pymeshlab_compare.py"] + (argv if argv is not None else sys.argv[1:]))
    section = markdown_section(results, command)
    if a.results:
        replace_section(a.results, section)
        print(f"[pymeshlab_compare] wrote the PyMeshLab section of {a.results}; meshes in {work}",
              file=sys.stderr)
    else:
        sys.stdout.write(section)
    return 0


if __name__ == "__main__":
    sys.exit(main())
