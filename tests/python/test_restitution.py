"""fibrodem.restitution runs the engine of `fibrodem restitution`
(core/study/restitution.hpp): in this process it gives the same table and
ERP as the command line's child processes."""

import csv
import json
import math

import pytest

import fibrodem
from conftest import run_cli

# The chronic-AF Courtemanche cell of tests/study/test_restitution.cpp, paced
# 3 times at 1 Hz, S2 at 2210 ms; Rush-Larsen so that each run takes
# a fraction of a second.
CELL = {
    "fibrodem": 1, "name": "pytest_crn_caf", "duration_ms": 2610,
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "courtemanche1999_caf"}},
    "stimulus": [
        {"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000, "period_ms": 1000, "count": 3},
        {"target": "myocyte", "start_ms": 2210, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"report": False},
}


def test_same_curve_and_erp_as_the_command_line(tmp_path):
    found = fibrodem.restitution(CELL, out=tmp_path / "py", intervals_ms=[400, 250, 180], jobs=2,
                                 runner="in_process")
    manifest = tmp_path / "cell.json"
    manifest.write_text(json.dumps(CELL))
    run_cli("restitution", str(manifest), "--out", str(tmp_path / "cli"), "--intervals", "400,250,180",
            "--jobs", "2")
    with open(tmp_path / "cli" / "restitution.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    cli = json.loads((tmp_path / "cli" / "restitution.json").read_text())
    assert found["erp_ms"] == cli["erp_ms"]
    assert [p["interval_ms"] for p in found["points"]] == [float(r["interval_ms"]) for r in rows]
    for p, r in zip(found["points"], rows):
        assert p["captured"] == (r["captured"] == "1")
        if p["captured"]:
            # The CSV holds shortest round-trip decimals: equal numbers.
            assert p["s2_apd90_ms"] == float(r["s2_apd90_ms"])
            assert p["di_ms"] == float(r["di_ms"])
        else:
            assert math.isnan(p["s2_apd90_ms"])
    # S2 at 400 and 250 ms captured, at 180 ms not (the ERP is near 189 ms):
    # the bisection ran between 250 and 180 down to a 1 ms bracket.
    assert 180 <= found["erp_ms"] < 250
    assert any(p["stage"] == "bisection" for p in found["points"])


def test_bad_arguments_are_refused():
    # The limits of study/study_options.hpp, which the command line's flags obey.
    with pytest.raises(fibrodem.ManifestError, match=r"--intervals \(intervals_ms\): expected a number > 0, got -1"):
        fibrodem.restitution(CELL, intervals_ms=[400, -1])
    with pytest.raises(fibrodem.ManifestError, match=r"cells\): expected a whole number >= 0, got -2"):
        fibrodem.restitution(CELL, cells=[-2])
    with pytest.raises(fibrodem.ManifestError, match=r"capture_fraction\): expected a number in \[0, 1\], got 1.5"):
        fibrodem.restitution(CELL, capture_fraction=1.5)
    with pytest.raises(TypeError, match="cells must be cell indices"):
        fibrodem.restitution(CELL, cells=[1.5])
