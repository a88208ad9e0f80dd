#!/usr/bin/python3
"""Checks model-error-study.py --control (issue 40; SPEC §11 "The odds and the lead, and whose error it is").

    check_forecast_control.py ROCKWATCH TRUTHS STUDY_OUT

For every case of STUDY_OUT/forecasts_control.csv: runs the control itself (rockwatch simulate on the case's
ground.csv, the wall told, --r the truth's r_equiv, --json) to get *that run's own* collapse time, and checks every
control forecast's outcome against it (collapse in (t, t + H]) — not against the truth's collapse, which is what the
fused forecasts are scored by — and that the case's `control` row of runs.csv carries that collapse and the run's
first IMMINENT, its lead the difference. At least one case must have a different outcome under the two (else the
check could not tell them apart). Then recomputes the control's pooled Brier score from the CSV and compares it with summary.json.
Exit 1 naming the case and time on a mismatch.
"""
import csv
import json
import os
import subprocess
import sys

from study_module import study_module


def main():
    rockwatch, truths, out = sys.argv[1:4]
    summary = json.load(open(os.path.join(out, "summary.json")))
    horizon = float(summary["settings"]["forecast_horizon_s"])
    rows = list(csv.DictReader(open(os.path.join(out, "forecasts_control.csv"))))
    runs = {(r["family"], r["case"]): r for r in csv.DictReader(open(os.path.join(out, "runs.csv")))
            if r["mode"] == "control"}
    if not rows:
        sys.exit("check_forecast_control: forecasts_control.csv is empty")
    bad, differs = [], 0
    study = study_module()
    for fam, case in sorted({(r["family"], r["case"]) for r in rows}):
        d = os.path.join(truths, fam, case)
        truth = json.load(open(os.path.join(d, "truth.json")))
        cmd = [rockwatch, "simulate", "--record", os.path.join(d, "ground.csv"), "--units", "mps2", "--json",
               "--r", repr(float(truth["r_equiv"]))] + study.wall_args(truth)
        run = json.loads(subprocess.run(cmd + ["--alarms"], check=True, capture_output=True, text=True).stdout)
        own = run.get("t_collapse_s")
        row = runs.get((fam, case))
        imminent = (run.get("alarm") or {}).get("t_first_imminent_s")
        want_row = (own, imminent, own - imminent if own is not None and imminent is not None else None)
        got_row = tuple(float(row[k]) if row and row[k] != "" else None
                        for k in ("t_collapse_true_s", "t_first_imminent_s", "lead_s")) if row else None
        if got_row is None or any((a is None) != (b is None) or (a is not None and abs(a - b) > 1e-9)
                                  for a, b in zip(got_row, want_row)):
            bad.append(f"{fam}/{case}: runs.csv control row (t_collapse, IMMINENT, lead) {got_row}, "
                       f"the run says {want_row}")
        tc_truth = truth["t_collapse_s"] if truth["collapsed"] else None
        for r in (r for r in rows if r["family"] == fam and r["case"] == case):
            t = float(r["t_s"])
            want = int(own is not None and t < own <= t + horizon)
            by_truth = int(tc_truth is not None and t < tc_truth <= t + horizon)
            differs += want != by_truth
            if int(r["outcome"]) != want:
                bad.append(f"{fam}/{case} t {t}: outcome {r['outcome']}, the control run's own collapse at {own} "
                           f"says {want}")
    for b in bad[:10]:
        print("check_forecast_control:", b, file=sys.stderr)
    if differs == 0:
        print("check_forecast_control: no forecast whose outcome differs between the control's own collapse and the "
              "truth's: choose cases where they differ", file=sys.stderr)
        bad.append("indistinguishable")
    pairs = [(float(r["p_collapse"]), int(r["outcome"])) for r in rows]
    brier = sum((p - o) ** 2 for p, o in pairs) / len(pairs)
    # Every family's forecasts together: the one family's entry, or "all" for several.
    fams = {r["family"] for r in rows}
    pooled = summary["families"].get(next(iter(fams)) if len(fams) == 1 else "all") or {}
    ctl = (pooled.get("forecast_control") or {}).get("raw") or {}
    if ctl.get("forecasts") != len(pairs) or abs(ctl.get("brier", -1) - brier) > 1e-12:
        bad.append(f"summary.json control raw: {ctl.get('forecasts')} forecasts, Brier {ctl.get('brier')}; "
                   f"the CSV: {len(pairs)}, {brier}")
        print("check_forecast_control:", bad[-1], file=sys.stderr)
    if bad:
        sys.exit(1)
    print(f"check_forecast_control: {len(rows)} control forecasts scored by their own run's collapse "
          f"({differs} of them would be scored otherwise by the truth's); Brier {brier:.4f} as summary.json says")


if __name__ == "__main__":
    main()
