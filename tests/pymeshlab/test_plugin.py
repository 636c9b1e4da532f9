# SPDX-License-Identifier: GPL-3.0-or-later
"""The S-ODT plugin inside PyMeshLab 2025.7: names, parameters, report,
classes, errors, repeated runs, selections, flips and threads."""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import CLASSIFY, PLUGIN, PYMESHLAB_PATH, SMOOTH, bundled, corner_angles_deg, recover_after_exception



def table_parameters():
    """The generated table of docs/parameters.md, which ParamTableDocs checks
    against sodt::paramTable(): {python key: (type, default as PyMeshLab
    returns it, (low, high) or None)}."""
    path = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "parameters.md")
    text = open(path, encoding="utf-8").read()
    body = text.split("rewrites it. -->\n", 1)[1].split("<!-- End of the generated table. -->", 1)[0]
    params = {}
    for row in body.splitlines()[2:]:
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]]
        key, kind, default, bounds, meaning = cells[1].strip("`"), cells[3], cells[4], cells[5], cells[6]
        shown = default.split("`")[1]
        if kind == "choice":
            value = int(re.search(r"`%s` \((\d+)\)" % re.escape(shown), meaning).group(1))
        elif kind == "on/off":
            value = shown == "on"
        else:
            value = float(shown)
        m = re.match(r"[\[(]([-0-9.e+]+), ([-0-9.e+]+)[\])]", bounds)
        params[key] = (kind, value, (float(m.group(1)), float(m.group(2))) if m else None)
    return params


TABLE = table_parameters()
# Python keyword arguments of the smoothing filter and their defaults: the
# table's, and the filter's own output_class.
SMOOTH_DEFAULTS = dict({k: v[1] for k, v in TABLE.items()}, output_class=True)
COUNTERS = ["moved", "backtracked", "fallback_moves", "rejected", "failed_solves", "unchanged"]
REPORT_INTS = ["vertices", "faces", "smooth", "crease", "corner", "fixed", "fixed_boundary",
               "fixed_nonmanifold", "active_vertices", "sweeps", "returned_sweep", "threads",
               "skipped_visits", "flips", "faces_changed", "reoriented_faces"] + COUNTERS
REPORT_FLOATS = ["min_angle_before", "min_angle_after", "max_angle_before", "max_angle_after",
                 "frac_below_30_before", "frac_below_30_after", "seconds"]
PALETTE = {0: (200, 200, 200), 1: (30, 90, 230), 2: (230, 30, 30), 3: (240, 200, 0)}


def test_filters_are_listed_with_python_names_and_snake_case_parameters(pm, meshset):
    assert SMOOTH in pm.filter_list()
    assert CLASSIFY in pm.filter_list()
    ms = meshset(bundled("blobs_mc.ply"))
    values = ms.filter_parameter_values(SMOOTH)
    assert set(values) == set(SMOOTH_DEFAULTS)
    for key, default in SMOOTH_DEFAULTS.items():
        assert values[key] == pytest.approx(default, rel=1e-6), key
    assert ms.filter_parameter_values(CLASSIFY) == {"epsilon": 2.0, "eta": 2.0, "select_features": False}


def test_smoothing_returns_the_quality_report(meshset):
    ms = meshset(bundled("blobs_mc.ply"))
    r = ms.apply_filter(SMOOTH, iterations=20)
    for k in REPORT_INTS:
        assert isinstance(r[k], int), k
    for k in REPORT_FLOATS + ["volume_before", "volume_after", "volume_rel_change"]:
        assert isinstance(r[k], float), k
    assert r["closed"] is True and r["cancelled"] is False and r["stopped_early"] is False
    m = ms.current_mesh()
    assert (r["vertices"], r["faces"]) == (m.vertex_number(), m.face_number())
    # The report describes the mesh PyMeshLab now holds.
    angles = corner_angles_deg(m.vertex_matrix(), m.face_matrix())
    assert r["min_angle_after"] == pytest.approx(angles.min(), abs=1e-9)
    assert r["max_angle_after"] == pytest.approx(angles.max(), abs=1e-9)
    assert r["frac_below_30_after"] == pytest.approx(np.mean(angles < 30.0), abs=1e-12)
    assert r["min_angle_before"] < 1.0 < 20.0 < r["min_angle_after"]
    assert r["frac_below_30_after"] < r["frac_below_30_before"]
    # Tangent-plane moves keep the enclosed volume (Appendix D of the paper).
    assert abs(r["volume_rel_change"]) < 1e-12
    assert r["volume_before"] == pytest.approx(ms.get_geometric_measures()["mesh_volume"], rel=1e-12)
    # Basic: every vertex is smooth; every visit of every sweep has one outcome.
    assert r["smooth"] == r["vertices"] == r["active_vertices"]
    assert r["crease"] == r["corner"] == r["fixed"] == 0
    assert r["sweeps"] == r["returned_sweep"] == 20
    assert sum(r[k] for k in COUNTERS) == r["sweeps"] * r["active_vertices"]
    assert r["flips"] == 0 and r["faces_changed"] == 0
    assert r["threads"] >= 1 and r["seconds"] > 0


def test_feature_classes_are_written_as_quality_and_colour(meshset):
    ms = meshset(bundled("cube_jitter.ply"))
    before = ms.current_mesh().vertex_matrix().copy()
    r = ms.apply_filter(SMOOTH, algorithm="feature")
    m = ms.current_mesh()
    q = m.vertex_scalar_array()
    assert set(np.unique(q)) <= {0.0, 1.0, 2.0}
    assert (np.count_nonzero(q == 0), np.count_nonzero(q == 1), np.count_nonzero(q == 2)) == \
        (r["smooth"], r["crease"], r["corner"])
    # The 8 cube corners are the corner vertices, and they stay where they were.
    lo, hi = before.min(axis=0), before.max(axis=0)
    at_corner = np.all(np.isclose(before, lo) | np.isclose(before, hi), axis=1)
    assert np.count_nonzero(at_corner) == 8
    assert np.array_equal(np.flatnonzero(q == 2), np.flatnonzero(at_corner))
    assert np.array_equal(m.vertex_matrix()[at_corner], before[at_corner])
    rgb = np.rint(m.vertex_color_matrix()[:, :3] * 255).astype(int)
    for code, colour in PALETTE.items():
        assert np.all(rgb[q == code] == colour), code
    assert r["min_angle_after"] > r["min_angle_before"] + 10


def test_output_class_off_leaves_quality_and_colour_alone(meshset):
    ms = meshset(bundled("cube_jitter.ply"))
    ms.apply_filter(SMOOTH, algorithm="feature", iterations=2, output_class=False)
    m = ms.current_mesh()
    assert not m.has_vertex_scalar()


@pytest.mark.parametrize("key,value", [
    ("iterations", -5), ("epsilon", -1.0), ("eta", 0.0), ("flip_max_dihedral", 91.0),
    ("tolerance", -1.0), ("threads", 1025), ("max_deviation", 200.0), ("max_backtracks", 61),
    ("max_normal_step", 11.0),
])
def test_bad_parameters_raise_the_plugins_message_and_leave_the_mesh_unchanged(pm, meshset, key, value):
    ms = meshset(bundled("cube_jitter.ply"))
    ms.apply_filter(CLASSIFY, select_features=True)  # quality, colour and selection to keep
    m = ms.current_mesh()
    state = [m.vertex_matrix().copy(), m.face_matrix().copy(), m.vertex_scalar_array().copy(),
             m.vertex_color_matrix().copy(), m.vertex_selection_array().copy()]
    with pytest.raises(pm.PyMeshLabException) as exc:
        ms.apply_filter(SMOOTH, **{key: value})
    assert "S-ODT Smoothing failed: " in str(exc.value)
    assert key in str(exc.value)
    m = ms.current_mesh()
    after = [m.vertex_matrix(), m.face_matrix(), m.vertex_scalar_array(), m.vertex_color_matrix(),
             m.vertex_selection_array()]
    for a, b in zip(state, after):
        assert np.array_equal(a, b)
    recover_after_exception(ms)
    assert np.array_equal(ms.current_mesh().vertex_matrix(), state[0])


def test_every_table_range_is_enforced_naming_the_key(pm, meshset):
    ms = meshset(bundled("cube_jitter.ply"))
    for key, (kind, _, bounds) in TABLE.items():
        if bounds is None:
            continue
        for value in (bounds[0] - 1, bounds[1] * 2 + 1):
            value = int(value) if kind == "integer" else float(value)
            with pytest.raises(pm.PyMeshLabException) as exc:
                ms.apply_filter(SMOOTH, **{key: value})
            assert key + " must be" in str(exc.value), (key, value, str(exc.value))
            recover_after_exception(ms)


def test_a_mesh_without_faces_is_refused(pm):
    ms = pm.MeshSet()
    ms.add_mesh(pm.Mesh(vertex_matrix=np.random.default_rng(1).random((10, 3))))
    with pytest.raises(pm.PyMeshLabException) as exc:
        ms.apply_filter(SMOOTH)
    # PyMeshLab checks the filter's precondition (faces) before calling it.
    assert "does not have" in str(exc.value) and "faces" in str(exc.value).lower()
    assert ms.current_mesh().vertex_number() == 10


def test_runs_twice_in_a_row(meshset):
    ms = meshset(bundled("blobs_mc.ply"))
    first = ms.apply_filter(SMOOTH, iterations=5)
    after_first = ms.current_mesh().vertex_matrix().copy()
    second = ms.apply_filter(SMOOTH, iterations=5)
    assert second["min_angle_before"] == pytest.approx(first["min_angle_after"], abs=1e-12)
    # The quality guard never lowers the minimum angle, and the second run goes on moving.
    assert second["min_angle_after"] >= second["min_angle_before"]
    assert second["moved"] + second["backtracked"] + second["fallback_moves"] > 0
    assert not np.array_equal(ms.current_mesh().vertex_matrix(), after_first)


def _mesh_with_left_half_selected(pm, path):
    """The mesh with the vertices left of the median x selected (through
    PyMeshLab's own selection filter on the x coordinate as quality)."""
    ms = pm.MeshSet()
    ms.load_new_mesh(path)
    m = ms.current_mesh()
    v, f = m.vertex_matrix(), m.face_matrix()
    x = v[:, 0]
    ms.clear()
    ms.add_mesh(pm.Mesh(vertex_matrix=v, face_matrix=f, v_scalar_array=x))
    ms.compute_selection_by_scalar_per_vertex(minq=float(x.min()) - 1.0, maxq=float(np.median(x)))
    sel = ms.current_mesh().vertex_selection_array().copy()
    assert 0 < np.count_nonzero(sel) < len(sel)
    return ms, sel


@pytest.mark.parametrize("explicit", [True, False], ids=["selected_only", "default_with_selection"])
def test_selection_limits_the_moves(pm, explicit):
    ms, sel = _mesh_with_left_half_selected(pm, bundled("blobs_mc.ply"))
    # With a selection in the mesh, selected_only defaults to on (as in the GUI).
    assert ms.filter_parameter_values(SMOOTH)["selected_only"] is True
    before = ms.current_mesh().vertex_matrix().copy()
    args = {"selected_only": True} if explicit else {}
    ms.apply_filter(SMOOTH, iterations=10, **args)
    after = ms.current_mesh().vertex_matrix()
    moved = np.any(after != before, axis=1)
    assert not np.any(moved[~sel])
    assert np.count_nonzero(moved[sel]) > 0.5 * np.count_nonzero(sel)


def test_flips_change_the_connectivity_only(meshset):
    ms = meshset(bundled("blobs_mc.ply"))
    faces_before = ms.current_mesh().face_matrix().copy()
    r = ms.apply_filter(SMOOTH, flips=True)
    m = ms.current_mesh()
    assert (m.vertex_number(), m.face_number()) == (4794, len(faces_before))
    assert r["flips"] > 0 and r["faces_changed"] > 0
    changed = np.any(np.sort(m.face_matrix(), axis=1) != np.sort(faces_before, axis=1), axis=1)
    assert np.count_nonzero(changed) == r["faces_changed"]
    topo = ms.get_topological_measures()
    assert topo["is_mesh_two_manifold"] and topo["boundary_edges"] == 0
    assert r["min_angle_after"] > 30.0


def border_edges(faces):
    """The edges of only one face, as sorted vertex index pairs."""
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    u, n = np.unique(e, axis=0, return_counts=True)
    return u[n == 1]


def test_repair_changes_the_vertices_and_reaches_its_angle(meshset):
    ms = meshset(bundled("plane_grid_open.ply"))
    n_before = ms.current_mesh().vertex_number()
    lo, hi = ms.current_mesh().vertex_matrix().min(axis=0), ms.current_mesh().vertex_matrix().max(axis=0)
    plain = ms.apply_filter(SMOOTH, flips=True)
    ms = meshset(bundled("plane_grid_open.ply"))
    r = ms.apply_filter(SMOOTH, flips=True, repair=True, repair_angle=30.0)
    m = ms.current_mesh()
    assert plain["min_angle_after"] < 30.0 <= r["min_angle_after"]
    assert r["vertices_added"] > 0 and r["below_repair_angle"] == 0
    assert m.vertex_number() == n_before + r["vertices_added"] - r["vertices_removed"]
    assert min(corner_angles_deg(m.vertex_matrix(), m.face_matrix())) >= 30.0 - 1e-6
    assert ms.get_topological_measures()["is_mesh_two_manifold"]
    # The border stays the unit square's (a border vertex may go along it,
    # none moves off it): every border edge lies on one of its sides, and
    # they add up to its perimeter.
    v, edges = m.vertex_matrix(), border_edges(m.face_matrix())
    ends = v[edges]  # (edges, 2, 3)
    on_side = [np.all(np.isclose(ends[:, :, k], x), axis=1) for k in (0, 1) for x in (lo[k], hi[k])]
    assert np.all(np.any(on_side, axis=0))
    perimeter = np.linalg.norm(ends[:, 0] - ends[:, 1], axis=1).sum()
    assert perimeter == pytest.approx(2 * ((hi - lo)[0] + (hi - lo)[1]), rel=1e-12)


def test_the_result_does_not_depend_on_the_thread_count(meshset):
    results = []
    for threads in (1, 2):
        ms = meshset(bundled("blobs_mc.ply"))
        r = ms.apply_filter(SMOOTH, threads=threads, flips=True)
        assert r["threads"] == threads
        results.append((ms.current_mesh().vertex_matrix(), ms.current_mesh().face_matrix()))
    assert np.array_equal(results[0][0], results[1][0])
    assert np.array_equal(results[0][1], results[1][1])


def test_classify_writes_classes_and_selects_the_features(meshset):
    ms = meshset(bundled("cube_jitter.ply"))
    before = ms.current_mesh().vertex_matrix().copy()
    r = ms.apply_filter(CLASSIFY, select_features=True)
    m = ms.current_mesh()
    assert np.array_equal(m.vertex_matrix(), before)
    q = m.vertex_scalar_array()
    assert r["corner"] == 8 and r["crease"] > 0 and r["fixed"] == 0
    assert r["smooth"] + r["crease"] + r["corner"] == m.vertex_number()
    assert np.array_equal(m.vertex_selection_array(), q >= 1)
    assert r["selected"] == r["crease"] + r["corner"]


def test_installed_in_pymeshlabs_plugin_folder_it_is_a_meshset_method(tmp_path):
    """As a user installs it: the plugin copied into pymeshlab/lib/plugins is
    loaded on import and bound as MeshSet.apply_coord_sodt_smoothing. The
    pymeshlab folder is mirrored with symlinks, so the build stays untouched."""
    src = os.path.join(PYMESHLAB_PATH, "pymeshlab")
    dst = tmp_path / "pymeshlab"
    for root, dirs, files in os.walk(src):
        rel = os.path.relpath(root, src)
        (dst / rel).mkdir(parents=True, exist_ok=True)
        for f in files:
            os.symlink(os.path.join(root, f), dst / rel / f)
    os.symlink(os.path.abspath(PLUGIN), dst / "lib" / "plugins" / "libfilter_sodt.so")
    code = ("import json, pymeshlab; ms = pymeshlab.MeshSet(); ms.load_new_mesh(%r); "
            "r = ms.apply_coord_sodt_smoothing(iterations=5, algorithm='basic'); "
            "print(json.dumps({'file': pymeshlab.__file__, 'min': r['min_angle_after']}))"
            % bundled("blobs_mc.ply"))
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    result = json.loads(out.stdout.strip().splitlines()[-1])
    assert result["file"].startswith(str(tmp_path))
    assert result["min"] > 10.0


def test_the_example_script_smooths_and_saves_the_classes(pm, tmp_path):
    """filter_sodt/examples/sodt_pymeshlab.py, as the README runs it."""
    example = os.path.join(os.path.dirname(__file__), "..", "..", "filter_sodt", "examples", "sodt_pymeshlab.py")
    out = tmp_path / "cube_feature.ply"
    env = dict(os.environ, PYTHONPATH=PYMESHLAB_PATH)
    run = subprocess.run([sys.executable, example, bundled("cube_jitter.ply"), str(out), "--plugin", PLUGIN,
                          "--algorithm", "feature", "--iterations", "10"],
                         env=env, capture_output=True, text=True, check=True)
    assert "min angle 5.82 -> " in run.stdout
    assert "vertex classes: " in run.stdout and " 8 corner" in run.stdout
    ms = pm.MeshSet()
    ms.load_new_mesh(str(out))
    q = ms.current_mesh().vertex_scalar_array()
    assert np.count_nonzero(q == 2) == 8 and np.count_nonzero(q == 1) > 0
    # Without --plugin, and with none installed, it says what to do.
    bad = subprocess.run([sys.executable, example, bundled("cube_jitter.ply"), str(tmp_path / "x.ply")],
                         env=env, capture_output=True, text=True)
    assert bad.returncode != 0 and "pass --plugin" in bad.stderr
    assert not (tmp_path / "x.ply").exists()
