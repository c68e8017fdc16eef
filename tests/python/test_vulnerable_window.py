"""fibrodem.vulnerable_window runs the engine of `fibrodem vulnerable-window`
(core/study/vulnerable_window.hpp): in this process it finds the same window
and outcomes as the command line's child processes."""

import json

import pytest

import fibrodem
from conftest import run_cli

# The strand of tests/study/test_vulnerable_window.cpp: 46 colman2013_caf myocytes,
# S1 and S2 at one end; "re-entry" while the S1 wave still travels, up to an
# interval near 74 ms. Each run a fraction of a second.
STRAND = {
    "fibrodem": 1, "name": "pytest_strand", "duration_ms": 400, "seed": 1,
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.05, "length_mm": 3},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013_caf"}},
    "coupling": {"D_m_nS": 5},
    "stimulus": [
        {"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 0.2}, "start_ms": 10,
         "duration_ms": 2, "amplitude_pA": 4000},
        {"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 0.2}, "start_ms": 200,
         "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "auto"},
    "output": {"reentry": {"every_ms": 1}, "report": False},
}


def test_same_window_as_the_command_line(tmp_path):
    found = fibrodem.vulnerable_window(STRAND, out=tmp_path / "py", from_ms=60, to_ms=80, step_ms=10, jobs=2,
                                       runner="in_process")
    manifest = tmp_path / "strand.json"
    manifest.write_text(json.dumps(STRAND))
    run_cli("vulnerable-window", str(manifest), "--out", str(tmp_path / "cli"), "--from", "60", "--to", "80",
            "--step", "10", "--jobs", "2")
    cli = json.loads((tmp_path / "cli" / "vulnerable_window.json").read_text())
    assert not found["reentry_output_added"]
    assert found["per_seed"] == [{"seed": 1, "windows": cli["per_seed"][0]["windows"]}]
    window = found["per_seed"][0]["windows"][0]
    assert window["lower_ms"] == 60 and window["open_below"]
    assert 60 < window["upper_ms"] < 80
    # The bisection left the boundary bracketed to 1 ms: the interval after
    # the window's end was run and not induced.
    outcomes = {r["interval_ms"]: r["outcome"] for r in found["runs"]}
    assert outcomes[window["upper_ms"]] == "reentry"
    assert outcomes[window["upper_ms"] + 1] != "reentry"


def test_scan_given_in_part_is_refused():
    with pytest.raises(ValueError, match="from_ms, to_ms and step_ms together"):
        fibrodem.vulnerable_window(STRAND, from_ms=60)
