#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Issue 31: results do not depend on the length unit, and the memory guard sees ulimit -v.

The same cloud in units 10^-8 ... 10^8 with the same data (u(x) = U(x / s)) must give the
same errors to 1e-10 (relative to the data, which are O(1) here) for every method that solves
boundary value problems, in 1D, 2D and 3D; before, VRSPH's published rows gave 2.6e-7 at s = 1
and 2e-2 at s = 100 for the linear U = x, with a different count of infeasible rows per unit.
Release only (label convergence): ~250 solves, ~1 minute.

Usage: test_units_and_limits.py PATH_TO_VRSPH
"""
import json
import os
import resource
import subprocess
import sys
import tempfile
import unittest

VRSPH = None
SCALES = (1e-8, 1e-3, 1.0, 100.0, 1e8)
METHODS = (("vrsph", "--method-opt", "vrsph:profile=qw"), ("vrsph", "--method-opt", "vrsph:rhs=point"), ("sph",),
           ("fpm",), ("cspm",), ("kgf",), ("m-sph",), ("brookshaw",))
# Per dimension: lattice size, and test functions of xi = x / s with their Laplacians (so that f
# is given exactly, not by finite differences of u, whose round-off is ~1e-10 of f at any
# unit): a linear one, a cubic (the default's compact rows reproduce it exactly), a smooth one.
CASES = {
    1: ("12", [("x", "0"), ("x^3", "6*x"), ("sin(2*x)", "-4*sin(2*x)")]),
    2: ("12", [("x", "0"), ("x^2*y+x*y^2", "2*y+2*x"), ("sin(x)*cos(2*y)", "-5*sin(x)*cos(2*y)")]),
    3: ("6", [("x", "0"), ("x^2*y+y*z^2", "2*y+2*y"), ("sin(x)*cos(y)*z", "-2*sin(x)*cos(y)*z")]),
}


def run(*args, preexec_fn=None):
    p = subprocess.run([VRSPH, *args], capture_output=True, text=True, timeout=600, preexec_fn=preexec_fn,
                       stdin=subprocess.DEVNULL)
    return p


def scaled_cloud(path, source, s):
    with open(source) as f:
        lines = f.read().splitlines()
    head = lines[0].split(",")
    coords = [k for k, name in enumerate(head) if name in ("x", "y", "z")]
    with open(path, "w") as out:
        out.write(lines[0] + "\n")
        for line in lines[1:]:
            cells = line.split(",")
            for k in coords:
                cells[k] = repr(float(cells[k]) * s)
            out.write(",".join(cells) + "\n")


def in_unit(expr, s):
    return expr.replace("x", f"(x/{s!r})").replace("y", f"(y/{s!r})").replace("z", f"(z/{s!r})")


class LengthUnits(unittest.TestCase):
    def clouds(self, work, dim, n):
        base = os.path.join(work, f"c{dim}.csv")
        p = run("cloud", "--family", "perturbed", "--dim", str(dim), "--n", n, "--seed", "3", "--output", base)
        self.assertEqual(p.returncode, 0, p.stderr)
        for s in SCALES:
            scaled_cloud(os.path.join(work, f"c{dim}_{s!r}.csv"), base, s)

    def errors(self, work, dim, method, u, lap=None):
        out = []
        for s in SCALES:
            data = ("--u", in_unit(u, s)) + (("--f", f"({in_unit(lap, s)})/{s!r}^2") if lap else ())
            p = run("solve", "--cloud-file", os.path.join(work, f"c{dim}_{s!r}.csv"), *data, "--method", *method,
                    "--format", "json")
            self.assertEqual(p.returncode, 0, f"{method} {dim}D s={s}: {p.stderr}")
            row = json.loads(p.stdout)["rows"][0]
            out.append((row["error_inf"], row.get("infeasible", 0)))
        return out

    def test_every_method_gives_the_same_errors_in_every_unit(self):
        with tempfile.TemporaryDirectory() as work:
            for dim, (n, functions) in CASES.items():
                self.clouds(work, dim, n)
                for method in METHODS + (("vrsph",),):
                    if dim == 1 and method[0] in ("m-sph", "brookshaw"):
                        continue  # the [SPE] schemes are 2D/3D
                    for u, lap in functions:
                        runs = self.errors(work, dim, method, u, lap)
                        errors, infeasible = [e for e, _ in runs], [k for _, k in runs]
                        with self.subTest(method=" ".join(method), dim=dim, u=u):
                            self.assertLess(max(errors) - min(errors), 1e-10, f"errors per unit {errors}")
                            self.assertEqual(len(set(infeasible)), 1, f"infeasible rows per unit {infeasible}")

    def test_derivatives_of_expressions_step_in_the_clouds_unit(self):
        """f = div(a grad u) from u by finite differences: the step is a fraction of the cloud's
        extent (it was 1e-3 in any unit: at s = 1e-8 a thousand times the domain)."""
        with tempfile.TemporaryDirectory() as work:
            self.clouds(work, 2, "12")
            for method in (("sph",), ("vrsph", "--method-opt", "vrsph:profile=qw")):
                errors = [e for e, _ in self.errors(work, 2, method, "sin(x)*cos(2*y)")]
                with self.subTest(method=" ".join(method)):
                    self.assertLess(max(errors) - min(errors), 1e-7 * max(errors), f"errors per unit {errors}")


class AddressSpaceLimit(unittest.TestCase):
    """Under ulimit -v the guard refuses, with the reason, what would not fit; before, the
    limit went unseen (MemAvailable only) and the run died in std::bad_alloc."""

    def test_a_run_beyond_ulimit_v_is_refused_by_the_guard(self):
        limit = 3 << 30  # the binary maps its libraries in a few hundred MB

        def cap():
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

        p = run("study", "--n", "3000", "--format", "json", preexec_fn=cap)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("resource limit", p.stderr)
        self.assertIn("ulimit -v", p.stderr)  # refused up front, not std::bad_alloc after minutes
        p = run("study", "--n", "20", "--format", "json", preexec_fn=cap)
        self.assertEqual(p.returncode, 0, p.stderr)


if __name__ == "__main__":
    VRSPH = sys.argv.pop(1)
    unittest.main(verbosity=2)
