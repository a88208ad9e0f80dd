#!/usr/bin/env python3
"""Two studies of one plan compared: what a change of the engine moved (docs/BENCHMARKS.md, "The chatter rule").

  study_diff.py STUDY_DIR REFERENCE_STUDY_DIR

Both directories are `rockwatch study --out` results of the same plan. Prints the runs, the verdicts (`collapsed`)
that differ, the survivors (in both) whose max |x| moved by more than 0.5 mm and the largest move, and per case the
Table 3 figures of summary.json side by side (minimum collapse PGA, the paper's normal-fit mean and sd) with the
largest change of a mean.
"""
import csv
import json
import os
import sys


def runs(study):
    path = os.path.join(study, "runs.csv")
    with open(path, newline="") as f:
        rows = {tuple(r.get(k, "") for k in ("wall", "record", "component", "vertical", "r", "pga_g")): r
                for r in csv.DictReader(f)}
    if not rows:
        sys.exit(f"study_diff: {path}: no runs")
    return rows


def cases(study):
    path = os.path.join(study, "summary.json")
    with open(path) as f:
        summary = json.load(f)
    out = {}
    for c in summary.get("cases", []):
        out[c["title"]] = (c.get("min_pga_collapse_g"), c.get("fit_mean_g"), c.get("fit_std_g"))
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, b = runs(sys.argv[1]), runs(sys.argv[2])
    if a.keys() != b.keys():
        sys.exit("study_diff: the two studies do not have the same plan")
    flips = [k for k in a if a[k]["collapsed"] != b[k]["collapsed"]]
    moved, worst = 0, (0.0, None)
    for k in a:
        if a[k]["collapsed"] == "false" and b[k]["collapsed"] == "false":
            d = abs(float(a[k]["max_abs_x_m"]) - float(b[k]["max_abs_x_m"]))
            moved += d > 0.5e-3
            if d > worst[0]:
                worst = (d, k)
    print(f"runs {len(a)}; verdicts that differ {len(flips)}; survivors moved > 0.5 mm {moved}; "
          f"largest move {worst[0] * 1e3:.3f} mm {' '.join(worst[1]) if worst[1] else ''}")
    for k in flips:
        print("  flip", " ".join(k), f"{b[k]['collapsed']} -> {a[k]['collapsed']}")
    ca, cb = cases(sys.argv[1]), cases(sys.argv[2])
    biggest = 0.0
    for name in cb:
        new, ref = ca.get(name, (None,) * 3), cb[name]
        fmt = lambda v: "-" if v is None else f"{v:.4f}"
        print(f"  {name}: min PGA {fmt(ref[0])} -> {fmt(new[0])} g, mean {fmt(ref[1])} -> {fmt(new[1])} g, "
              f"sd {fmt(ref[2])} -> {fmt(new[2])} g")
        if new[1] is not None and ref[1] is not None:
            biggest = max(biggest, abs(new[1] - ref[1]))
    print(f"largest change of a Table 3 mean: {biggest:.4f} g")


if __name__ == "__main__":
    main()
