# SPDX-License-Identifier: GPL-3.0-or-later
"""The plugin in PyMeshLab and the sodt command give the same mesh.

Tolerance: none. Both run the same double-precision core, compiled with the
same flags (no fused multiply-add, see CMakeLists.txt), on the same vertex
order and the same float32 coordinates widened to double, and the plugin
reads its float parameters back as the decimals the user typed
(sodt_rich_params.cpp), so the CLI's and the plugin's runs perform the same
operations in the same order: coordinates and faces must be equal bit for
bit, and the reported angles too. (MeshLab's GUI works in float, so this
holds for PyMeshLab only.)"""
import json
import subprocess

import numpy as np
import pytest

from conftest import SMOOTH, SODT_CLI, bundled, shared

CASES = [
    # (mesh, plugin keyword arguments, the same as CLI options)
    ("blobs_mc.ply", {}, []),
    ("blobs_mc.ply", {"flips": True, "keep_best": True}, ["--flips", "--keep-best"]),
    ("cube_jitter.ply", {"algorithm": "feature", "max_deviation": 0.05, "epsilon": 2.5},
     ["--algorithm", "feature", "--max-deviation", "0.05", "--epsilon", "2.5"]),
    ("cube_noisy.ply", {"algorithm": "denoise", "max_normal_step": 0.07, "iterations": 7},
     ["--algorithm", "denoise", "--max-normal-step", "0.07", "--iterations", "7"]),
    ("cube_noisy.ply", {"algorithm": "filtered", "iterations": 10}, ["--algorithm", "filtered", "--iterations", "10"]),
    ("torus.off", {"algorithm": "filtered", "noise_level": 0.2}, ["--algorithm", "filtered", "--noise-level", "0.2"]),
    ("plane_grid_open.ply", {"guard": "fold", "tolerance": 0.01}, ["--guard", "fold", "--tolerance", "0.01"]),
    ("shared:mol_a.ply", {}, []),
]


@pytest.mark.parametrize("mesh,kwargs,options", CASES,
                         ids=[f"{c[0]}-{'-'.join(c[2]) or 'defaults'}" for c in CASES])
def test_plugin_in_pymeshlab_equals_the_cli(pm, meshset, tmp_path, mesh, kwargs, options):
    path = shared(mesh.split(":", 1)[1]) if mesh.startswith("shared:") else bundled(mesh)
    ms = meshset(path)
    report = ms.apply_filter(SMOOTH, **kwargs)
    out, rep = tmp_path / "cli.ply", tmp_path / "cli.json"
    subprocess.run([SODT_CLI, "smooth", path, str(out), "--report", str(rep), "--quiet", "--distance", "off"]
                   + options, check=True)
    cli = json.loads(rep.read_text())
    ref = pm.MeshSet()
    ref.load_new_mesh(str(out))
    mine, theirs = ms.current_mesh(), ref.current_mesh()
    assert np.array_equal(mine.face_matrix(), theirs.face_matrix())
    assert np.array_equal(mine.vertex_matrix(), theirs.vertex_matrix())
    for k in ("min_angle_before", "min_angle_after", "max_angle_after"):
        assert report[k] == cli[k], k
    assert report["flips"] == cli["flips"]
    assert report["returned_sweep"] == cli["returned_sweep"]
    if kwargs.get("algorithm") == "filtered":
        # The same filter, chosen for the same reasons.
        assert ["none", "normals", "taubin"][report["filter_kind"]] == cli["filter"]["kind"]
        for k in ("steps", "noise_level", "noise_estimated", "risk", "risk_unfiltered", "restored_vertices"):
            assert report["filter_" + k] == cli["filter"][k], k
