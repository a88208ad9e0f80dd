#!/usr/bin/python3
"""Identify-then-predict, measured (issue 27 item 4; docs/BENCHMARKS.md "Identification").

For each true wall that differs from its drawings (the paper wall): a snap-back test made with
`rockwatch simulate --x0 --sensors-out` (200 Hz transducer, 0.5 mm noise, 2 mm offset), identified with
`rockwatch identify --wall-out`, then the identified wall's verdicts over the default study's records
(`rockwatch study --vertical without`, 22 records x 20 PGA levels) against the true wall's, overall and near
capacity (the runs within 0.02 g of a record's lowest collapse PGA for the true wall).

    scripts/identify-evaluation.py [--rockwatch build/release/host_tools/rockwatch] [--out DIR]

Writes DIR/identify_evaluation.csv and prints a Markdown table. Deterministic (fixed sensor seeds).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

CASES = [
    # name, wall options of the true wall, r of the true wall, release displacement [m]
    ("b x0.85", ["--b", "0.085"], "0.85", "0.045"),
    ("b x0.9", ["--b", "0.09"], "0.85", "0.05"),
    ("b x1.1", ["--b", "0.11"], "0.85", "0.05"),
    ("h1:h2 1.5:2.0", ["--h1", "1.5", "--h2", "2.0"], "0.85", "0.05"),
    ("Fp 2 kN/m", ["--fp", "2000"], "0.85", "0.05"),
    ("Fp 3 kN/m", ["--fp", "3000"], "0.85", "0.05"),
    ("r 0.80", [], "0.8", "0.05"),
    ("r_ana", [], "ana", "0.05"),
]


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stderr)
    return p.stdout


def verdicts(runs_csv):
    out = {}
    with open(runs_csv, newline="") as f:
        for row in csv.DictReader(f):
            out[(row["record"], row["component"], row["pga_g"])] = row["collapsed"] == "true"
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rockwatch", default="build/release/host_tools/rockwatch")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    rw = a.rockwatch
    out_dir = a.out or tempfile.mkdtemp(prefix="identify-evaluation.")
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for seed, (name, wall, r, x0) in enumerate(CASES, start=1):
        d = os.path.join(out_dir, "case%d" % seed)
        os.makedirs(d, exist_ok=True)
        snap = os.path.join(d, "snap.csv")
        truth = json.loads(run([rw, "simulate", "--x0", x0, "--r", r, "--t-end", "8", "--sensors-out", snap,
                                "--sensor-rate-hz", "200", "--sensor-bias-m", "0.002", "--sensor-seed", str(seed),
                                "--json"] + wall))
        wall_json = os.path.join(d, "wall.json")
        t0 = time.perf_counter()
        ident = json.loads(run([rw, "identify", "--wall-sensors", snap, "--json", "--wall-out", wall_json]))
        seconds = time.perf_counter() - t0
        true_study, id_study = os.path.join(d, "study-true"), os.path.join(d, "study-identified")
        run([rw, "study", "--out", true_study, "--vertical", "without", "--r", r, "--force"] + wall)
        run([rw, "study", "--out", id_study, "--vertical", "without", "--wall-file", wall_json, "--force"])
        vt, vi = verdicts(os.path.join(true_study, "runs.csv")), verdicts(os.path.join(id_study, "runs.csv"))
        keys = sorted(vt)
        agree = sum(vt[k] == vi[k] for k in keys)
        # Near capacity: within 0.02 g of the record's lowest collapse PGA (true wall).
        lowest = {}
        for (rec, comp, pga), collapsed in vt.items():
            if collapsed:
                lowest[(rec, comp)] = min(lowest.get((rec, comp), 9.0), float(pga))
        near = [k for k in keys if (k[0], k[1]) in lowest and abs(float(k[2]) - lowest[(k[0], k[1])]) <= 0.02 + 1e-9]
        agree_near = sum(vt[k] == vi[k] for k in near)
        x_inst_true = truth["x_inst_m"]
        rows.append({
            "case": name,
            "r_true": truth["r"],
            "r_identified": ident["r"],
            "r_error": ident["r"] - truth["r"],
            "sigma_r": ident["sigma_r"],
            "x_inst_true_m": x_inst_true,
            "x_inst_identified_m": ident["x_inst_m"],
            "x_inst_error_percent": 100.0 * (ident["x_inst_m"] - x_inst_true) / x_inst_true,
            "sigma_x_inst_m": ident["sigma_x_inst_m"],
            "residual_rms_m": ident["residual_rms_m"],
            "identify_s": seconds,
            "runs": len(keys),
            "verdicts_equal": agree,
            "runs_near_capacity": len(near),
            "verdicts_equal_near_capacity": agree_near,
        })
        print("%-14s r %.4f (true %.4f)  x_inst %+.3f %%  verdicts %d/%d, near capacity %d/%d  (%.2f s)" % (
            name, ident["r"], truth["r"], rows[-1]["x_inst_error_percent"], agree, len(keys), agree_near, len(near),
            seconds), file=sys.stderr)
    with open(os.path.join(out_dir, "identify_evaluation.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("| true wall | r true | r identified (σ) | x_inst error | residual RMS | verdicts equal | near capacity | identify [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for x in rows:
        print("| %s | %.4f | %.4f (%.4f) | %+.3f %% (σ %.3f %%) | %.3f mm | %d/%d | %d/%d | %.2f |" % (
            x["case"], x["r_true"], x["r_identified"], x["sigma_r"], x["x_inst_error_percent"],
            100.0 * x["sigma_x_inst_m"] / x["x_inst_true_m"], 1000.0 * x["residual_rms_m"], x["verdicts_equal"],
            x["runs"], x["verdicts_equal_near_capacity"], x["runs_near_capacity"], x["identify_s"]))
    total = sum(x["runs"] for x in rows)
    equal = sum(x["verdicts_equal"] for x in rows)
    print("\nall cases: %d/%d verdicts equal; output in %s" % (equal, total, out_dir))


if __name__ == "__main__":
    main()
