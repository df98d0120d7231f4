#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Markdown summary of `vrsph bench accuracy --format json`: one row per target, per
configuration the unknowns and seconds of its smallest run that reached the target ("—" where
it did not, with the reason below the table), and the ratio of vrsph's fastest configuration to
the fastest peer (below 1: vrsph reaches the target sooner).

Usage: accuracy_table.py RESULT.json [RESULT.json ...]
"""
import json
import sys


def summary(path):
    with open(path, encoding="utf-8") as fh:
        doc = json.load(fh)
    rows = doc["rows"]
    configs = list(dict.fromkeys(r["configuration"] for r in rows))
    meshes = {r["configuration"]: r.get("mesh", "") for r in rows}
    out = [f"### {doc['dim']}D {doc['cloud']}, vrsph threads {doc['threads']}, peer ranks {doc.get('anchor_ranks', '-')}"
           f" (peer mesh: {', '.join(f'{c}: {meshes[c]}' for c in configs if c.startswith('fenicsx'))})", ""]
    out.append("| target | " + " | ".join(configs) + " | best vrsph / best peer |")
    out.append("|---" * (len(configs) + 2) + "|")
    reasons = {}
    for t in doc["targets"]:
        cells, best_v, best_p = [], None, None
        for c in configs:
            r = next(x for x in rows if x["target"] == t and x["configuration"] == c)
            if r["status"] != "reached":
                cells.append("—")
                reasons.setdefault(c, (t, r["status"]))
                continue
            cells.append(f"{r['N']:,} / {r['seconds']:.3g} s")
            if c.startswith("fenicsx"):
                best_p = r["seconds"] if best_p is None else min(best_p, r["seconds"])
            else:
                best_v = r["seconds"] if best_v is None else min(best_v, r["seconds"])
        ratio = f"{best_v / best_p:.2f}" if best_v and best_p else "—"
        out.append(f"| {t:g} | " + " | ".join(cells) + f" | {ratio} |")
    out.append("")
    for c, (t, why) in reasons.items():
        out.append(f"- {c} from {t:g}: {why}")
    return "\n".join(out)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    print("\n\n".join(summary(p) for p in sys.argv[1:]))
