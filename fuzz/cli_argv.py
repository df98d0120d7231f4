#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Grammar-based fuzzing of the whole vrsph argument vector.

Draws random command lines from every subcommand's options, mixing valid values with
hostile ones (empty, NaN, huge, negative, junk, wrong types), and runs them with a time
limit. A finding is a signal (crash), exit 70 (internal error), an exit code outside the
documented set, exit 0 with an error message, a Python traceback, or a run exceeding the
limit on a command line that is small by construction.

Usage: cli_argv.py PATH_TO_VRSPH [--seconds S | --runs N] [--seed K] [--jobs J] [--timeout T]
Reproducers of findings are printed as shell command lines; the exit status is 1 if any.
"""
import argparse
import os
import random
import shlex
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

HOSTILE_NUMBERS = ["", "nan", "inf", "-inf", "-1", "0", "1e308", "1e-308", "abc", "1e30", "2.5x", "0x10", "-0",
                   "99999999999999999999", "1,2", " "]
EXPRESSIONS = ["x", "sin(pi*x)*sin(pi*y)", "1/0", "sqrt(-1)", "exp(1000*x)", "x^", "(", "", "1+x*y+z",
               "one-plus-r2", "sin-pi", "log(x)", "x<0.5?1:2", "rnd()", "1e308*x*10", "exp(x)*sin(2*y)"]


def small_int_list(r):
    return ",".join(str(r.choice([2, 3, 4, 5, 6, 8, 10, 12])) for _ in range(r.randint(1, 3)))


def value(r, kind):
    if r.random() < 0.25:
        return r.choice(HOSTILE_NUMBERS)
    if kind == "n":
        return small_int_list(r)
    if kind == "int":
        return str(r.choice([0, 1, 2, 3, 4, 5, 8, 12]))
    if kind == "real":
        return r.choice(["0.1", "0.5", "1", "2", "3", "4", "6", "1e-3", "0.99"])
    if kind == "expr":
        return r.choice(EXPRESSIONS)
    return r.choice(kind)


COMMON_BVP = {
    "--problem": ["qw-ex5", "aar-static", "spe-dirichlet", "spe-mixed", "custom", "nope"], "--dim": "int", "--method":
    ["sph", "vrsph", "fpm", "kgf", "cspm", "sph,vrsph", "mfpm", "fpm2o", "nope", "rkpm1", "m-sph", "s-sph,cb-sph",
     "brookshaw"],
    "--mobility": ["1,2", "1+x*x,2+y", "1,2,3", "1,-1", "1,0/0", "1e300,1", "max(1,y),1", "1,(2", "x"],
    "--layout": ["vertex", "cells", "hex"],
    "--cloud": ["uniform", "perturbed", "centroids", "disk", "nope"], "--seed": "int", "--h-factor": "real",
    "--h-mode": ["fixed", "covering", "knn", "x"], "--h-knn": "int", "--delta": "real",
    "--kernel": ["cubic", "gaussian", "quintic", "wendland-c2", "wendland-c4", "cubic-spe", "box"],
    "--neumann": ["x0", "x1,y1", "all", "w0", "z1"], "--q": "expr", "--u": "expr", "--a": "expr", "--f": "expr",
    "--g": "expr", "--solver": ["sparselu", "umfpack", "bicgstab", "x"], "--on-infeasible": ["warn", "error", "x"],
    "--infeasible-tol": "real", "--regular-layer": "real",
    "--method-opt": ["nnls_tolerance=1e-12", "nnls_max_iterations=0", "volume=shepard", "rows=full", "x=1", "foo",
                     "max_condition=nan", "gradient_order=2", "on_singular=warn", "gradient=g2", "gradient=g9",
                     "anisotropy=paper", "anisotropy=x", "pair_gradient=corrected"],
    "--format": ["md", "csv", "json", "xml"],
}
COMMANDS = {
    "stability": {"--method": ["m-sph", "s-sph,cb-sph", "vrsph", "fpm2o", "nope"], "--dim": "int", "--n": "int",
                  "--cloud": ["uniform", "perturbed", "disk"], "--layout": ["vertex", "cells", "x"], "--tau": "real",
                  "--k": "int", "--h-factor": "real", "--delta": "real", "--xi-statistics": None,
                  "--neighbours": ["4,8", "1", "x"], "--configurations": "int", "--format": ["md", "csv", "json"],
                  "--plot": ["{tmp}/s.png", "{tmp}/s.txt", "/dev/full"]},
    "diffuse": {"--nu": ["0.1", "0.26", "0.1,0.2", "x", "-1"], "--dt": "real", "--t-end": "real",
                "--scheme": ["explicit", "implicit", "cn", "rk4"], "--dx": ["0.1", "0.2", "0.3", "0"],
                "--h-factor": "real", "--allow-unstable": None, "--method": ["m-sph", "vrsph", "fpm", "x"],
                "--history": ["{tmp}/h.csv", "/dev/full"], "--vtu-series": ["{tmp}/p", "/dev/full/x"],
                "--report-times": ["1,2", "0.5", "x"], "--format": ["md", "csv", "json"]},
    "methods": {"--format": ["md", "csv", "json", "x"]},
    "kernels": {},
    "cloud": {"--family": ["uniform", "perturbed", "centroids", "disk", "x"], "--layout": ["vertex", "cells", "x"],
              "--domain": ["unit", "symmetric", "x"], "--dim": "int", "--n": "int", "--ghost-layers": "int",
              "--delta": "real", "--seed": "int", "--h-factor": "real", "--format": ["md", "csv", "json"],
              "--input": ["{fx}/good.csv", "{fx}/far_pair.csv", "{fx}/nul_byte.csv", "{fx}", "{fx}/missing.csv",
                          "{fx}/bom.csv", "{fx}/identical_points.csv", "{fx}/binary.csv"],
              "--output": ["{tmp}/c.csv", "{tmp}/c.vtu", "{tmp}/c.txt", "/dev/full", "{tmp}"], "--check": None,
              "--perturb-boundary": None},
    "operator": {**{k: v for k, v in COMMON_BVP.items() if k not in ("--neumann", "--q", "--f", "--g", "--solver", "--mobility", "--layout",
                                                                      "--on-infeasible", "--infeasible-tol")},
                 "--problem": ["qw-trunc", "unit-box", "aar-derivative", "spe-patch", "x"],
                 "--test": ["r2", "power-sum", "product", "heterogeneous", "x"], "--exponent": "int",
                 "--rotated": None, "--variant": ["m-sph", "s-sph:gradient=g2", "vrsph", "fpm", "x:y=z", "m-sph:foo"],
                 "--operator": ["value", "dx", "dy", "dz", "gradient", "laplacian", "div-a-grad",
                                "second-derivative", "curl"], "--n": "n", "--exact": "expr", "--no-ghosts": None},
    "study": {**COMMON_BVP, "--n": "n", "--seeds": "n", "--fix-constant": None, "--perturb-boundary": None,
              "--output": ["{tmp}/t.md", "/dev/full", "{tmp}"]},
    "solve": {**COMMON_BVP, "--n": "int", "--vtu": ["{tmp}/s.vtu", "/dev/full", "{tmp}", ""],
              "--cloud-file": ["{fx}/good.csv", "{fx}/mixed_cloud.csv", "{fx}/neumann_only_cloud.csv", "{fx}/far_pair.csv",
                               "{fx}/nul_byte.csv", "{fx}/one_point.csv", "{fx}/cloud.vtu", "{fx}/missing.csv", "{fx}"],
              "--h": "real", "--csv": ["{tmp}/s.csv", "/dev/full", "{tmp}"], "--fix-constant": None},
    "spectrum": {"--method": ["fpm2o", "aar-sph", "chen-beraun", "mfpm", "sph", "vrsph", "x"], "--n": "int",
                 "--kernel": ["gaussian", "cubic"], "--h-factor": "real", "--cloud": ["uniform", "perturbed", "disk"],
                 "--delta": "real", "--seed": "int", "--format": ["md", "json"]},
}
DOCUMENTED = {0, 1, 2, 3, 4, 5}


def draw(r, fixtures, tmp):
    cmd = r.choice(list(COMMANDS))
    args = [cmd]
    options = COMMANDS[cmd]
    for opt in r.sample(list(options), k=min(len(options), r.randint(0, 5))):
        kind = options[opt]
        args.append(opt)
        if kind is not None:
            args.append(value(r, kind).replace("{fx}", fixtures).replace("{tmp}", tmp))
    if r.random() < 0.2:
        args.insert(0, "--max-memory")
        args.insert(1, r.choice(["1M", "100M", "0", "lots", "8G"]))
    return args


def check(vrsph, args, timeout, cwd):
    """(exit code or None, problem or None). Runs in cwd (a scratch directory): a drawn value
    such as `--vtu nan` writes a file of that name."""
    try:
        p = subprocess.run([vrsph, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                           errors="replace", timeout=timeout, stdin=subprocess.DEVNULL, cwd=cwd)
    except subprocess.TimeoutExpired:
        return None, f"no answer within {timeout} s"
    rc, err = p.returncode, p.stderr
    if rc < 0:
        return rc, f"killed by signal {-rc}"
    if rc not in DOCUMENTED:
        return rc, f"exit {rc}: {err.strip()[:300]}"
    if rc == 0 and "error" in err.lower() and "warning" not in err.lower():
        return rc, f"exit 0 with an error message: {err.strip()[:300]}"
    if "Traceback" in err:
        return rc, "Python traceback"
    return rc, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("vrsph")
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=60)
    ap.add_argument("--runs", type=int, default=0, help="stop after this many command lines (0: by --seconds)")
    a = ap.parse_args()
    vrsph = os.path.abspath(a.vrsph)  # the runs happen in a scratch directory
    fixtures = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "errors", "fixtures")
    r = random.Random(a.seed)
    findings, runs, codes = [], 0, {}
    deadline = time.time() + a.seconds
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(a.jobs) as pool:
        while (runs < a.runs) if a.runs else (time.time() < deadline):
            batch = [draw(r, os.path.normpath(fixtures), tmp) for _ in range(4 * a.jobs)]
            for args, (rc, problem) in zip(batch, pool.map(lambda x: check(vrsph, x, a.timeout, tmp), batch)):
                runs += 1
                codes[rc] = codes.get(rc, 0) + 1
                if problem:
                    findings.append((args, problem))
                    print(f"FINDING: vrsph {shlex.join(args)}\n    {problem}", flush=True)
    spread = ", ".join(f"exit {k}: {v}" for k, v in sorted(codes.items(), key=lambda kv: str(kv[0])))
    print(f"cli_argv: {runs} command lines ({spread}), {len(findings)} findings")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
