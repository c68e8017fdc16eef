"""The `fibrodem` command of an installed package: the command line built
with this module (in fibrodem._core.cli_dir, the package's bin/), run in
place of this process."""

import os
import sys

from . import _core


def main():
    exe = os.path.join(_core.cli_dir, "fibrodem")
    if not os.access(exe, os.X_OK):
        sys.exit("fibrodem: no command line beside the Python module (%s is not an executable file): "
                 "reinstall the package" % exe)
    os.execv(exe, [exe, *sys.argv[1:]])
