#!/usr/bin/python3
"""Identify-then-predict, measured (issue 27 item 4; docs/BENCHMARKS.md "Identification").

For each true wall that differs from its drawings (the paper wall): a snap-back test made with
`rockwatch simulate --x0 --sensors-out` (200 Hz transducer, 0.5 mm noise, 2 mm offset), identified with
`rockwatch identify --wall-out`, then the identified wall's verdicts over the default study's records
(`rockwatch study --vertical without`, 22 records x 20 PGA levels) against the true wall's, overall and near
capacity (the runs within 0.02 g of a record's lowest collapse PGA for the true wall).

    scripts/identify-evaluation.py [--rockwatch build/release/host_tools/rockwatch] [--out DIR]

Writes DIR/identify_evaluation.csv and prints a Markdown table. Deterministic (fixed sensor seeds).

    scripts/identify-evaluation.py --forced [--bootstrap N] [--out DIR]

Forced tests instead: four true walls x the shipped suite's sets 1, 3, 5, 7 (component X) x 0.15 and 0.22 g, the
transducer as above (seed = case number); each identified with the record from the paper wall, and again from a
starting wall with the true wall's held fields (h1 : h2, Fp: SPEC 9.1). A case is "ok" when r is within 0.005 and
x_inst within 1 %; records that leave the wall at rest (exit 2, "at rest throughout") are counted apart. Writes
DIR/identify_forced.csv and prints a summary. With --bootstrap N every identification also runs N bootstrap refits
(identify --bootstrap N): the summary then compares |error| / sigma of the curvature's and of the bootstrap's
standard errors.
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


FORCED_WALLS = [
    # name, the true wall's options, r, the held fields a lab would know (the start of the second identification)
    ("b x0.9", ["--b", "0.09"], "0.85", []),
    ("h1:h2 1.5:2.0", ["--h1", "1.5", "--h2", "2.0"], "0.85", ["--h1", "1.5", "--h2", "2.0"]),
    ("Fp 2 kN/m", ["--fp", "2000"], "0.85", ["--fp", "2000"]),
    ("r 0.80", [], "0.8", []),
]
SUITE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sim", "suites", "npr9998-2015")


def forced(rw, out_dir, bootstrap=0):
    rows = []
    case = 0
    for name, wall, r, held in FORCED_WALLS:
        for set_no in (1, 3, 5, 7):
            for pga in ("0.15", "0.22"):
                case += 1
                rec = ["--suite", SUITE, "--set", str(set_no), "--component", "X", "--scale-pga", pga]
                sensors = os.path.join(out_dir, "forced%d.csv" % case)
                truth = json.loads(run([rw, "simulate"] + rec + wall + ["--r", r, "--sensors-out", sensors,
                                        "--sensor-rate-hz", "200", "--sensor-noise-m", "0.0005",
                                        "--sensor-bias-m", "0.002", "--sensor-seed", str(case), "--json"]))
                for start_name, start in (("paper wall", []), ("held fields known", held)):
                    if start_name != "paper wall" and not held:
                        continue
                    t0 = time.perf_counter()
                    boot = ["--bootstrap", str(bootstrap)] if bootstrap else []
                    p = subprocess.run([rw, "identify", "--wall-sensors", sensors, "--json"] + rec + start + boot,
                                       capture_output=True, text=True)
                    seconds = time.perf_counter() - t0
                    row = {"case": case, "wall": name, "set": set_no, "pga_g": pga, "start": start_name,
                           "collapsed": truth["collapsed"], "max_abs_x_m": truth["max_abs_x_m"], "identify_s": seconds}
                    if p.returncode == 2 and "at rest throughout" in p.stderr:
                        row["outcome"] = "at rest"
                    elif p.returncode != 0:
                        row["outcome"] = "refused: " + p.stderr.strip()[:120]
                    else:
                        ident = json.loads(p.stdout)
                        x_err = (ident["x_inst_m"] - truth["x_inst_m"]) / truth["x_inst_m"]
                        r_err = ident["r"] - truth["r"]
                        ok = abs(r_err) <= 0.005 and abs(x_err) <= 0.01
                        row.update({"r_error": r_err, "sigma_r": ident["sigma_r"], "x_inst_error": x_err,
                                    "sigma_x_inst_rel": ident["sigma_x_inst_m"] / truth["x_inst_m"],
                                    "residual_over_noise": ident["residual_rms_m"] / ident["noise_estimate_m"],
                                    "noise_estimate_m": ident["noise_estimate_m"],
                                    "fit_explains_record": ident["fit_explains_record"],
                                    "outcome": "ok" if ok else "off"})
                        if ident.get("bootstrap"):
                            b = ident["bootstrap"]
                            row.update({"curvature_sigma_r": b["curvature_sigma_r"],
                                        "curvature_sigma_x_inst_rel": b["curvature_sigma_x_inst_m"] / truth["x_inst_m"],
                                        "bootstrap_refused": b["refused"]})
                    rows.append(row)
                    print("%2d %-14s set %d %s g %-17s %s" % (case, name, set_no, pga, start_name,
                          row["outcome"] if "x_inst_error" not in row else
                          "%s r %+.4f x_inst %+.2f %% residual/noise %.2f explains %s (%.1f s)" % (
                              row["outcome"], row["r_error"], 100 * row["x_inst_error"], row["residual_over_noise"],
                              row["fit_explains_record"], seconds)), file=sys.stderr)
    keys = sorted({k for x in rows for k in x}, key=lambda k: list(rows[0].keys()).index(k)
                  if k in rows[0] else 100)
    with open(os.path.join(out_dir, "identify_forced.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    for start_name in ("paper wall", "held fields known"):
        sel = [x for x in rows if x["start"] == start_name]
        fitted = [x for x in sel if "x_inst_error" in x]
        ok = [x for x in fitted if x["outcome"] == "ok"]
        flagged = [x for x in fitted if not x["fit_explains_record"]]
        silent = [x for x in fitted if x["outcome"] != "ok" and x["fit_explains_record"]]
        print("start %-17s: %d tests, %d at rest (refused), %d fitted: %d ok (r within 0.005, x_inst within 1 %%), "
              "%d flagged (fit_explains_record false), %d off but not flagged (worst x_inst %+.2f %%)" % (
                  start_name, len(sel), len(sel) - len(fitted), len(fitted), len(ok), len(flagged), len(silent),
                  100 * max((x["x_inst_error"] for x in silent), key=abs, default=0.0)))
        if bootstrap:
            explained = [x for x in fitted if x["fit_explains_record"]]
            for label, sr, sx in (("curvature", "curvature_sigma_r", "curvature_sigma_x_inst_rel"),
                                  ("bootstrap", "sigma_r", "sigma_x_inst_rel")):
                zx = sorted(abs(x["x_inst_error"]) / max(x[sx], 1e-300) for x in explained)
                zr = sorted(abs(x["r_error"]) / max(x[sr], 1e-300) for x in explained)
                if zx:
                    print("  %s sigma over the %d explained fits: |x_inst error|/sigma median %.2f, max %.3g, "
                          "within 2 sigma %d, within 3 sigma %d; |r error|/sigma median %.2f, max %.3g, within 2 "
                          "sigma %d, within 3 sigma %d" % (
                              label, len(explained), zx[len(zx) // 2], zx[-1], sum(z <= 2 for z in zx),
                              sum(z <= 3 for z in zx), zr[len(zr) // 2], zr[-1], sum(z <= 2 for z in zr),
                              sum(z <= 3 for z in zr)))
        noise = [x["noise_estimate_m"] for x in fitted]
        if noise:
            print("  noise estimate: %.3f-%.3f mm (true 0.5 mm)" % (1e3 * min(noise), 1e3 * max(noise)))
    print("output in %s" % out_dir)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rockwatch", default="build/release/host_tools/rockwatch")
    ap.add_argument("--out", default=None)
    ap.add_argument("--forced", action="store_true", help="forced tests of real records instead of snap-back tests")
    ap.add_argument("--bootstrap", type=int, default=0, help="with --forced: identify --bootstrap N (default 0)")
    a = ap.parse_args()
    rw = a.rockwatch
    out_dir = a.out or tempfile.mkdtemp(prefix="identify-evaluation.")
    os.makedirs(out_dir, exist_ok=True)
    if a.forced:
        forced(rw, out_dir, a.bootstrap)
        return
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
