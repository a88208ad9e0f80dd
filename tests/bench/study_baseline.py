#!/usr/bin/env python3
"""The "straightforward implementation" of the default study, for docs/BENCHMARKS.md: the same 1760 analyses as
`rockwatch study` (22 suite records x 20 PGA levels x r ana/exp x without/with vertical), each one a
`rockwatch simulate --json` process started from Python, one after the other.

Usage: study_baseline.py ROCKWATCH SUITE_DIR [RUNS_CSV]
Prints the wall time and the number of collapses; with RUNS_CSV (a `rockwatch study` runs.csv of the same plan)
also the number of verdicts that differ (must be 0: both call the same engine).
"""
import csv
import json
import subprocess
import sys
import time


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    tool, suite = sys.argv[1], sys.argv[2]
    levels = [round(0.11 + 0.01 * i, 2) for i in range(20)]
    verdicts = {}
    start = time.monotonic()
    for vertical in (False, True):
        for r in ("ana", "exp"):
            for s in range(1, 12):
                for component in ("X", "Y"):
                    for pga in levels:
                        args = [tool, "simulate", "--suite", suite, "--set", str(s), "--component", component,
                                "--r", r, "--scale-pga", repr(pga), "--json"]
                        if vertical:
                            args.append("--vertical-from-suite")
                        out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
                        j = json.loads(out)
                        verdicts[(vertical, r, s, component, pga)] = j["collapsed"] or j["collapse_after_end"]
    elapsed = time.monotonic() - start
    print(f"analyses {len(verdicts)}  collapses {sum(verdicts.values())}  wall time {elapsed:.2f} s")
    if len(sys.argv) > 3:
        differ = 0
        with open(sys.argv[3], newline="") as f:
            for row in csv.DictReader(f):
                key = (row["vertical"] in ("true", "1", "with"), row["r"], int(row["record"].lstrip("set")),
                       row["component"], round(float(row["pga_g"]), 2))
                if key in verdicts and verdicts[key] != (row["collapsed"] in ("true", "1")):
                    differ += 1
        print(f"verdicts that differ from {sys.argv[3]}: {differ}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
