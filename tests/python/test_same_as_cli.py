"""The module runs the core the command line runs: the same manifest gives the
same numbers, bit for bit (traces.csv and biomarkers.csv hold shortest
round-trip decimals, so reading them back loses nothing)."""

import json

import numpy as np

import fibrodem
from conftest import run_cli


def assert_same_result(a, b):
    assert list(a.traces) == list(b.traces)
    np.testing.assert_array_equal(a.t_ms, b.t_ms)
    for name in a.traces:
        # assert_array_equal: exact equality (NaN == NaN), no tolerance
        np.testing.assert_array_equal(a.traces[name], b.traces[name], err_msg=name)
    np.testing.assert_array_equal(np.asarray(a._biomarkers), np.asarray(b._biomarkers))
    for name in a.maps:
        np.testing.assert_array_equal(a.maps[name], b.maps[name], err_msg=name)
    np.testing.assert_array_equal(a.cell_types, b.cell_types)
    assert a.summary["mean_biomarkers"] == b.summary["mean_biomarkers"]


def test_run_in_memory_equals_command_line_run(cell_pair, tmp_path):
    manifest = tmp_path / "scene.json"
    manifest.write_text(json.dumps(cell_pair))
    run_cli("run", str(manifest), "--set", "coupling.D_f_nS=4", "--out", str(tmp_path / "cli"), "--quiet")
    from_cli = fibrodem.read(tmp_path / "cli")

    scene = fibrodem.load_scene(manifest).set("coupling.D_f_nS", 4)
    in_memory = fibrodem.run(scene)

    assert in_memory.out_dir is None and from_cli.status == in_memory.status == "completed"
    # 700 ms at 0.5 ms: 1401 samples; two beats of 3 cells.
    assert len(in_memory.t_ms) == 1401 and len(in_memory._biomarkers) == 6
    assert_same_result(in_memory, from_cli)
    assert from_cli.summary["manifest"] == in_memory.summary["manifest"]


def test_run_with_out_writes_what_the_command_line_writes(cell_pair, tmp_path):
    result = fibrodem.run(fibrodem.load_scene(cell_pair), out=tmp_path / "py")
    assert result.out_dir == str(tmp_path / "py")
    for name in ("summary.json", "traces.csv", "biomarkers.csv", "run.log", "activation_map.png", "maps.vtk"):
        assert (tmp_path / "py" / name).exists(), name
    assert_same_result(result, fibrodem.read(tmp_path / "py"))


def test_without_out_nothing_is_written(cell_pair, tmp_path, monkeypatch):
    cell_pair["output"]["dir"] = str(tmp_path / "ignored")
    monkeypatch.chdir(tmp_path)
    fibrodem.run(fibrodem.load_scene(cell_pair))
    assert list(tmp_path.iterdir()) == []


def test_simulate_cell_equals_a_single_cell_run():
    pulse = fibrodem.pacing(period_ms=1000, start_ms=10)
    logged = fibrodem.simulate_cell("colman", variant="ni2017", parameters={"g_K1_scale": 1.2}, stimulus=pulse,
                                    duration_ms=300, solver={"method": "rush_larsen", "dt_ms": 0.01},
                                    log=["V", "Ca_i"], log_every_ms=0.5)
    scene = fibrodem.load_scene({
        "fibrodem": 1, "name": "single", "duration_ms": 300,
        "tissue": {"builder": "single_cell", "type": "myocyte"},
        "cells": {"myocyte": {"model": "colman", "variant": "ni2017", "parameters": {"g_K1_scale": 1.2}}},
        "stimulus": [pulse], "solver": {"method": "rush_larsen", "dt_ms": 0.01},
        "output": {"traces": {"cells": [0], "variables": ["V", "Ca_i"], "every_ms": 0.5}}})
    result = fibrodem.run(scene)
    np.testing.assert_array_equal(logged["t_ms"], result.t_ms)
    np.testing.assert_array_equal(logged["V"], result.trace("V", 0))
    np.testing.assert_array_equal(logged["Ca_i"], result.trace("Ca_i", 0))
    np.testing.assert_array_equal(logged.biomarkers, result._biomarkers)
    assert len(logged.biomarkers) == 1 and 200 < logged.biomarkers["apd90_ms"][0] < 350


def test_plugins_lists_what_the_command_line_lists():
    from_cli = json.loads(run_cli("plugins", "--json").stdout)
    assert fibrodem.plugins() == from_cli
    colman = next(m for m in fibrodem.plugins() if m["name"] == "colman")
    V = next(s for s in colman["states"] if s["name"] == "V")
    assert V["unit"] == "mV" and V["lower"] < -100 and V["upper"] > 50
    assert [v["name"] for v in colman["variants"]][:2] == ["colman2013", "ni2017"]
    assert all({"name", "unit", "default", "description"} <= set(p) for p in colman["parameters"])
