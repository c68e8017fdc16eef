"""Shared set-up of the Python module's tests (run by ctest as "python module
(pytest)", which sets PYTHONPATH to <build>/python and FIBRODEM_EXE)."""

import copy
import os
import subprocess

import pytest

SOURCE_DIR = os.environ.get("FIBRODEM_SOURCE_DIR",
                            os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
FIBRODEM_EXE = os.environ.get("FIBRODEM_EXE", os.path.join(SOURCE_DIR, "build", "fibrodem"))

# A cell pair (colman myocyte + 2 passive fibroblasts) paced twice: 0.3 s of
# simulated time, a few tenths of a second of wall time each way.
CELL_PAIR = {
    "fibrodem": 1,
    "name": "pytest_cell_pair",
    "seed": 3,
    "duration_ms": 700,
    "tissue": {"builder": "cell_pair", "fibroblasts": 2},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"law": "gap_junction", "D_m_nS": 1000, "D_f_nS": 1},
    "stimulus": [{"target": "myocyte", "start_ms": 20, "duration_ms": 2, "amplitude_pA": 2000,
                  "period_ms": 350, "count": 2}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0, 1, 2], "variables": ["V"], "every_ms": 0.5},
               "biomarkers": {"from_ms": 0}, "maps": True},
}


@pytest.fixture
def cell_pair():
    return copy.deepcopy(CELL_PAIR)


def run_cli(*args, check=True):
    """The command line, as a user runs it; returns the CompletedProcess."""
    done = subprocess.run([FIBRODEM_EXE, *args], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError("fibrodem %s: exit %d\n%s" % (" ".join(args), done.returncode, done.stderr))
    return done
