"""Result's conveniences: progress, read_sweep, plot."""

import io
import json

import numpy as np
import pytest

import fibrodem
from conftest import SOURCE_DIR, run_cli


def test_progress_callback_and_bar(cell_pair, monkeypatch):
    scene = fibrodem.load_scene(cell_pair).set("output.progress_every_s", 0)
    calls = []
    fibrodem.run(scene, progress=lambda t_ms, duration_ms: calls.append((t_ms, duration_ms)))
    # progress_every_s 0 turns the periodic calls off: only the final one
    assert calls == [(700.0, 700.0)]
    scene.set("output.progress_every_s", 1e-9)
    calls.clear()
    fibrodem.run(scene.set("duration_ms", 5), progress=lambda t, d: calls.append(t))
    # every step (0.01 ms) once the interval is below a step's wall time, then the end
    assert len(calls) > 100 and calls[-1] == 5.0 and calls == sorted(calls)
    stderr = io.StringIO()
    monkeypatch.setattr("sys.stderr", stderr)
    fibrodem.run(scene, progress=True)
    assert "5.0 / 5.0 ms" in stderr.getvalue()


def test_a_raising_progress_callback_stops_the_run(cell_pair):
    def progress(t_ms, duration_ms):
        raise ValueError("stop here")
    with pytest.raises(ValueError, match="stop here"):
        fibrodem.run(fibrodem.load_scene(cell_pair).set("output.progress_every_s", 1e-9), progress=progress)


def test_read_sweep(cell_pair, tmp_path):
    cell_pair["duration_ms"] = 400
    (tmp_path / "pair.json").write_text(json.dumps(cell_pair))
    (tmp_path / "sweep.json").write_text(json.dumps(
        {"fibrodem_sweep": 1, "manifest": "pair.json", "grid": {"coupling.D_f_nS": [0.5, 8]}}))
    run_cli("sweep", str(tmp_path / "sweep.json"), "--out", str(tmp_path / "sweep"), "--jobs", "1")
    table = fibrodem.read_sweep(tmp_path / "sweep")
    assert list(table["coupling.D_f_nS"]) == [0.5, 8.0]
    assert list(table["status"]) == ["completed", "completed"]
    # each row's numbers are its run's summary.json's mean biomarkers (run_K folders)
    for k in range(2):
        run = fibrodem.read(tmp_path / "sweep" / ("run_%d" % k))
        assert run.status == "completed"
        assert table["myocyte_apd90_ms"][k] == run.summary["mean_biomarkers"]["myocyte"]["apd90_ms"]
    # stronger coupling pulls the fibroblasts' rest towards the myocyte's (-73 mV)
    assert table["fibroblast_rmp_mV"][1] < table["fibroblast_rmp_mV"][0]


def test_plot_saves_a_png(cell_pair, tmp_path):
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    result = fibrodem.run(fibrodem.load_scene(cell_pair))
    figure = result.plot(tmp_path / "look.png")
    assert (tmp_path / "look.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(figure.axes[0].lines) == 3  # V of cells 0, 1, 2


def test_trace_names_what_was_traced(cell_pair):
    result = fibrodem.run(fibrodem.load_scene(cell_pair).set("duration_ms", 10))
    assert result.variables == ["V"] and result.cells("V") == [0, 1, 2]
    with pytest.raises(KeyError, match="V_7"):
        result.trace("V", 7)
    assert np.all(np.isnan(result.maps["apd90_ms"]))  # no beat completed in 10 ms


def test_a_run_releases_the_gil(cell_pair):
    import threading
    import time
    ticks = []
    running = threading.Event()

    def other_thread():
        running.set()
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    stop = threading.Event()
    worker = threading.Thread(target=other_thread)
    worker.start()
    running.wait()
    start = time.perf_counter()
    fibrodem.run(fibrodem.load_scene(cell_pair))  # no progress callback: no Python code runs in it
    end = time.perf_counter()
    stop.set()
    worker.join()
    # the other thread kept running while the run (~0.3 s of wall time) held no GIL
    during = [t for t in ticks if start < t < end]
    assert end - start > 0.05 and len(during) >= 10, (end - start, len(during))


def test_maps_hold_each_cells_last_beat(cell_pair):
    result = fibrodem.run(fibrodem.load_scene(cell_pair))
    beats = result._biomarkers
    assert len(beats) == 6  # 3 cells x 2 beats (stimuli at 20 and 370 ms)
    for cell in range(3):
        last = beats[beats["cell"] == cell][-1]
        assert last["beat"] == 1
        assert result.maps["activation_ms"][cell] == last["activation_ms"]
        assert result.maps["apd90_ms"][cell] == last["apd90_ms"]
