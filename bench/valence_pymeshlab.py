# SPDX-License-Identifier: GPL-3.0-or-later
"""Smooths one mesh with the S-ODT plugin inside PyMeshLab 2025.7, as a
Python user would, and prints what it did: the high-valence benchmark
(bench/high_valence.sh) and its ctest guard (label "valence") run it.

usage: valence_pymeshlab.py PYMESHLAB_DIR PLUGIN MESH [NAME=VALUE ...]
  PYMESHLAB_DIR  the folder holding PyMeshLab's pymeshlab/
  PLUGIN         the libfilter_sodt.so built for PyMeshLab
  NAME=VALUE     filter parameters (numbers, true/false, or text)

Exit status 0 when the filter ran and returned its report, 1 otherwise.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "compare"))
from pymeshlab_compare import pristine_pymeshlab  # noqa: E402


def value(text):
    if text in ("true", "false"):
        return text == "true"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def main(argv):
    if len(argv) < 4 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) > 1 and argv[1] in ("-h", "--help") else 2
    sys.path.insert(0, pristine_pymeshlab(argv[1]))
    import pymeshlab
    pymeshlab.load_plugin(argv[2])
    params = {}
    for arg in argv[4:]:
        name, _, text = arg.partition("=")
        params[name] = value(text)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(argv[3])
    report = ms.apply_filter("apply_coord_sodt_smoothing", **params)
    m = ms.current_mesh()
    print(f"{m.vertex_number()} vertices, {m.face_number()} faces; "
          f"min angle {report['min_angle_before']:.3f} -> {report['min_angle_after']:.3f} deg")
    return 0 if "min_angle_after" in report else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
