"""fibrodem.sweep and fibrodem.compare run the engines of `fibrodem sweep` and
`fibrodem compare` (core/study/): the same input gives the same tables, bit
for bit (the CSV files hold shortest round-trip decimals), whichever way a
sweep's points run (a child process of the command line, or this process)."""

import copy
import json
import os

import numpy as np
import pytest

import fibrodem
from conftest import FIBRODEM_EXE, run_cli
from fibrodem._result import _csv_table

# A small in-series tissue whose random layout changes with the seed (as in
# tests/study/test_sweep.cpp), 20 ms: each run a fraction of a second.
SEEDED = {
    "fibrodem": 1, "name": "pytest_seeded", "duration_ms": 20, "seed": 3,
    "tissue": {"builder": "in_series", "width_mm": 0.2, "height_mm": 0.8, "fm_ratio": 0.3},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"D_f_nS": 1},
    "stimulus": [{"target": {"y_min_frac": 0.8, "type": "myocyte"}, "start_ms": 10, "duration_ms": 2,
                  "amplitude_pA": 3000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02},
    "output": {"traces": {"cells": [0, 1], "variables": ["V"], "every_ms": 0.5}},
}


def assert_same_table(array, csv_file):
    """Every column of a structured array equals the CSV file's, exactly (NaN == NaN)."""
    expected = _csv_table(csv_file)
    assert array.dtype.names == expected.dtype.names
    for name in expected.dtype.names:
        np.testing.assert_array_equal(array[name], expected[name], err_msg=name)


@pytest.fixture
def seeded_sweep(tmp_path):
    (tmp_path / "m.json").write_text(json.dumps(SEEDED))
    (tmp_path / "sweep.json").write_text(json.dumps(
        {"fibrodem_sweep": 1, "manifest": "m.json", "grid": {"coupling.D_f_nS": [0.5, 4]}, "seeds": 2}))
    run_cli("sweep", str(tmp_path / "sweep.json"), "--out", str(tmp_path / "cli"), "--jobs", "2", "--no-report")
    return tmp_path


@pytest.mark.parametrize("runner", ["process", "in_process"])
def test_sweep_equals_command_line_sweep(seeded_sweep, runner):
    tmp_path = seeded_sweep
    swept = fibrodem.sweep(tmp_path / "sweep.json", out=tmp_path / runner, jobs=2, report=False, runner=runner)
    assert swept.runner == ("process: " + FIBRODEM_EXE if runner == "process" else "in_process")
    assert swept.completed and swept.statuses == ["completed"] * 4 and swept.reused == 0
    # The tables in memory are the command line's files, and the files it wrote are too.
    assert_same_table(swept._rows, tmp_path / "cli" / "sweep.csv")
    assert_same_table(swept._stats, tmp_path / "cli" / "sweep_stats.csv")
    for name in ("sweep.csv", "sweep_stats.csv", "sweep.md"):
        assert (tmp_path / runner / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert swept.markdown == (tmp_path / "cli" / "sweep.md").read_text()
    # Each run's numbers are those of a lone run of its manifest.
    for k in (0, 3):
        np.testing.assert_array_equal(swept.result(k).trace("V", 1),
                                      fibrodem.read(tmp_path / "cli" / ("run_%d" % k)).trace("V", 1))
    # Order: D_f 0.5 (seeds 3, 4), 4 (seeds 3, 4); the statistics are over each point's two seeds.
    assert [v["seed"] for v in swept.values] == [3, 4, 3, 4]
    rows, stats = swept._rows, swept._stats
    assert rows["fibroblast_rmp_mV"][0] != rows["fibroblast_rmp_mV"][1]  # the tissues differ
    for point in range(2):
        pair = rows["fibroblast_rmp_mV"][2 * point:2 * point + 2]
        # mean and SD (n - 1) of two values, by hand; rtol: a sum's rounding
        np.testing.assert_allclose(stats["fibroblast_rmp_mV_mean"][point], pair.mean(), rtol=1e-12)
        np.testing.assert_allclose(stats["fibroblast_rmp_mV_sd"][point], abs(pair[0] - pair[1]) / np.sqrt(2),
                                   rtol=1e-12)
    # More coupling pulls the passive fibroblasts (about -58 mV alone) towards the myocytes' -75 mV.
    assert stats["fibroblast_rmp_mV_mean"][1] < stats["fibroblast_rmp_mV_mean"][0]


def test_sweep_from_a_dict_with_its_manifest_and_set(cell_pair, tmp_path, monkeypatch):
    cell_pair["duration_ms"] = 100
    (tmp_path / "pair.json").write_text(json.dumps(cell_pair))
    grid = {"coupling.D_f_nS": [0.5, 8]}
    (tmp_path / "sweep.json").write_text(json.dumps({"fibrodem_sweep": 1, "manifest": "pair.json", "grid": grid}))
    run_cli("sweep", str(tmp_path / "sweep.json"), "--out", str(tmp_path / "cli"), "--jobs", "1",
            "--set", "stimulus[0].amplitude_pA=2500", "--no-report")

    given = {"fibrodem_sweep": 1, "manifest": copy.deepcopy(cell_pair), "grid": grid}
    swept = fibrodem.sweep(given, out=tmp_path / "py", jobs=1, set={"stimulus[0].amplitude_pA": 2500},
                           report=False, runner="in_process")
    assert_same_table(swept._rows, tmp_path / "cli" / "sweep.csv")
    assert swept.stats is None and swept.seeds == []
    assert swept.summaries[1]["manifest"]["stimulus"][0]["amplitude_pA"] == 2500

    # A manifest path in a dict is relative to the current folder; "PATH=VALUE" as --set.
    monkeypatch.chdir(tmp_path)
    again = fibrodem.sweep(dict(given, manifest="pair.json"), out="py", set=["stimulus[0].amplitude_pA=2500"],
                           report=False, runner="in_process")
    assert again.reused == 2  # the same manifests completed before: kept, not run again
    assert_same_table(again._rows, tmp_path / "cli" / "sweep.csv")


def test_a_sweep_point_that_fails_is_in_the_result(cell_pair, tmp_path):
    cell_pair["duration_ms"] = 20
    swept = fibrodem.sweep({"fibrodem_sweep": 1, "manifest": cell_pair, "grid": {"solver.method": ["rush_larsen",
                                                                                                    "leapfrog"]}},
                           out=tmp_path, report=False, runner="in_process")
    assert not swept.completed and swept.statuses == ["completed", "failed"]
    assert "solver.method" in swept.errors[1] and "leapfrog" in swept.errors[1]
    assert "leapfrog" in swept.markdown


def test_sweep_runner_and_argument_errors(tmp_path, monkeypatch):
    with pytest.raises(TypeError, match="sweep must be a sweep file path"):
        fibrodem.sweep(42)
    with pytest.raises(ValueError, match="runner must be"):
        fibrodem.sweep({"fibrodem_sweep": 1, "manifest": "m.json", "grid": {}}, runner="threads")
    with pytest.raises(fibrodem.ManifestError) as error:
        fibrodem.sweep({"fibrodem_sweep": 1, "manifest": SEEDED, "grid": {"coupling.D_f_nS": []}}, out=tmp_path,
                       runner="in_process")
    assert error.value.path == "grid.coupling.D_f_nS"
    monkeypatch.setenv("FIBRODEM_EXE", str(tmp_path / "missing"))
    with pytest.raises(FileNotFoundError, match="FIBRODEM_EXE"):
        fibrodem.sweep_executable()
    monkeypatch.delenv("FIBRODEM_EXE")
    # Without the variable: the command line built with the module.
    assert fibrodem.sweep_executable() == os.path.join(fibrodem._core.cli_dir, "fibrodem")


def test_compare_over_seeds_equals_command_line_compare(tmp_path):
    (tmp_path / "m.json").write_text(json.dumps(SEEDED))
    run_cli("compare", str(tmp_path / "m.json"), "--a", "coupling.D_f_nS=0.5", "--b", "coupling.D_f_nS=4",
            "--seeds", "2", "--out", str(tmp_path / "cli"), "--quiet", "--no-report")
    ab = fibrodem.compare(tmp_path / "m.json", a_set={"coupling.D_f_nS": 0.5}, b_set=["coupling.D_f_nS=4"], seeds=2,
                          out=tmp_path / "py", report=False)
    assert ab.seeds == [3, 4]
    assert_same_table(ab._rows, tmp_path / "cli" / "comparison.csv")
    assert_same_table(ab._paired, tmp_path / "cli" / "paired.csv")
    assert ab.markdown == (tmp_path / "cli" / "paired.md").read_text()
    # The paired difference by hand from the four runs' summaries.
    rmp = lambda s: s["mean_biomarkers"]["fibroblast"]["rmp_mV"]
    differences = [rmp(b) - rmp(a) for a, b in zip(ab.summaries_a, ab.summaries_b)]
    row = ab._paired[ab._paired["metric"] == "fibroblast_rmp_mV"][0]
    np.testing.assert_allclose(row["b_minus_a_mean"], np.mean(differences), rtol=1e-12)
    assert row["pairs"] == 2 and row["b_minus_a_mean"] < 0
    assert ab.a_dir == str(tmp_path / "py" / "seed_3" / "A")
    assert ab.b.summary["manifest"]["coupling"]["D_f_nS"] == 4


def test_compare_two_manifests_and_a_bad_b(cell_pair, tmp_path):
    cell_pair["duration_ms"] = 100
    (tmp_path / "a.json").write_text(json.dumps(cell_pair))
    b = copy.deepcopy(cell_pair)
    b["coupling"]["D_f_nS"] = 6
    (tmp_path / "b.json").write_text(json.dumps(b))
    run_cli("compare", str(tmp_path / "a.json"), str(tmp_path / "b.json"), "--out", str(tmp_path / "cli"), "--quiet")
    ab = fibrodem.compare(fibrodem.load_scene(cell_pair), b, out=tmp_path / "py")
    assert ab.paired is None and ab.seeds == []
    assert_same_table(ab._rows, tmp_path / "cli" / "comparison.csv")
    for name in ("comparison.csv", "comparison.md", "traces.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert (tmp_path / "py" / "report.html").exists()
    # relative_diff = (b - a) / |a|
    np.testing.assert_allclose(ab._rows["relative_diff"], (ab._rows["b"] - ab._rows["a"]) / np.abs(ab._rows["a"]),
                               rtol=1e-15)

    b["cells"]["fibroblast"]["model"] = "no_such_model"
    with pytest.raises(fibrodem.ManifestError) as error:
        fibrodem.compare(cell_pair, b, out=tmp_path / "bad")
    assert error.value.path == "B: cells.fibroblast.model" and "no_such_model" in str(error.value)
    assert not (tmp_path / "bad" / "A" / "summary.json").exists()  # checked before A ran
    with pytest.raises(fibrodem.ManifestError, match="two manifests"):
        fibrodem.compare(cell_pair, out=tmp_path / "one")
