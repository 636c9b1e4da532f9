#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Smooth a mesh with the S-ODT plugin from Python (PyMeshLab 2025.7).

  python3 sodt_pymeshlab.py IN OUT [--plugin libfilter_sodt.so] [--algorithm basic|feature|denoise]
                            [--iterations N] [--flips]

Without --plugin the plugin must be installed in pymeshlab's lib/plugins
folder (then it is also a MeshSet method, ms.apply_coord_sodt_smoothing).
Prints the quality report the filter returns and the vertex classes, and saves
OUT with the classes as vertex quality and colour.
"""
import argparse
import sys

import numpy as np
import pymeshlab

FILTER = "apply_coord_sodt_smoothing"
CLASS_NAMES = ["smooth", "crease", "corner", "fixed"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--plugin", help="libfilter_sodt.so built for PyMeshLab (double precision)")
    ap.add_argument("--algorithm", default="basic", choices=["basic", "feature", "denoise"])
    ap.add_argument("--iterations", type=int, default=20)
    ap.add_argument("--flips", action="store_true", help="also flip edges (changes the connectivity)")
    a = ap.parse_args()

    if FILTER not in pymeshlab.filter_list():
        if not a.plugin:
            sys.exit(f"the S-ODT plugin is not installed in {pymeshlab.__file__.rsplit('/', 1)[0]}/lib/plugins: "
                     "pass --plugin PATH/libfilter_sodt.so")
        pymeshlab.load_plugin(a.plugin)

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(a.input)
    try:
        report = ms.apply_filter(FILTER, algorithm=a.algorithm, iterations=a.iterations, flips=a.flips)
    except pymeshlab.PyMeshLabException as e:
        sys.exit(str(e))

    print(f"min angle {report['min_angle_before']:.2f} -> {report['min_angle_after']:.2f} deg, "
          f"max angle {report['max_angle_before']:.2f} -> {report['max_angle_after']:.2f} deg, "
          f"angles below 30 deg {100 * report['frac_below_30_before']:.2f}% -> "
          f"{100 * report['frac_below_30_after']:.2f}%")
    if report["closed"]:
        print(f"enclosed volume {report['volume_before']:.9g} -> {report['volume_after']:.9g}")
    print(f"{report['sweeps']} sweeps on {report['threads']} threads in {report['seconds']:.3f} s, "
          f"{report['flips']} flips")

    # The classes the run used, written as vertex quality (0..3) and colour.
    codes = ms.current_mesh().vertex_scalar_array().astype(int)
    print("vertex classes:", ", ".join(f"{np.count_nonzero(codes == c)} {n}" for c, n in enumerate(CLASS_NAMES)))
    ms.save_current_mesh(a.output, save_vertex_quality=True, save_vertex_color=True)
    print("wrote", a.output)


if __name__ == "__main__":
    main()
