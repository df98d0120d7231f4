# SPDX-License-Identifier: BSD-3-Clause
"""What the package tests share: a command that must succeed, a fresh work directory, and the
version this build carries."""
import os
import shutil
import subprocess
import sys


def run(cmd, **kw):
    """Runs cmd; on failure ends the test with its command line and the tails of its output."""
    print("+", " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-4000:]}\n{p.stderr[-4000:]}")
    return p.stdout


def fresh(directory):
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)


def build_version(build):
    """The version of the build tree (its generated vrsph/_version.py)."""
    with open(os.path.join(build, "python", "vrsph", "_version.py"), encoding="utf-8") as f:
        return f.read().split('"')[1]
