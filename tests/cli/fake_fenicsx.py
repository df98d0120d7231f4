#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""A stand-in for ../shared/anchors/fenicsx_ex5.py with the same command line and output, for
the CLI tests of `bench solve --anchor` and `bench accuracy` on machines without FEniCSx.
Its error is a known function of the mesh: max error = (k n)^-(k+1) for Pk on n cells per
direction; nodes (k n + 1)^d; 1e-7 s per node. FAKE_FENICSX_FAIL=message makes it fail
with that message on stderr; FAKE_FENICSX_GARBAGE=1 prints a line that is not JSON.
"""
import json
import os
import sys

args = sys.argv[1:]
degree, dim, points = 1, 2, None
for flag in ("--degree", "--dim", "--points"):
    if flag in args:
        k = args.index(flag)
        value = args[k + 1]
        del args[k:k + 2]
        if flag == "--degree":
            degree = int(value)
        elif flag == "--dim":
            dim = int(value)
        else:
            points = value
if os.environ.get("FAKE_FENICSX_FAIL"):
    print(os.environ["FAKE_FENICSX_FAIL"], file=sys.stderr)
    sys.exit(1)
if os.environ.get("FAKE_FENICSX_GARBAGE"):
    print("{not json")
    sys.exit(0)
sizes = [int(a) for a in args if not a.startswith("--")]
if points is not None:
    with open(points) as fh:
        count = sum(1 for _ in fh) - 1  # header
    n = round(count ** (1 / dim)) - 1
    sizes = [n]
for n in sizes:
    nodes = (degree * n + 1) ** dim
    error = float(degree * n) ** -(degree + 1)
    print(json.dumps(dict(peer=f"fenicsx-p{degree}", degree=degree, dim=dim, ranks=1, n=None if points else n,
                          nodes=nodes, error_inf=error, total=1e-7 * nodes, iterations=7, reason=2)), flush=True)
