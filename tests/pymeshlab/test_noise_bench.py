# SPDX-License-Identifier: GPL-3.0-or-later
"""The noise benchmark (bench/noise/noise_bench.py) end to end on the
bundled cube: its scores, its targets table and the section it writes into
a RESULTS.md, keeping what else the file holds."""
import json
import os
import shutil
import subprocess
import sys

import pytest

from conftest import SODT_CLI

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH = os.path.join(ROOT, "bench", "noise", "noise_bench.py")
sys.path.insert(0, os.path.dirname(BENCH))
import noise_bench as nb  # noqa: E402


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One run on the cube at sigma 0.3 edges, with a RESULTS.md that already
    holds a title and another tool's section."""
    work = tmp_path_factory.mktemp("noise")
    results = work / "docs" / "RESULTS.md"
    results.parent.mkdir()
    results.write_text("# Results\n\nkept text\n\n<!-- pymeshlab-comparison:begin -->\nother tool\n"
                       "<!-- pymeshlab-comparison:end -->\n", encoding="utf-8")
    if not shutil.which("MeshDenoiser"):
        pytest.fail("MeshDenoiser is missing: install Debian's meshsdfilter-tools (scripts/install-deps.sh)")
    cmd = ["/usr/bin/python3", BENCH, "--out", str(work / "out"), "--sodt", SODT_CLI,
           "--pymeshlab", os.environ["SODT_PYMESHLAB_DIR"], "--shared", str(work / "no-shared"),
           "--meshes", "cube", "--sigmas", "0.3", "--methods", "sodt_filtered,taubin,meshdenoiser",
           "--results", str(results)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    data = json.loads((work / "out" / "results.json").read_text(encoding="utf-8"))
    return work, results, data


def row(data, method):
    rows = [x for x in data["rows"] if x["method"] == method]
    assert len(rows) == 1, method
    return rows[0]


def test_filtered_removes_most_of_the_noise_and_keeps_the_edges(run):
    _work, _results, data = run
    inp, fil, tau = row(data, "input"), row(data, "sodt_filtered"), row(data, "taubin")
    assert inp["mean_rel"] > 0 and fil["mean_ratio"] == pytest.approx(fil["mean_rel"] / inp["mean_rel"])
    assert fil["mean_ratio"] <= 0.5
    assert fil["mean_ratio"] < tau["mean_ratio"]
    # The cube's 90 degree edges: the noise blurs them, Taubin rounds them off.
    assert fil["sharp_dihedral_err_deg"] < 0.5 * inp["sharp_dihedral_err_deg"]
    assert fil["sharp_dihedral_err_deg"] < 0.5 * tau["sharp_dihedral_err_deg"]
    # The targets: good triangles and no face turned over.
    assert fil["min_angle"] >= 20
    # sodt stats reads the noise made (0.3 edges), a little high on a CAD part.
    assert 0.8 * 0.3 < inp["noise_estimate"] < 1.6 * 0.3
    assert fil["noise_estimate"] < 0.5 * inp["noise_estimate"]
    assert fil["inverted"] == 0


def test_results_section_replaces_its_own_and_keeps_the_rest(run):
    work, results, data = run
    text = results.read_text(encoding="utf-8")
    assert text.startswith("# Results\n\nkept text\n")
    assert "other tool" in text and text.count(nb.RESULTS_BEGIN) == 1 and text.count(nb.RESULTS_END) == 1
    section = text[text.index(nb.RESULTS_BEGIN):]
    assert "## Noise benchmark" in section and "](figures/noise-distance.svg)" in section
    assert "**The targets of `sodt filtered`**" in section and "| cube | 0.3 |" in section
    svg = results.parent / "figures" / "noise-distance.svg"
    assert svg.is_file() and svg.read_text(encoding="utf-8").lstrip().startswith("<?xml")
    # A second write replaces the section instead of adding one.
    nb.replace_results(str(results), nb.results_section(nb.markdown(data["rows"], data["meta"],
                                                                    data["meta"]["methods"]),
                                                        "figures/noise-distance.svg"))
    again = results.read_text(encoding="utf-8")
    assert again.count(nb.RESULTS_BEGIN) == 1 and "other tool" in again and "kept text" in again


def test_targets_are_checked_against_the_rivals(run):
    _work, _results, data = run
    checks = {label: ok for mesh, sigma, cs in nb.target_checks(data["rows"]) for label, _v, ok in cs}
    assert checks["mean ≤ 0.5×"]
    assert checks["min angle ≥ 20°"] == (row(data, "sodt_filtered")["min_angle"] >= 20)
    assert checks["no inverted face"] == (row(data, "sodt_filtered")["inverted"] == 0)
    # A denoiser that left more noise than Taubin misses the rival target.
    rows = [dict(x) for x in data["rows"]]
    for x in rows:
        if x["method"] == "sodt_filtered":
            x["mean_ratio"] = row(data, "taubin")["mean_ratio"] + 0.01
            x["min_angle"] = 19.9
    worse = {label: ok for _m, _s, cs in nb.target_checks(rows) for label, _v, ok in cs}
    assert not worse["mean ≤ best rival"] and not worse["min angle ≥ 20°"]
    # Values that differ are written so that they read different.
    for x in rows:
        if x["method"] == "sodt_filtered":
            x["mean_ratio"] = row(data, "taubin")["mean_ratio"] - 0.001
    close = [v for _m, _s, cs in nb.target_checks(rows) for label, v, _ok in cs if label == "mean ≤ best rival"]
    mine, best = close[0].split(" vs ")
    assert mine != best, close[0]
    assert nb.distinct(0.25, 0.25, 2) == ("0.25", "0.25")
