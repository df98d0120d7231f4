# SPDX-License-Identifier: BSD-3-Clause
"""Shared fixtures: the CLI binary (VRSPH_CLI, set by CTest) for equality checks."""
import json
import os
import subprocess

import pytest

import vrsph

BUILT = {part["name"] for part in vrsph.parts() if part["built"]}


def needs(*parts):
    """Skips a test of a feature of optional parts this build lacks (vrsph.parts())."""
    missing = [p for p in parts if p not in BUILT]
    return pytest.mark.skipif(bool(missing), reason=f"vrsph built without {', '.join(missing)}")


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("VRSPH_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("VRSPH_CLI is not set (CTest sets it)")

    def run(*args):
        p = subprocess.run([path, *args], capture_output=True, text=True, timeout=600)
        assert p.returncode == 0, p.stderr
        return json.loads(p.stdout) if "--format" in args and "json" in args else p.stdout

    return run
