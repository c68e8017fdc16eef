"""`pip install .` into a fresh venv, then the installed package at work.

The venv has --system-site-packages (numpy, setuptools and wheel are
Debian's; pip runs --no-index --no-build-isolation, offline), and the
package is built from this test's own CMake build (FIBRODEM_CMAKE_BUILD_DIR:
nothing is compiled twice). From a folder outside the source and the build,
with no PYTHONPATH: the module is the installed one and finds its command
line and plugins in the package (fibrodem/bin); a small cell pair run in
memory gives the numbers the installed `fibrodem run` writes, bit for bit
(the module and the command line run the same core:
tests/python/test_same_as_cli.py); and `fibrodem --version` names the
module's version.

Usage: python3 tests/python_install.py SOURCE_DIR BUILD_DIR
"""

import json
import os
import subprocess
import sys
import tempfile

# A colman myocyte and a passive fibroblast (two plugins), paced once: 60 ms.
SCENE = {
    "fibrodem": 1, "name": "installed_package", "seed": 1, "duration_ms": 60,
    "tissue": {"builder": "cell_pair", "fibroblasts": 1},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"law": "gap_junction", "D_m_nS": 1000, "D_f_nS": 2},
    "stimulus": [{"target": "myocyte", "start_ms": 5, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0, 1], "variables": ["V"], "every_ms": 1}},
}

# check.py, run by the venv's python in the scratch folder: argv[1] the venv.
CHECK = r"""
import json, os, subprocess, sys
import numpy as np
import fibrodem
venv = sys.argv[1]
package = os.path.dirname(fibrodem.__file__)
assert package.startswith(venv + os.sep), "imported %s, not the venv's package" % package
assert fibrodem._core.cli_dir == os.path.join(package, "bin"), fibrodem._core.cli_dir
plugin_files = {m["name"]: m["file"] for m in fibrodem.plugins()}
assert {"colman", "passive_fibroblast"} <= set(plugin_files), sorted(plugin_files)
for file in plugin_files.values():
    assert file.startswith(os.path.join(package, "bin", "plugins") + os.sep), file
scene = json.load(open("scene.json"))
in_memory = fibrodem.run(fibrodem.load_scene(scene))
command = os.path.join(venv, "bin", "fibrodem")
subprocess.run([command, "run", "scene.json", "--out", "out", "--quiet"], check=True)
written = fibrodem.read("out")
np.testing.assert_array_equal(in_memory.t_ms, written.t_ms)
assert len(in_memory.t_ms) == 61, len(in_memory.t_ms)
for cell in (0, 1):
    np.testing.assert_array_equal(in_memory.trace("V", cell), written.trace("V", cell))
# The myocyte fired: an action potential overshoots 0 mV.
assert in_memory.trace("V", 0).max() > 0, in_memory.trace("V", 0).max()
version = subprocess.run([command, "--version"], capture_output=True, text=True, check=True).stdout
assert fibrodem.__version__ in version, (version, fibrodem.__version__)
print("installed fibrodem", fibrodem.__version__, "in", package)
"""


def run(args, **kwargs):
    print("+", " ".join(args), flush=True)
    subprocess.run(args, check=True, **kwargs)


def main(source, build):
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "FIBRODEM_EXE", "FIBRODEM_PLUGIN_PATH", "FIBRODEM_MODULE_PATH")}
    with tempfile.TemporaryDirectory(prefix="fibrodem_install_") as scratch:
        venv = os.path.join(scratch, "venv")
        run([sys.executable, "-m", "venv", "--system-site-packages", venv], env=env)
        python = os.path.join(venv, "bin", "python")
        run([python, "-m", "pip", "install", "--quiet", "--no-index", "--no-build-isolation",
             "--disable-pip-version-check", "--no-cache-dir", source], env=dict(env, FIBRODEM_CMAKE_BUILD_DIR=build))
        with open(os.path.join(scratch, "scene.json"), "w") as f:
            json.dump(SCENE, f)
        with open(os.path.join(scratch, "check.py"), "w") as f:
            f.write(CHECK)
        run([python, "check.py", venv], env=env, cwd=scratch)


if __name__ == "__main__":
    main(os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]))
