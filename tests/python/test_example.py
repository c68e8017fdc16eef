"""examples/python/d_f_sweep.py runs and draws its figure."""

import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_d_f_sweep_example(tmp_path):
    import pytest
    pytest.importorskip("matplotlib")
    script = os.path.join(SOURCE_DIR, "examples", "python", "d_f_sweep.py")
    png = tmp_path / "sweep.png"
    done = subprocess.run([sys.executable, script, "--beats", "1", "--out", str(png)], capture_output=True,
                          text=True, env=os.environ)
    assert done.returncode == 0, done.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = [line.split() for line in done.stdout.splitlines()[1:7]]
    assert [float(r[0]) for r in rows] == [0.0, 0.5, 1.0, 2.0, 4.0, 8.0]
    # The passive fibroblasts (E -49.6 mV, docs/topics/models.md) depolarise the
    # myocyte's rest more the stronger they are coupled: RMP rises with D_f.
    rmp = [float(r[1]) for r in rows]
    assert rmp == sorted(rmp) and rmp[-1] - rmp[0] > 1.0
