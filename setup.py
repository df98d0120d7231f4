# SPDX-License-Identifier: BSD-3-Clause
"""The wheel's build: setuptools (PEP 517, pyproject.toml) runs vrsph's CMake for the compiled
core `vrsph._vrsph` and the `vrsph` command, then packs them with the pure-Python files.

CMake runs in build/wheel (kept, so a second build is incremental). VRSPH_CMAKE_ARGS adds
configure options, e.g. "-DVRSPH_WITH_CGAL=OFF -DVRSPH_WITH_SUITESPARSE=OFF" for a wheel
without the GPL-licensed parts. VRSPH_CMAKE_BUILD_DIR names an existing, configured build
directory to take the targets from instead (the `package_wheel` test packs its own build).
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    """The one version string: CMake's project(vrsph VERSION ...)."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    return re.search(r"project\(vrsph VERSION ([0-9]+\.[0-9]+\.[0-9]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        for tool in ("cmake", "ninja"):
            if shutil.which(tool) is None:
                sys.exit(f"vrsph: building the wheel needs {tool}: apt-get install cmake ninja-build "
                         "(scripts/setup.sh installs every build dependency)")
        given = os.environ.get("VRSPH_CMAKE_BUILD_DIR")
        build = Path(given).resolve() if given else ROOT / "build" / "wheel"
        package = Path(self.get_ext_fullpath(ext.name)).resolve().parent  # <build_lib>/vrsph
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                     f"-DPython3_EXECUTABLE={sys.executable}", "-DVRSPH_BUILD_TESTS=OFF", "-DVRSPH_BUILD_BENCH=OFF",
                     "-DVRSPH_BUILD_PYTHON=ON", "-DVRSPH_BUILD_CLI=ON",
                     *shlex.split(os.environ.get("VRSPH_CMAKE_ARGS", ""))]
        if not given:
            subprocess.run(configure, check=True)
        jobs = str(os.cpu_count() or 2)
        subprocess.run(["cmake", "--build", str(build), "-j", jobs, "--target", "_vrsph", "vrsph_python_files",
                        "vrsph_cli"], check=True)
        # The package as CMake lays it out (pure-Python files, _version.py, the compiled core).
        shutil.copytree(build / "python" / "vrsph", package, dirs_exist_ok=True)
        # The command and the plot scripts it runs, as an installed prefix would hold them.
        command = package / "_cli" / "bin"
        command.mkdir(parents=True, exist_ok=True)
        shutil.copy2(build / "apps" / "vrsph" / "vrsph", command / "vrsph")
        share = package / "_cli" / "share" / "vrsph"
        share.mkdir(parents=True, exist_ok=True)
        for script in (ROOT / "share").glob("plot_*.py"):
            shutil.copy2(script, share / script.name)


setup(
    version=project_version(),
    packages=["vrsph"],
    package_dir={"vrsph": "python/vrsph"},
    package_data={"vrsph": ["*.pyi", "py.typed"]},
    ext_modules=[Extension("vrsph._vrsph", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
