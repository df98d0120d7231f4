#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Adds data columns to a cloud CSV (x,y,...): a layered coefficient k (1 below y = 0.5, 100
above, a smooth step of width 0.05), a unit source src = -1 and wall values g = 0.
Usage: add_columns.py IN.csv OUT.csv"""
import csv
import math
import sys

with open(sys.argv[1], encoding="utf-8") as f:
    rows = list(csv.DictReader(f))
with open(sys.argv[2], "w", encoding="utf-8", newline="") as f:
    w = csv.writer(f)
    w.writerow(list(rows[0].keys()) + ["k", "src", "g"])
    for r in rows:
        y = float(r["y"])
        k = 1 + 99 * 0.5 * (1 + math.tanh((y - 0.5) / 0.05))
        w.writerow(list(r.values()) + [repr(k), "-1", "0"])
