#!/usr/bin/python3
"""The ensemble forecast on real records (issue 40; docs/BENCHMARKS.md "Model error: the forecast on real records").

For each horizontal real record in tests/data/records (PEER AT2, ITACA .cor.acc, miniSEED), each restitution (r exp,
r ana) and a PGA grid around the paper wall's collapse PGA for that record, runs

    rockwatch simulate --record R --scale-pga G --r exp|ana --alarms --forecast-members N --forecast-horizon-s H --json

and scores every forecast against the run's own outcome (SPEC section 10 "Evaluation": 1 when the run collapses in
(t, t + H]). The collapse PGA of a record is found first: the lowest level of a geometric grid (x 1.1 from 0.03 g)
that collapses the wall; the forecasts are run at that PGA times --factors (default 0.8 ... 1.6).

The records are split by *earthquake event* (never a component of one event in both):
  fit         Imperial Valley-02 (1940), Imperial Valley-06 (1979), Northridge-01 and its aftershock Northridge-05
              (1994), San Fernando (1971), Livermore-01 (1980), N-California 40199209 (2007)
  validation  Kobe (1995), Loma Prieta (1989), Umbria-Marche (1997), L'Aquila (2009), Chi-Chi (1999),
              Groningen Zijldijk (2020, induced)
The calibration shipped for real records is fitted on `fit` only; `validation` is held out from every choice.

    scripts/forecast-real-records.py [--rockwatch build/release/host_tools/rockwatch] [--out DIR] [--jobs 2]
        [--horizon 5] [--members 200] [--sets fit,validation] [--records NAME,...] [--r exp,ana] [--factors 0.8:1.6:0.1]
        [--calibration c0,c1,c2,c3,c4] [--simulate-arg ARG ...] [--refit] [--refit-all] [--wall-sensors
        [--transducer whole|none|dies|accel-only]] [--fresh]
        [--study [--forecast-setting NAME=VALUE ...]] [--check-under-statement 0.1]

--study runs the same forecasts through `rockwatch study --records --forecast` (one study per record and r), which
takes the forecaster's settings (--forecast-setting, SPEC section 10): how the ground continuation was compared
without rebuilding (it publishes no calibrated P: use --refit). --check-under-statement D exits 1 when the published
P is under-stated by more than D in a bin of >= 30 forecasts (the ctest forecast_real_records_not_understated).

--refit also fits the calibration (SPEC section 10's five coefficients, maximum likelihood) on the `fit` forecasts and
scores it on both sets (on `fit`: leave one event out). --refit-all fits it on every event's forecasts (the shipped
coefficients since the second fit of issue 40) and scores it leaving one event out over all events. --wall-sensors runs each level twice: the true wall's
transducer (`--sensors-out`, 0.5 mm noise) and then the fused forecast (`--wall-sensors`), as
scripts/forecast-with-sensors.py does, for the nominal wall.

Writes DIR/boundary.json (the collapse PGA per record and r, reused when present), DIR/forecasts_H<h>.csv (one row
per forecast), DIR/summary_H<h>.json and DIR/reliability_H<h>.png; prints the tables. Deterministic (fixed member
seeds, fixed grids); progress on stderr when it is a terminal.
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RECORDS_DIR = os.path.join(HERE, "..", "tests", "data", "records")
BGAR_GAIN = "213867.4766"

# (name, file, extra reader options, event, set)
RECORDS = [
    ("ELC180", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", [], "Imperial Valley-02 1940", "fit"),
    ("ELC270", "RSN6_IMPVALL.I_I-ELC270-hor2.AT2", [], "Imperial Valley-02 1940", "fit"),
    ("E12140", "RSN175_IMPVALL.H_H-E12140.AT2", [], "Imperial Valley-06 1979", "fit"),
    ("E12230", "RSN175_IMPVALL.H_H-E12230.AT2", [], "Imperial Valley-06 1979", "fit"),
    ("LOS270", "RSN960_NORTHR_LOS270.AT2", [], "Northridge 1994", "fit"),
    ("SYL090", "RSN1690_NORTH151_SYL090-hor1.AT2", [], "Northridge 1994", "fit"),
    ("SYL360", "RSN1690_NORTH151_SYL360-hor2.AT2", [], "Northridge 1994", "fit"),
    ("PUL164", "RSN77_SFERN_PUL164-hor1.AT2", [], "San Fernando 1971", "fit"),
    ("PUL254", "RSN77_SFERN_PUL254-hor2.AT2", [], "San Fernando 1971", "fit"),
    ("SRM070", "RSN215_LIVERMOR_A-SRM070.AT2", [], "Livermore-01 1980", "fit"),
    ("SRM340", "RSN215_LIVERMOR_A-SRM340.AT2", [], "Livermore-01 1980", "fit"),
    ("PLS-HNE", "RSN20075_40199209_1826HNE.AT2", [], "N-California 2007", "fit"),
    ("PLS-HNN", "RSN20075_40199209_1826HNN.AT2", [], "N-California 2007", "fit"),
    ("KJM000", "RSN1106_KOBE_KJM000.AT2", [], "Kobe 1995", "validation"),
    ("KJM090", "RSN1106_KOBE_KJM090.AT2", [], "Kobe 1995", "validation"),
    ("CLS000", "RSN753_LOMAP_CLS000-hor1.AT2", [], "Loma Prieta 1989", "validation"),
    ("CLS090", "RSN753_LOMAP_CLS090-hor2.AT2", [], "Loma Prieta 1989", "validation"),
    ("BEV000", "RSN4346_UBMARCHE.P_A-BEV000.AT2", [], "Umbria-Marche 1997", "validation"),
    ("BEV270", "RSN4346_UBMARCHE.P_A-BEV270.AT2", [], "Umbria-Marche 1997", "validation"),
    ("AQG-NS", "16833_H1.cor.acc", [], "L'Aquila 2009", "validation"),
    ("AQG-WE", "16833_H2.cor.acc", [], "L'Aquila 2009", "validation"),
    ("TCU122N", "RSN1546_CHICHI_TCU122-N.AT2", [], "Chi-Chi 1999", "validation"),
    ("BGAR-HGE", "NL.BGAR.mseed", ["--channel", "HGE", "--gain", BGAR_GAIN], "Groningen Zijldijk 2020", "validation"),
    ("BGAR-HGN", "NL.BGAR.mseed", ["--channel", "HGN", "--gain", BGAR_GAIN], "Groningen Zijldijk 2020", "validation"),
]
FACTORS = "0.8:1.6:0.1"


def progress(msg):
    if sys.stderr.isatty():
        print("\r" + msg + " " * 10, end="", file=sys.stderr, flush=True)


def run_json(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"forecast-real-records: {' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}")
    return json.loads(p.stdout)


def record_args(rec):
    return ["--record", os.path.join(RECORDS_DIR, rec[1])] + rec[2]


def find_boundary(a, rec, r):
    """The lowest level of the grid 0.03 g x 1.1^k (to 4 g) at which the wall collapses (None: never)."""
    g = 0.03
    while g <= 4.0:
        j = run_json([a.rockwatch, "simulate"] + record_args(rec) + ["--r", r, "--scale-pga", "%.4f" % g, "--json"])
        if j["collapsed"] or j.get("t_collapse_s") is not None:
            return round(g, 4)
        g *= 1.1
    return None


def run_study(a, rec, r, g0, horizon):
    """--study: the same forecasts through `rockwatch study --records --forecast`, which takes --forecast-setting
    (the forecaster's SPEC section 10 settings, to try a ground continuation without rebuilding)."""
    import tempfile
    f0, f1, df = a.factor_grid
    with tempfile.TemporaryDirectory() as tmp:
        lst = os.path.join(tmp, "records.txt")
        with open(lst, "w") as f:
            f.write(os.path.abspath(os.path.join(RECORDS_DIR, rec[1])) + "\n")
        cmd = [a.rockwatch, "study", "--records", lst, "--r", r, "--vertical", "without",
               "--pga", "%.5f:%.5f:%.5f" % (g0 * f0, g0 * f1 + 1e-6, g0 * df), "--forecast",
               "--forecast-members", str(a.members), "--forecast-horizon-s", "%g" % horizon, "--jobs", "1",
               "--out", os.path.join(tmp, "s")] + rec[2]
        for fs in a.forecast_setting:
            cmd += ["--forecast-setting", fs]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            sys.exit(f"forecast-real-records: {' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()[-2000:]}")
        rows = []
        with open(os.path.join(tmp, "s", "forecast.csv")) as f:
            for x in csv.DictReader(f):
                tc = x.get("t_collapse_s", "")
                rows.append({"record": rec[0], "event": rec[3], "set": rec[4], "r": r,
                             "pga_g": round(float(x["pga_g"]), 4), "t_s": float(x["t_s"]),
                             "p": float(x["p_collapse"]), "p_cal": float("nan"),
                             "e": float(x["energy_ratio_max_2s"]), "xr": float(x["x_over_x_inst"]),
                             "outcome": int(float(x["outcome"])), "t_collapse_s": tc})
        return rows


def transducer_as(kind, path):
    """The sensor file the fused run reads, for --transducer KIND (docs/BENCHMARKS.md "The fused state's spread needs
    a displacement reading"): whole, none (its reading at t = 0 only), dies (cut 1 s after |x| first reaches 2 mm) or
    accel-only (the displacement column emptied; the accelerometer written by --sensors-out)."""
    if kind == "whole":
        return path
    with open(path) as f:
        lines = f.readlines()
    out, t_cut = [lines[0]], None
    for line in lines[1:]:
        cells = line.strip().split(",")
        if kind == "none":
            out.append(line)
            break
        if kind == "accel-only":
            out.append("%s,,%s\n" % (cells[0], cells[2]))
            continue
        t, x = float(cells[0]), float(cells[1])
        if t_cut is None and abs(x) >= 2e-3:
            t_cut = t + 1.0
        if t_cut is not None and t > t_cut:
            break
        out.append(line)
    changed = path[:-len(".csv")] + "_" + kind + ".csv"
    with open(changed, "w") as f:
        f.writelines(out)
    return changed


def run_level(a, rec, r, pga, horizon):
    base = [a.rockwatch, "simulate"] + record_args(rec) + ["--r", r, "--scale-pga", "%.4f" % pga]
    fc = ["--alarms", "--forecast-members", str(a.members), "--forecast-horizon-s", "%g" % horizon, "--json"]
    if a.calibration:
        fc += ["--forecast-calibration", a.calibration]
    fc += a.simulate_arg
    if a.wall_sensors:
        sensors = os.path.join(a.out, "sensors", "%s_%s_%.4f.csv" % (rec[0], r, pga))
        os.makedirs(os.path.dirname(sensors), exist_ok=True)
        accel = ["--sensor-accel-noise-mps2", "0.05"] if a.transducer == "accel-only" else []
        truth = run_json(base + ["--sensors-out", sensors, "--json"] + accel)
        sensors = transducer_as(a.transducer, sensors)
        j = run_json(base + ["--wall-sensors", sensors] + fc)
        tc = truth.get("t_collapse_s")
    else:
        j = run_json(base + fc)
        tc = j.get("t_collapse_s")
    rows = []
    for e in j["forecast"]["series"]:
        t = e["t_s"]
        o = 1 if (tc is not None and t < tc <= t + horizon + 1e-9) else 0
        pc = e.get("p_collapse_calibrated")
        rows.append({"record": rec[0], "event": rec[3], "set": rec[4], "r": r, "pga_g": pga, "t_s": t,
                     "p": e["p_collapse"], "p_cal": pc if pc is not None else float("nan"),
                     "e": e["energy_ratio_max_2s"], "xr": e["x_over_x_inst"], "outcome": o,
                     "t_collapse_s": tc if tc is not None else ""})
    return rows


# ---- scoring ---------------------------------------------------------------------------------------------------

def bins_of(ps, os_):
    out = []
    for k in range(10):
        lo, hi = k / 10.0, (k + 1) / 10.0
        sel = [(p, o) for p, o in zip(ps, os_) if (lo <= p < hi) or (k == 9 and p == 1.0)]
        if sel:
            out.append({"lo": lo, "hi": hi, "n": len(sel), "mean_p": sum(p for p, _ in sel) / len(sel),
                        "observed": sum(o for _, o in sel) / len(sel)})
    return out


def score(ps, os_):
    n = len(ps)
    base = sum(os_) / n
    b = sum((p - o) ** 2 for p, o in zip(ps, os_)) / n
    ref = base * (1.0 - base)
    bins = bins_of(ps, os_)
    pop = [x for x in bins if x["n"] >= 30]
    return {"forecasts": n, "base_rate": base, "brier": b, "brier_skill": 1.0 - b / ref if ref > 0 else float("nan"),
            "max_abs_error": max((abs(x["observed"] - x["mean_p"]) for x in pop), default=0.0),
            "max_under_statement": max((x["observed"] - x["mean_p"] for x in pop), default=0.0),
            "calibrated": all(abs(x["observed"] - x["mean_p"]) <= 0.1 for x in pop), "reliability": bins}


def features(rows, members):
    lo = 0.5 / members
    X = []
    for f in rows:
        p = min(max(f["p"], lo), 1.0 - lo)
        L = math.log(p / (1.0 - p))
        X.append([1.0, L, f["e"], f["xr"], L * min(f["e"], 2.0)])
    return X


def fit_logistic(X, y, ridge=1e-6, iters=100):
    import numpy as np
    X = np.asarray(X, float)
    y = np.asarray(y, float)
    w = np.zeros(X.shape[1])
    for _ in range(iters):
        z = np.clip(X @ w, -50, 50)
        p = 1.0 / (1.0 + np.exp(-z))
        g = X.T @ (y - p) - ridge * w
        H = (X * (p * (1 - p))[:, None]).T @ X + ridge * np.eye(X.shape[1])
        d = np.linalg.solve(H, g)
        m = np.max(np.abs(d))
        if m > 10.0:
            d *= 10.0 / m
        w = w + d
        if m < 1e-10:
            break
    return [float(v) for v in w]


def apply_logistic(w, X):
    return [1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, sum(a * b for a, b in zip(w, x)))))) for x in X]


def leave_one_event_out(rows, members, key):
    """Each event's rows get, under `key`, the calibration fitted on the other events' rows only."""
    for ev in sorted({x["event"] for x in rows}):
        train = [x for x in rows if x["event"] != ev]
        test = [x for x in rows if x["event"] == ev]
        if not train:
            continue
        wv = fit_logistic(features(train, members), [x["outcome"] for x in train])
        for x, p in zip(test, apply_logistic(wv, features(test, members))):
            x[key] = p


def table(name, s):
    lines = [f"{name}: {s['forecasts']} forecasts, base rate {s['base_rate']:.3f}, Brier {s['brier']:.4f}, "
             f"skill {s['brier_skill']:.3f}, max |obs - P| (bins >= 30) {s['max_abs_error']:.3f}, "
             f"max under-statement {s['max_under_statement']:+.3f}",
             "  bin      n     mean P  observed"]
    for b in s["reliability"]:
        flag = " *" if b["n"] >= 30 and abs(b["observed"] - b["mean_p"]) > 0.1 else ""
        lines.append(f"  {b['lo']:.1f}-{b['hi']:.1f} {b['n']:6d}  {b['mean_p']:.3f}   {b['observed']:.3f}{flag}")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rockwatch", default=os.path.join(HERE, "..", "build", "release", "host_tools", "rockwatch"))
    ap.add_argument("--out", default="forecast-real-records")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--horizon", type=float, default=5.0)
    ap.add_argument("--members", type=int, default=200)
    ap.add_argument("--sets", default="fit,validation")
    ap.add_argument("--records", help="comma-separated record names (default: every record of --sets)")
    ap.add_argument("--r", default="exp,ana")
    ap.add_argument("--factors", default=FACTORS,
                    help="PGA levels FROM:TO:STEP as multiples of the record's collapse PGA (0.8:1.6:0.1)")
    ap.add_argument("--calibration", help="--forecast-calibration for simulate (default: the shipped one)")
    ap.add_argument("--simulate-arg", action="append", default=[], help="one more simulate argument (repeatable)")
    ap.add_argument("--study", action="store_true",
                    help="run the forecasts through `rockwatch study --records` (takes --forecast-setting; no "
                         "calibrated P: use --refit)")
    ap.add_argument("--forecast-setting", action="append", default=[], help="with --study: NAME=VALUE (repeatable)")
    ap.add_argument("--refit", action="store_true", help="fit the calibration on `fit`, score it on both sets")
    ap.add_argument("--refit-all", action="store_true",
                    help="fit the calibration on every event (what ships since issue 40's second fit) and score it "
                         "leaving one event out over all of them")
    ap.add_argument("--wall-sensors", action="store_true")
    ap.add_argument("--transducer", choices=("whole", "none", "dies", "accel-only"), default="whole",
                    help="with --wall-sensors: what the fused run reads: the whole record's transducer, none (its "
                         "reading at t = 0 only), one that dies 1 s after |x| first reaches 2 mm, or an "
                         "accelerometer alone")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--fresh", action="store_true", help="search the collapse PGAs again (ignore DIR/boundary.json)")
    ap.add_argument("--check-under-statement", type=float, metavar="D",
                    help="exit 1 when, in a bin of >= 30 forecasts of any set, the observed frequency exceeds the mean "
                         "published (calibrated) P by more than D (the ctest's check, issue 40)")
    a = ap.parse_args()
    a.rockwatch = os.path.abspath(a.rockwatch)
    os.makedirs(a.out, exist_ok=True)
    sets = a.sets.split(",")
    recs = [r for r in RECORDS if r[4] in sets]
    if a.records:
        names = a.records.split(",")
        recs = [r for r in recs if r[0] in names]
    rs = a.r.split(",")
    f0, f1, df = (float(v) for v in a.factors.split(":"))
    a.factor_grid = (f0, f1, df)
    factors = [round(f0 + k * df, 6) for k in range(int(round((f1 - f0) / df)) + 1)]

    # 1. The collapse PGA per record and r (cached: it does not depend on the forecast).
    bpath = os.path.join(a.out, "boundary.json")
    boundary = json.load(open(bpath)) if os.path.exists(bpath) and not a.fresh else {}
    todo = [(rec, r) for rec in recs for r in rs if f"{rec[0]}/{r}" not in boundary]
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
        for i, ((rec, r), g) in enumerate(zip(todo, ex.map(lambda t: find_boundary(a, *t), todo))):
            boundary[f"{rec[0]}/{r}"] = g
            progress(f"[boundary {i + 1}/{len(todo)}] {rec[0]} r {r}: {g} g")
    with open(bpath, "w") as f:
        json.dump(boundary, f, indent=1, sort_keys=True)

    # 2. Forecasts at the levels around it.
    jobs = []
    for rec in recs:
        for r in rs:
            g0 = boundary.get(f"{rec[0]}/{r}")
            if g0 is None:
                continue
            if a.study:
                jobs.append((rec, r, g0))
            else:
                jobs += [(rec, r, round(g0 * k, 4)) for k in factors]
    rows = []
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
        fn = run_study if a.study else run_level
        futs = [ex.submit(fn, a, rec, r, g, a.horizon) for rec, r, g in jobs]
        for i, fu in enumerate(futs):
            rows += fu.result()
            progress(f"[forecast {i + 1}/{len(jobs)}] {jobs[i][0][0]} r {jobs[i][1]} {jobs[i][2]} g")
    if sys.stderr.isatty():
        print("", file=sys.stderr)
    tag = "H%g" % a.horizon
    if not rows:
        sys.exit("forecast-real-records: no forecasts (no record collapsed on the grid?)")

    # 3. Scores per set: raw, calibrated (simulate's published P), and with --refit the calibration fitted on `fit`.
    summary = {"horizon_s": a.horizon, "members": a.members, "r": rs, "factors": factors, "boundary_g": boundary,
               "simulate_args": a.simulate_arg, "calibration_arg": a.calibration, "sets": {}}
    refit = None
    if a.refit:
        fit_rows = [x for x in rows if x["set"] == "fit"]
        refit = fit_logistic(features(fit_rows, a.members), [x["outcome"] for x in fit_rows])
        summary["refit_coefficients"] = refit
        for x, p in zip(rows, apply_logistic(refit, features(rows, a.members))):
            x["p_refit"] = p
        # On `fit` itself: leave one event out.
        leave_one_event_out(fit_rows, a.members, "p_refit_loeo")
    refit_all = None
    if a.refit_all:
        # The shipped coefficients: every event's forecasts. Scored leave one *event* out over all events, so that no
        # forecast is scored by coefficients its own earthquake helped fit (SPEC section 10 "Real records").
        refit_all = fit_logistic(features(rows, a.members), [x["outcome"] for x in rows])
        summary["refit_all_coefficients"] = refit_all
        leave_one_event_out(rows, a.members, "p_refit_all_loeo")
    for st in sets + ["all"]:
        sel = [x for x in rows if st == "all" or x["set"] == st]
        if not sel or not any(x["outcome"] for x in sel):
            continue
        os_ = [x["outcome"] for x in sel]
        entry = {"runs": len({(x["record"], x["r"], x["pga_g"]) for x in sel}),
                 "records": sorted({x["record"] for x in sel}), "raw": score([x["p"] for x in sel], os_)}
        if all(not math.isnan(x["p_cal"]) for x in sel):
            entry["calibrated"] = score([x["p_cal"] for x in sel], os_)
        if refit:
            key = "p_refit_loeo" if st == "fit" else "p_refit"
            if st != "all":
                entry["refit"] = score([x.get(key, x["p_refit"]) for x in sel], os_)
        if refit_all and all("p_refit_all_loeo" in x for x in sel):
            entry["refit_all_loeo"] = score([x["p_refit_all_loeo"] for x in sel], os_)
        summary["sets"][st] = entry
        print(f"## {st} (H = {a.horizon:g} s, {entry['runs']} runs)")
        names = {"refit": "refit, leave one event out" if st == "fit" else "refit on fit",
                 "refit_all_loeo": "refit on every event, scored leaving one event out"}
        for k in ("raw", "calibrated", "refit", "refit_all_loeo"):
            if k in entry:
                print(table(names.get(k, k), entry[k]))
        print()
    if refit:
        print("refit coefficients (c0..c4):", ",".join("%.4f" % v for v in refit))
    if refit_all:
        print("refit-all coefficients (c0..c4):", ",".join("%.4f" % v for v in refit_all))
    with open(os.path.join(a.out, f"forecasts_{tag}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys())[:12] + ["p_refit", "p_refit_loeo", "p_refit_all_loeo"], restval="",
                           extrasaction="ignore")
        w.writeheader()
        for x in rows:
            w.writerow(x)
    with open(os.path.join(a.out, f"summary_{tag}.json"), "w") as f:
        json.dump(summary, f, indent=1)
    if not a.no_plot:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            fig, axes = plt.subplots(1, len(summary["sets"]), figsize=(4.2 * len(summary["sets"]), 4.4), squeeze=False)
            for ax, (st, entry) in zip(axes[0], summary["sets"].items()):
                ax.plot([0, 1], [0, 1], "k--", lw=0.8)
                ax.fill_between([0, 1], [-0.1, 0.9], [0.1, 1.1], color="0.9")
                for k, m in (("raw", "o-"), ("calibrated", "s-"), ("refit", "^-")):
                    if k in entry:
                        b = [x for x in entry[k]["reliability"] if x["n"] >= 30]
                        ax.plot([x["mean_p"] for x in b], [x["observed"] for x in b], m, ms=4,
                                label=f"{k} (skill {entry[k]['brier_skill']:.2f})")
                ax.set_xlim(0, 1)
                ax.set_ylim(0, 1)
                ax.set_title(f"{st}: {entry['raw']['forecasts']} forecasts, {entry['runs']} runs", fontsize=9)
                ax.set_xlabel(f"P(collapse within {a.horizon:g} s)")
                ax.set_ylabel("observed frequency")
                ax.legend(fontsize=7, loc="upper left")
            fig.tight_layout()
            fig.savefig(os.path.join(a.out, f"reliability_{tag}.png"), dpi=110)
        except ImportError:
            print("note: no matplotlib, no PNG", file=sys.stderr)


    if a.check_under_statement is not None:
        worst = max(e["calibrated" if "calibrated" in e else "raw"]["max_under_statement"]
                    for e in summary["sets"].values())
        if worst > a.check_under_statement:
            print(f"FAIL: the published P is under-stated by {worst:.3f} (> {a.check_under_statement}) in a bin of >= 30 "
                  "forecasts", file=sys.stderr)
            sys.exit(1)
        print(f"ok: the largest under-statement in a bin of >= 30 forecasts is {worst:+.3f} "
              f"(<= {a.check_under_statement})")


if __name__ == "__main__":
    main()
