#!/usr/bin/python3
"""Checks model-error-study.py's mode identified_fused (issue 40; SPEC §11 "A free-rocking test first").

    check_identified_fused.py ROCKWATCH TRUTHS STUDY_OUT

For every case of STUDY_OUT/runs.csv with an identified_fused row: runs what a lab would run itself — `rockwatch
identify --wall-sensors snapback.csv --wall-out W.json` (the wall told), then `rockwatch simulate --record ground.csv
--units mps2 --wall-file W.json --alarms --wall-sensors sensors.csv --json` — and checks that the row carries that
run's first IMMINENT and COLLAPSED, its x̂_inst and r̂ at the end and their σ. At least one case must differ from its
fused row (the observer started from the told wall) in one of those figures, else the check could not tell the two
modes apart (a mode that ignored the wall file would pass the rest). Exit 1 naming the case and the field.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

from study_module import study_module

FIELDS = (("t_first_imminent_s", ("alarm", "t_first_imminent_s")),
          ("t_first_collapsed_s", ("alarm", "t_first_collapsed_s")),
          ("x_inst_end", ("observer", "x_inst_estimate_m")),
          ("x_inst_end_sigma", ("observer", "sigma_x_inst_m")),
          ("r_end", ("observer", "r_estimate")),
          ("r_end_sigma", ("observer", "sigma_r")))


def number(text):
    return float(text) if text not in ("", None) else None


def same(a, b):
    return (a is None) == (b is None) and (a is None or abs(a - b) <= 1e-12 * max(1.0, abs(b)))


def main():
    rockwatch, truths, out = sys.argv[1:4]
    rows = list(csv.DictReader(open(os.path.join(out, "runs.csv"))))
    by_mode = {(r["family"], r["case"], r["mode"]): r for r in rows}
    cases = sorted({(r["family"], r["case"]) for r in rows if r["mode"] == "identified_fused"})
    if not cases:
        sys.exit("check_identified_fused: runs.csv has no identified_fused row (run the study with identify)")
    study = study_module()
    bad, differs = [], 0
    for fam, case in cases:
        d = os.path.join(truths, fam, case)
        truth = json.load(open(os.path.join(d, "truth.json")))
        with tempfile.TemporaryDirectory(prefix="check-identified-fused-") as tmp:
            wall = os.path.join(tmp, "wall.json")
            subprocess.run([rockwatch, "identify", "--wall-sensors", os.path.join(d, "snapback.csv"),
                            "--wall-out", wall, "--json"] + study.wall_args(truth),
                           check=True, capture_output=True, text=True)
            run = json.loads(subprocess.run(
                [rockwatch, "simulate", "--record", os.path.join(d, "ground.csv"), "--units", "mps2", "--wall-file",
                 wall, "--alarms", "--wall-sensors", os.path.join(d, "sensors.csv"), "--json"],
                check=True, capture_output=True, text=True).stdout)
        row, fused = by_mode[(fam, case, "identified_fused")], by_mode.get((fam, case, "fused"))
        for field, (section, key) in FIELDS:
            want = (run.get(section) or {}).get(key)
            got = number(row.get(field))
            if not same(got, want):
                bad.append(f"{fam}/{case}: identified_fused {field} {got}, the lab's own run says {want}")
            if fused is not None and not same(number(fused.get(field)), got):
                differs += 1
    for b in bad[:10]:
        print("check_identified_fused:", b, file=sys.stderr)
    if differs == 0:
        print("check_identified_fused: every identified_fused row equals its fused row: the wall file made no "
              "difference (choose cases where it does)", file=sys.stderr)
        bad.append("indistinguishable")
    if bad:
        sys.exit(1)
    print(f"check_identified_fused: {len(cases)} cases, each the lab's own run; {differs} figures differ from fused")


if __name__ == "__main__":
    main()
