# SPDX-License-Identifier: BSD-3-Clause
"""The `vrsph` command of a pip-installed package: runs the CLI binary the wheel carries."""
import os
import sys
from pathlib import Path


def main():
    binary = Path(__file__).resolve().parent / "_cli" / "bin" / "vrsph"
    if not binary.exists():
        sys.exit("vrsph: this installation has no command-line tool (it was built without the wheel's "
                 "_cli/bin/vrsph); use the one of your CMake build or the Debian package")
    os.execv(str(binary), [str(binary), *sys.argv[1:]])


if __name__ == "__main__":
    main()
