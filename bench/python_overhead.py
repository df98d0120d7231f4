#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Overhead of the Python face: the same VRSPH Laplacian (neighbour search + stencil) built
from Python (vrsph.stencil, SciPy matrix included) and by the CLI (`vrsph operator`, its
seconds_neighbours + seconds_stencil), in one run, on the same perturbed cloud.

Usage: PYTHONPATH=build/release/python python3 bench/python_overhead.py build/release/apps/vrsph/vrsph [n] [repeat]
"""
import json
import subprocess
import sys
import time

import vrsph


def main() -> int:
    cli, n = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    repeat = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    cloud = vrsph.cloud.perturbed(dim=2, n=n, seed=1)
    py, cpp = [], []
    for _ in range(repeat):  # interleaved, so that machine noise hits both alike
        t = time.perf_counter()
        L = vrsph.stencil(cloud, method="vrsph", operator="laplacian", h_factor=3)
        py.append(time.perf_counter() - t)
        out = subprocess.run([cli, "operator", "--problem", "qw-trunc", "--method", "vrsph", "--cloud", "perturbed",
                              "--no-ghosts", "--n", str(n), "--seed", "1", "--format", "json"],
                             capture_output=True, text=True, check=True).stdout
        row = json.loads(out)["rows"][0]
        cpp.append(row["seconds_neighbours"] + row["seconds_stencil"])
    print(f"| N | python s (best of {repeat}) | CLI s (best of {repeat}) | ratio | nnz |")
    print("|---|---|---|---|---|")
    print(f"| {len(cloud)} | {min(py):.3f} | {min(cpp):.3f} | {min(py) / min(cpp):.3f} | {L.nnz} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
