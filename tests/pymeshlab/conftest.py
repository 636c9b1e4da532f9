# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared fixtures of the PyMeshLab tests (ctest -L pymeshlab).

ctest passes the paths in the environment (tests/pymeshlab/CMakeLists.txt):
  SODT_PYMESHLAB_DIR     the folder holding PyMeshLab 2025.7's pymeshlab/
  SODT_PYMESHLAB_PLUGIN  libfilter_sodt.so built for PyMeshLab (double)
  SODT_CLI               the sodt command of the same build
  SODT_MESH_DIR          the bundled meshes (meshes/)
  SODT_SHARED_MESH_DIR   ../shared/meshes (tests that need it fail without it)
and PYTHONPATH holds bench/compare. A missing path is an error, never a skip.

The tests import a mirror of that pymeshlab made of symlinks, without any
libfilter_sodt.so installed in its plugin folder (scripts/demo.sh installs one
there), so that they always load the plugin of this build.
"""
import os
import sys

import numpy as np
import pytest

from pymeshlab_compare import pristine_pymeshlab


def _env_path(name):
    value = os.environ.get(name, "")
    if not value or not os.path.exists(value):
        raise RuntimeError(f"{name}='{value}' does not exist; run these tests through ctest "
                           "(ctest -L pymeshlab) from a build configured with SODT_MESHLAB2025_DIR")
    return value


PYMESHLAB_PATH = pristine_pymeshlab(_env_path("SODT_PYMESHLAB_DIR"))
sys.path.insert(0, PYMESHLAB_PATH)
PLUGIN = _env_path("SODT_PYMESHLAB_PLUGIN")
SODT_CLI = _env_path("SODT_CLI")
MESH_DIR = _env_path("SODT_MESH_DIR")
SHARED_MESH_DIR = os.environ.get("SODT_SHARED_MESH_DIR", "")

SMOOTH = "apply_coord_sodt_smoothing"
CLASSIFY = "compute_scalar_by_sodt_feature_class_per_vertex"


def bundled(name):
    return os.path.join(MESH_DIR, name)


def shared(name):
    """A mesh of ../shared/meshes; fails (does not skip) when it is missing."""
    path = os.path.join(SHARED_MESH_DIR, name)
    if not os.path.isfile(path):
        pytest.fail(f"shared mesh {path} is missing (SODT_SHARED_MESH_DIR='{SHARED_MESH_DIR}')")
    return path


@pytest.fixture(scope="session")
def pm():
    """pymeshlab with the plugin of this build loaded (once: a second
    load_plugin of the same file raises)."""
    import pymeshlab
    assert pymeshlab.__file__.startswith(PYMESHLAB_PATH)
    assert SMOOTH not in pymeshlab.filter_list()
    pymeshlab.load_plugin(PLUGIN)
    return pymeshlab


@pytest.fixture
def meshset(pm):
    """A MeshSet loader: meshset(path) -> MeshSet with that mesh current."""
    def load(path):
        ms = pm.MeshSet()
        ms.load_new_mesh(path)
        return ms
    return load


def recover_after_exception(ms):
    """PyMeshLab 2025.7 leaves a dangling pointer behind when a filter raises
    (meshset_helper.cpp keeps VerbosityManager::staticLogger on the MeshSet's
    log, and only a filter that succeeds resets it): once that MeshSet is
    gone, the next load_new_mesh in any MeshSet crashes (PyMeshLab issue #399;
    its own filters do the same). A filter that succeeds on the same MeshSet
    clears it: here S-ODT with 0 sweeps and no class output, which changes
    nothing."""
    ms.apply_filter(SMOOTH, iterations=0, output_class=False)


def corner_angles_deg(vertices, faces):
    """All corner angles of the triangles, in degrees (numpy, double)."""
    p = vertices[faces]  # F x 3 x 3
    angles = []
    for i in range(3):
        a = p[:, (i + 1) % 3] - p[:, i]
        b = p[:, (i + 2) % 3] - p[:, i]
        cos = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    return np.concatenate(angles)
