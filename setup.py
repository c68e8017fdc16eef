"""The build step of `pip install .` (pyproject.toml holds the metadata).

Configures and builds the project with its own CMake, then puts into the
package the extension fibrodem/_core*.so and, in fibrodem/bin/, the
`fibrodem` command line with its run-time modules and plugins, laid out as
the build lays them out (fibrodem/bin/plugins/); the module finds them there
(python/src/module.cpp, cli_dir).

setuptools' build folder is build/pip (a folder of its own inside the CMake
build folder `scripts/setup.sh` makes), where a fresh CMake build goes.
FIBRODEM_CMAKE_BUILD_DIR=DIR builds in that CMake build folder instead
(configured already, or configured now), and setuptools' folder is DIR/pip:
the tests install from the build they test. CMAKE_BUILD_PARALLEL_LEVEL sets
the jobs (default: every core); CMAKE_CXX_COMPILER_LAUNCHER=ccache and the
like reach CMake from the environment."""

import glob
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = os.path.dirname(os.path.abspath(__file__))


def project_version():
    """The version CMakeLists.txt declares, the one the module reports."""
    with open(os.path.join(SOURCE, "CMakeLists.txt")) as f:
        return re.search(r"project\(fibrodem VERSION ([0-9.]+)", f.read()).group(1)


def cached_value(build, name):
    """`name`'s value in build's CMakeCache.txt: "" if it is not there, None if
    the folder is not configured."""
    try:
        with open(os.path.join(build, "CMakeCache.txt")) as f:
            found = re.search(r"^" + name + r":[A-Z]+=(.*)$", f.read(), re.M)
    except FileNotFoundError:
        return None
    return found.group(1) if found else ""


GIVEN_BUILD = os.environ.get("FIBRODEM_CMAKE_BUILD_DIR")
BUILD_BASE = os.path.join(GIVEN_BUILD or "build", "pip")  # setuptools' folder, egg-info too: none in the sources


class CMakeBuild(build_ext):

    def build_extension(self, ext):
        build = os.path.abspath(GIVEN_BUILD or os.path.join(self.build_temp, "cmake"))
        # The interpreter a venv's python links to: the build folder outlives
        # the venv it was first made from, and serves every venv of that Python.
        python = os.path.realpath(sys.executable)
        configured = cached_value(build, "Python_EXECUTABLE")
        if configured is None or (not GIVEN_BUILD and configured != python):
            subprocess.run(["cmake", "-S", SOURCE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                            "-DPython_EXECUTABLE=" + python, "-DFIBRODEM_BUILD_TESTS=OFF"], check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        # fibrodem_python depends on the command line, its plugins and modules.
        subprocess.run(["cmake", "--build", build, "-j", jobs, "--target", "fibrodem_python"], check=True)

        built = os.path.join(build, "python", "fibrodem", "_core" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not os.path.isfile(built):
            found = glob.glob(os.path.join(build, "python", "fibrodem", "_core*.so"))
            sys.exit("setup.py: %s has no %s for this Python (%s)%s" % (
                build, os.path.basename(built), sys.executable,
                ": it has " + ", ".join(map(os.path.basename, found)) + ", built for another Python "
                "(configure it with -DPython_EXECUTABLE=" + sys.executable + ")" if found else ""))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copy2(built, target)
        self.bundle_command_line(build, os.path.join(os.path.dirname(target), "bin"))

    @staticmethod
    def bundle_command_line(build, bin_dir):
        shutil.rmtree(bin_dir, ignore_errors=True)
        os.makedirs(os.path.join(bin_dir, "plugins"))
        shutil.copy2(os.path.join(build, "fibrodem"), bin_dir)
        for module in glob.glob(os.path.join(build, "libfibrodem-*.so")):
            shutil.copy2(module, bin_dir)
        for plugin in glob.glob(os.path.join(build, "plugins", "libfibrodem_*.so")):
            shutil.copy2(plugin, os.path.join(bin_dir, "plugins"))


# The packages here, not in pyproject.toml's [tool.setuptools], which
# Debian 12's setuptools (66) warns is beta.
setup(version=project_version(), package_dir={"": "python"}, packages=["fibrodem"],
      package_data={"fibrodem": ["*.pyi", "py.typed"]}, ext_modules=[Extension("fibrodem._core", sources=[])],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": BUILD_BASE}, "egg_info": {"egg_base": BUILD_BASE}})
