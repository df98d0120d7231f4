# SPDX-License-Identifier: BSD-3-Clause
"""The package's version and parts, and an installation whose halves do not match (issue 36)."""
import os
import shutil
import subprocess
import sys

import vrsph


def test_version_and_parts():
    assert vrsph.__version__.count(".") == 2
    names = [p["name"] for p in vrsph.parts()]
    assert names == ["PETSC", "MPI", "CGAL", "CLP", "SUITESPARSE", "MUPARSER", "VTK_XML", "JSON", "TOML", "OPENMP"]
    assert all(p["licence"] and p["packages"] for p in vrsph.parts())
    assert issubclass(vrsph.FeatureUnavailable, vrsph.ConfigError)


def test_a_compiled_core_of_another_version_is_refused_by_name(tmp_path):
    package = os.path.dirname(vrsph.__file__)
    copy = tmp_path / "vrsph"
    shutil.copytree(package, copy, ignore=shutil.ignore_patterns("__pycache__"))
    (copy / "_version.py").write_text('__version__ = "0.0.1"\nbuilt_for_python = "3.11"\n')
    p = subprocess.run([sys.executable, "-c", "import vrsph"], cwd=tmp_path, capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(tmp_path)))
    assert p.returncode != 0
    assert "the Python package is version 0.0.1 but its compiled core" in p.stderr
    assert vrsph.__version__ in p.stderr


def test_a_missing_compiled_core_names_the_interpreter(tmp_path):
    package = os.path.dirname(vrsph.__file__)
    copy = tmp_path / "vrsph"
    shutil.copytree(package, copy, ignore=shutil.ignore_patterns("__pycache__", "_vrsph*.so"))
    p = subprocess.run([sys.executable, "-c", "import vrsph"], cwd=tmp_path, capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(tmp_path)))
    assert p.returncode != 0
    assert "cannot load its compiled core" in p.stderr and "this package was built for Python" in p.stderr
