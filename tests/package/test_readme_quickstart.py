#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The README's quick starts run exactly as written (issue 36): the shell block with the built
`vrsph` first on PATH, the Python block against the build's package, and the CMake + C++ blocks
as a project of their own, configured with -Dvrsph_DIR=<build dir>, built and run.

usage: test_readme_quickstart.py README VRSPH_BINARY PYTHON_DIR BUILD_DIR"""
import os
import re
import subprocess
import sys
import tempfile
import unittest

README, VRSPH, PYTHON_DIR, BUILD_DIR = sys.argv[1:5]
del sys.argv[1:5]


def blocks():
    text = open(README, encoding="utf-8").read()
    section = text.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    found = {}
    for lang, body in re.findall(r"```(\w+)\n(.*?)```", section, re.S):
        found.setdefault(lang, []).append(body)
    return found


class QuickStart(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.blocks = blocks()

    def test_each_block_is_short(self):
        for lang in ("sh", "python", "cmake", "cpp"):
            self.assertIn(lang, self.blocks)
            for body in self.blocks[lang]:
                self.assertLessEqual(len(body.strip().splitlines()), 10, lang)

    def test_shell(self):
        env = dict(os.environ, PATH=os.path.dirname(os.path.abspath(VRSPH)) + os.pathsep + os.environ["PATH"])
        with tempfile.TemporaryDirectory() as d:
            for body in self.blocks["sh"]:
                p = subprocess.run(["bash", "-e", "-c", body], cwd=d, env=env, capture_output=True, text=True,
                                   timeout=600)
                self.assertEqual(p.returncode, 0, p.stdout[-2000:] + p.stderr[-2000:])
            self.assertTrue(os.path.exists(os.path.join(d, "u.vtu")))
            self.assertTrue(os.path.exists(os.path.join(d, "cloud.csv")))

    def test_python(self):
        env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
        with tempfile.TemporaryDirectory() as d:
            p = subprocess.run([sys.executable, "-c", self.blocks["python"][0]], cwd=d, env=env, capture_output=True,
                               text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stderr)
        error = float(re.search(r"max error ([0-9.e+-]+)", p.stdout).group(1))
        self.assertLess(error, 1e-3)
        self.assertIn("M-matrix True", p.stdout)

    def test_cpp(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "CMakeLists.txt"), "w", encoding="utf-8") as f:
                f.write(self.blocks["cmake"][0])
            with open(os.path.join(d, "main.cpp"), "w", encoding="utf-8") as f:
                f.write(self.blocks["cpp"][0])
            build = os.path.join(d, "build")
            for cmd in (["cmake", "-S", d, "-B", build, f"-Dvrsph_DIR={BUILD_DIR}", "-DCMAKE_BUILD_TYPE=Release"],
                        ["cmake", "--build", build]):
                p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
                self.assertEqual(p.returncode, 0, p.stdout[-3000:] + p.stderr[-3000:])
            p = subprocess.run([os.path.join(build, "my_solver")], capture_output=True, text=True, timeout=300)
        self.assertEqual(p.returncode, 0, p.stderr)
        error = float(re.search(r"max error ([0-9.e+-]+)", p.stdout).group(1))
        self.assertLess(error, 1e-3)
        self.assertIn("M-matrix 1", p.stdout)


if __name__ == "__main__":
    unittest.main()
