"""Ctrl-C during fibrodem.run: KeyboardInterrupt, and with out= the folder
says `interrupted`, as after `fibrodem run` gets SIGINT."""

import json
import os
import signal
import subprocess
import sys
import textwrap

CHILD = textwrap.dedent("""
    import sys, fibrodem
    scene = fibrodem.load_scene(sys.argv[1])
    scene.set("duration_ms", 200000).set("output.progress_every_s", 0.05)
    def progress(t_ms, duration_ms):
        print("running", t_ms, flush=True)
    try:
        fibrodem.run(scene, out=sys.argv[2], progress=progress)
        print("completed", flush=True)
    except KeyboardInterrupt as stop:
        print("KeyboardInterrupt", stop.result.status, stop.result.summary["simulated_ms"], flush=True)
""")


def test_sigint_stops_a_run_with_keyboard_interrupt(cell_pair, tmp_path):
    manifest = tmp_path / "scene.json"
    manifest.write_text(json.dumps(cell_pair))
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(manifest), str(tmp_path / "out")],
                             stdout=subprocess.PIPE, text=True, env=os.environ)
    try:
        assert child.stdout.readline().startswith("running")  # the run is under way
        child.send_signal(signal.SIGINT)
        lines = child.stdout.read().splitlines()
        assert child.wait(timeout=60) == 0
    finally:
        child.kill()
    last = lines[-1].split()
    assert last[:2] == ["KeyboardInterrupt", "interrupted"], lines
    simulated_ms = float(last[2])
    assert 0 < simulated_ms < 200000
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "interrupted" and "SIGINT" in summary["error"]
    assert summary["simulated_ms"] == simulated_ms
    assert "run interrupted" in (tmp_path / "out" / "run.log").read_text()


def test_after_a_run_python_keeps_its_own_sigint_handler(cell_pair):
    import fibrodem
    before = signal.getsignal(signal.SIGINT)
    fibrodem.run(fibrodem.load_scene(cell_pair).set("duration_ms", 10))
    assert signal.getsignal(signal.SIGINT) is before
