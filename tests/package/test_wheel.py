#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The wheel (issue 36): `pip wheel --no-build-isolation` packs this build's module and command
(setup.py, VRSPH_CMAKE_BUILD_DIR); the wheel installs into a fresh virtual environment
(`python3 -m venv --system-site-packages`: Debian's numpy and scipy), `import vrsph` works from
outside the source tree with the installed package (not the build's), the `vrsph` command runs,
and the Python test suite passes against the installed package.

usage: test_wheel.py SOURCE_DIR BUILD_DIR WORK_DIR"""
import glob
import os
import shutil
import sys

from package_util import build_version, fresh, run

SOURCE, BUILD, WORK = (os.path.abspath(a) for a in sys.argv[1:4])


fresh(WORK)
env = dict(os.environ, VRSPH_CMAKE_BUILD_DIR=BUILD)
env.pop("PYTHONPATH", None)
python = "/usr/bin/python3"  # Debian's, with pip, venv, numpy and scipy
run([python, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "--wheel-dir", os.path.join(WORK, "dist"),
     SOURCE], env=env, cwd=WORK)
wheels = glob.glob(os.path.join(WORK, "dist", "vrsph-*.whl"))
assert len(wheels) == 1, wheels
version = build_version(BUILD)
assert os.path.basename(wheels[0]).startswith(f"vrsph-{version}-"), (wheels[0], version)
venv = os.path.join(WORK, "venv")
run([python, "-m", "venv", "--system-site-packages", venv])
vpython = os.path.join(venv, "bin", "python")
run([vpython, "-m", "pip", "install", "--no-index", "--no-deps", wheels[0]], cwd=WORK)
clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VRSPH_CLI")}
where = run([vpython, "-c", "import vrsph, sys; print(vrsph.__file__); print(vrsph.__version__); "
             "print(vrsph.solve(vrsph.cloud.perturbed(dim=2, n=20, seed=1), u='x*y+exp(x)').error_inf)"],
            cwd=WORK, env=clean).split()
assert where[0].startswith(venv), f"imported {where[0]}, not the installed package"
assert where[1] == version, where
assert float(where[2]) < 1e-3, where
out = run([os.path.join(venv, "bin", "vrsph"), "--version"], cwd=WORK, env=clean)
assert out.startswith(f"vrsph {version} "), out
# The Python suite against the installed package (its CLI comparisons with the wheel's command).
# (copied with the examples they run, so nothing is imported from the source tree)
tests = os.path.join(WORK, "tree", "python", "tests")
shutil.copytree(os.path.join(SOURCE, "python", "tests"), tests)
shutil.copytree(os.path.join(SOURCE, "examples", "python"), os.path.join(WORK, "tree", "examples", "python"))
clean["VRSPH_CLI"] = os.path.join(venv, "lib", f"python{sys.version_info.major}.{sys.version_info.minor}",
                                  "site-packages", "vrsph", "_cli", "bin", "vrsph")
clean["MPLBACKEND"] = "Agg"
run([vpython, "-m", "pytest", "-q", "-p", "no:cacheprovider", tests], cwd=WORK, env=clean)
print(f"wheel {os.path.basename(wheels[0])}: installed, imported from {where[0]}, Python tests passed")
