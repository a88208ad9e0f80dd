#!/usr/bin/python3
"""The ensemble forecast from the fused state, measured (issue 29 with issue 27's observer; docs/BENCHMARKS.md
"Forecast from the fused state").

A true wall that differs from its drawings (default: 10 % thinner, --b 0.09) under five real records at nine PGA
levels; its transducer written by `rockwatch simulate --sensors-out` (0.5 mm noise, the record's rate, seed 1), then
fused with the nominal paper wall by `rockwatch simulate --wall-sensors ... --alarms --forecast-members 200
--forecast-horizon-s 3` (a forecast every 0.1 s). Scored against the true wall's own run: a forecast's outcome is the
true wall's collapse within (t, t + 3 s].

    scripts/forecast-with-sensors.py [--rockwatch build/release/host_tools/rockwatch] [--wall "--b 0.09"] [--out DIR]

Prints: the Brier score of the calibrated and the raw P; for the runs in which the true wall collapses, the median
lead of the first P >= 0.5 (calibrated, raw) and of IMMINENT; for the survivors, how many ever reach P >= 0.5 or
IMMINENT. Deterministic. Run it with the build of another commit to compare (the numbers in BENCHMARKS).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

RECORDS = ["RSN6_IMPVALL.I_I-ELC180-hor1", "RSN6_IMPVALL.I_I-ELC270-hor2", "RSN960_NORTHR_LOS270",
           "RSN175_IMPVALL.H_H-E12140", "RSN4346_UBMARCHE.P_A-BEV000"]
PGAS_G = ["0.1", "0.12", "0.13", "0.14", "0.15", "0.16", "0.2", "0.24", "0.28"]
HORIZON_S = 3.0


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"forecast-with-sensors: {' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}")
    return json.loads(p.stdout)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rockwatch", default=os.path.join(here, "..", "build", "release", "host_tools", "rockwatch"))
    ap.add_argument("--wall", default="--b 0.09", help="the true wall's options (simulate's wall options)")
    ap.add_argument("--out", help="keep the sensor files and JSON here (default: a temporary directory)")
    a = ap.parse_args()
    records_dir = os.path.join(here, "..", "tests", "data", "records")
    out = a.out or tempfile.mkdtemp(prefix="forecast-with-sensors-")
    os.makedirs(out, exist_ok=True)
    brier_cal, brier_raw = [], []
    lead_cal, lead_raw, lead_imminent = [], [], []
    survivors = crossed_cal = crossed_raw = crossed_imminent = 0
    total = len(RECORDS) * len(PGAS_G)
    for i, rec in enumerate(RECORDS):
        for j, pga in enumerate(PGAS_G):
            n = i * len(PGAS_G) + j + 1
            if sys.stderr.isatty():
                print(f"\r[{n}/{total}] {rec} {pga} g", end="", file=sys.stderr, flush=True)
            base = [a.rockwatch, "simulate", "--record", os.path.join(records_dir, rec + ".AT2"), "--scale-pga", pga]
            csv_path = os.path.join(out, f"truth_{rec}_{pga}.csv")
            truth = run(base + a.wall.split() + ["--sensors-out", csv_path, "--json"])
            fused = run(base + ["--wall-sensors", csv_path, "--alarms", "--forecast-members", "200",
                                "--forecast-horizon-s", str(HORIZON_S), "--json"])
            with open(os.path.join(out, f"fused_{rec}_{pga}.json"), "w") as f:
                json.dump(fused, f)
            collapses = truth["collapsed"] or truth.get("collapse_after_end", False)
            tc = truth.get("t_collapse_s") if collapses else None
            series = fused["forecast"]["series"]
            for e in series:
                y = 1.0 if tc is not None and e["t_s"] < tc <= e["t_s"] + HORIZON_S else 0.0
                brier_raw.append((e["p_collapse"] - y) ** 2)
                brier_cal.append((e["p_collapse_calibrated"] - y) ** 2)
            first_cal = next((e["t_s"] for e in series if e["p_collapse_calibrated"] >= 0.5), None)
            first_raw = next((e["t_s"] for e in series if e["p_collapse"] >= 0.5), None)
            imminent = fused["alarm"].get("t_first_imminent_s")
            if tc is None:
                survivors += 1
                crossed_cal += first_cal is not None
                crossed_raw += first_raw is not None
                crossed_imminent += imminent is not None
            else:
                for lst, t in ((lead_cal, first_cal), (lead_raw, first_raw), (lead_imminent, imminent)):
                    if t is not None:
                        lst.append(tc - t)
    if sys.stderr.isatty():
        print("", file=sys.stderr)
    collapsed = total - survivors
    print(f"true wall {a.wall}: {total} runs, {collapsed} collapse, {survivors} survive; {len(brier_cal)} forecasts")
    print(f"Brier: calibrated {statistics.mean(brier_cal):.4f}, raw {statistics.mean(brier_raw):.4f}")
    for name, lead, crossed in (("calibrated P >= 0.5", lead_cal, crossed_cal), ("raw P >= 0.5", lead_raw, crossed_raw),
                                ("IMMINENT", lead_imminent, crossed_imminent)):
        med = f"{statistics.median(lead):.2f} s" if lead else "-"
        print(f"{name:20s} collapses caught {len(lead)}/{collapsed}, median lead {med}; "
              f"survivors reaching it {crossed}/{survivors}")
    print(f"(files in {out})")


if __name__ == "__main__":
    main()
