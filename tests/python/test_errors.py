"""Bad input arrives as the exceptions the module documents, with the command
line's messages."""

import json
import os
import subprocess
import sys

import pytest

import fibrodem
from conftest import FIBRODEM_EXE, run_cli


def test_set_raises_what_the_command_line_prints(cell_pair, tmp_path):
    manifest = tmp_path / "scene.json"
    manifest.write_text(json.dumps(cell_pair))
    scene = fibrodem.load_scene(manifest)
    with pytest.raises(fibrodem.ManifestError) as caught:
        scene.set("coupling.D_f_nS", -1)
    assert caught.value.path == "coupling.D_f_nS"
    assert caught.value.expected.startswith("expected a number in [0, ")
    cli = run_cli("validate", str(manifest), "--set", "coupling.D_f_nS=-1", check=False)
    assert cli.returncode == 2
    assert cli.stderr.strip() == "error: " + str(caught.value)
    # the scene is unchanged after a refused set
    assert scene.manifest["coupling"]["D_f_nS"] == 1


def test_set_path_errors_are_the_command_lines(cell_pair):
    scene = fibrodem.load_scene(cell_pair)
    with pytest.raises(fibrodem.ManifestError) as caught:
        scene.set("stimulus[4].amplitude_pA", 1)
    assert caught.value.path == "stimulus[4]" and "no such list entry" in caught.value.expected
    with pytest.raises(fibrodem.ManifestError) as caught:
        scene.set("solver.method", "runge_kutta")
    assert caught.value.path == "solver.method"


def test_load_scene_errors(cell_pair, tmp_path):
    del cell_pair["duration_ms"]
    with pytest.raises(fibrodem.ManifestError) as caught:
        fibrodem.load_scene(cell_pair)
    assert caught.value.path == "duration_ms"
    with pytest.raises(fibrodem.ManifestError):
        fibrodem.load_scene(tmp_path / "missing.json")
    with pytest.raises(TypeError, match=r"scene\['x'\]"):
        fibrodem.load_scene({"x": object()})


def test_errors_found_when_the_scene_is_built(cell_pair):
    cell_pair["cells"]["myocyte"]["parameters"] = {"no_such_parameter": 1}
    with pytest.raises(fibrodem.ManifestError) as caught:
        fibrodem.run(fibrodem.load_scene(cell_pair))
    assert caught.value.path.startswith("cells.myocyte.parameters")
    cell_pair["cells"]["myocyte"] = {"model": "no_such_model"}
    with pytest.raises(fibrodem.ManifestError, match="no cell-model plugin named 'no_such_model'") as caught:
        fibrodem.run(fibrodem.load_scene(cell_pair))
    assert caught.value.path == "cells.myocyte.model"


def test_a_faulty_plugin_raises_plugin_error():
    # The loader's deliberately broken plugins (tests/plugins, built into
    # <build>/test_plugins) first on the search path, in a fresh interpreter
    # (the search path is read once per process).
    test_plugins = os.path.join(os.path.dirname(FIBRODEM_EXE), "test_plugins")
    code = ("import fibrodem\n"
            "try:\n    fibrodem.plugins()\n"
            "except fibrodem.PluginError as e:\n    print('PluginError', e)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=dict(os.environ, FIBRODEM_PLUGIN_PATH=test_plugins))
    assert done.stdout.startswith("PluginError") and "ABI" in done.stdout, done.stdout + done.stderr


def test_wrong_argument_types_name_the_argument(cell_pair):
    scene = fibrodem.load_scene(cell_pair)
    cases = [
        (lambda: fibrodem.load_scene(42), "source"),
        (lambda: scene.set(3, 1.0), "path"),
        (lambda: fibrodem.run(cell_pair), "scene"),
        (lambda: fibrodem.run(scene, out=3), "out"),
        (lambda: fibrodem.run(scene, progress="yes"), "progress"),
        (lambda: fibrodem.read(3), "directory"),
        (lambda: fibrodem.simulate_cell(1), "model"),
        (lambda: fibrodem.simulate_cell("colman", parameters=[1]), "parameters"),
        (lambda: fibrodem.simulate_cell("colman", duration_ms="1"), "duration_ms"),
        (lambda: fibrodem.simulate_cell("colman", log="V"), "log"),
        (lambda: fibrodem.simulate_cell("colman", solver=3), "solver"),
    ]
    for call, argument in cases:
        with pytest.raises(TypeError, match=argument):
            call()


def test_a_failed_run_raises_run_error_with_the_result_so_far():
    # Forward Euler at 0.2 ms is far beyond colman's fastest gate's limit
    # (~0.02 ms, docs/topics/numerics.md#fixed-steps): a blow-up, named.
    with pytest.raises(fibrodem.RunError, match="blow-up") as caught:
        fibrodem.simulate_cell("colman", stimulus=fibrodem.pacing(start_ms=5), duration_ms=100,
                               solver={"method": "euler", "dt_ms": 0.2}, log_every_ms=0.2)
    assert len(caught.value.result["t_ms"]) > 0
