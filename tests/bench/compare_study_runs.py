#!/usr/bin/env python3
"""Two studies of the same plan compared run by run (docs/BENCHMARKS.md, "Sub-steps, the worst sample and the alarm").

  compare_study_runs.py RUNS_CSV REFERENCE_RUNS_CSV

Both runs.csv files are written by `rockwatch study` with the same plan (e.g. the same command at two --max-step
values). Prints the number of runs, the verdicts (`collapsed`) that differ, and over the runs that survive in both
with a reference max |x| > 0 the relative error of max |x| against the reference: median and p90 (nearest rank).
"""
import csv
import math
import sys


def key(row):
    return tuple(row.get(k, "") for k in ("wall", "record", "component", "vertical", "r", "pga_g"))


def read(path):
    with open(path, newline="") as f:
        rows = {key(r): r for r in csv.DictReader(f)}
    if not rows:
        sys.exit(f"compare_study_runs: {path}: no runs")
    return rows


def nearest_rank(sorted_values, q):
    return sorted_values[max(0, math.ceil(q * len(sorted_values)) - 1)]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip())
    runs, reference = read(sys.argv[1]), read(sys.argv[2])
    if runs.keys() != reference.keys():
        sys.exit("compare_study_runs: the two studies do not have the same runs (not the same plan)")
    differ = sum(runs[k]["collapsed"] != reference[k]["collapsed"] for k in runs)
    errors = sorted(
        abs(float(runs[k]["max_abs_x_m"]) - float(reference[k]["max_abs_x_m"])) / float(reference[k]["max_abs_x_m"])
        for k in runs
        if runs[k]["collapsed"] == "false" and reference[k]["collapsed"] == "false"
        and float(reference[k]["max_abs_x_m"]) > 0)
    print(f"runs {len(runs)}, verdicts that differ {differ}; survivors' max |x| ({len(errors)}) against the reference: "
          f"median {100 * nearest_rank(errors, 0.5):.3f} %, p90 {100 * nearest_rank(errors, 0.9):.1f} %")


if __name__ == "__main__":
    main()
