#!/usr/bin/python3
"""Is the ensemble forecast right? (issue 29 item 4, a first measurement; docs/benchmarks-history.md "Ensemble forecast").

Runs `rockwatch simulate --forecast-members N --forecast-horizon-s H --alarms --json --out HISTORY` over the shipped
suite's horizontal records (sets 4-11 x X/Y) at several PGA levels around the paper wall's capacity, and scores each
forecast P(collapse within H) at time t against what the same model did on the rest of the record (the outcome:
collapse at a time in (t, t + H]). Nothing of the forecaster is fitted to these records (its parameters were chosen
on sets 1-3, SPEC section 10), so its scores are out of sample; the state-only baseline, a logistic regression on
E/E_barrier (its maximum over the last 2 s) and |x|/x_inst, is fitted in sample on the same forecasts (its advantage).

    scripts/forecast-evaluation.py [--rockwatch build/release/host_tools/rockwatch] [--out DIR] [--jobs 2]
                                   [--sets 4-11] [--pgas 0.15,...,0.4] [--members 100] [--horizon 3] [--every 0.1]

The forecaster's tuned defaults (intensity spread, high-pass ratio, no envelope growth; SPEC section 10) were chosen
with this script on sets 1-3 (--sets 1-3); the default evaluation is on sets 4-11, kept apart from that choice.

Writes DIR/forecast_reliability.png, DIR/forecast_evaluation.json and prints a Markdown summary: the reliability
table (bins of 0.1; calibrated when |observed - mean forecast| <= 0.1 in every bin with >= 30 forecasts), Brier
score and skill against the base rate and against the baseline, and the lead time before collapse at the threshold
p* where at most 5 % of the surviving runs ever cross it, beside the IMMINENT alarm's lead and false-alarm rate.
Deterministic (fixed member seeds).

`rockwatch study --forecast` makes the same evaluation inside the tool (the same forecasts: its Brier score and
reliability table on sets 4-11 at these levels are this script's), with the baseline and the thresholds fitted leave
one record out instead of in sample (docs/BENCHMARKS.md, "Forecast").
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

SUITE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sim", "suites", "npr9998-2015")
# Paper wall, reduced parameters of the linear model (SPEC section 9, v'' = 0): E/p1 = xd^2/2 + c|x| - k x^2/2.
C_MPS2 = 1.660032
K_PS2 = 16.546117
BARRIER = C_MPS2 * C_MPS2 / (2.0 * K_PS2)


def run_one(args, set_no, comp, pga, tmp):
    hist = os.path.join(tmp, "h_%02d%s_%g.csv" % (set_no, comp, pga))
    cmd = [args.rockwatch, "simulate", "--suite", SUITE, "--set", str(set_no), "--component", comp,
           "--scale-pga", str(pga), "--alarms", "--json", "--out", hist,
           "--forecast-members", str(args.members), "--forecast-horizon-s", str(args.horizon),
           "--forecast-every-s", str(args.every)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stderr)
    j = json.loads(p.stdout)
    # Per block of `every` seconds: the largest E/E_barrier of the history rows in it; and the state at each step.
    t_rows, x_rows, e_block = [], [], {}
    with open(hist) as f:
        r = csv.reader(f)
        header = next(r)
        it, ix, ixd = header.index("t_s"), header.index("x_m"), header.index("xd_mps")
        for row in r:
            t, x, xd = float(row[it]), float(row[ix]), float(row[ixd])
            t_rows.append(t)
            x_rows.append(x)
            e = (0.5 * xd * xd + C_MPS2 * abs(x) - 0.5 * K_PS2 * x * x) / BARRIER
            b = int(math.floor(t / args.every + 1e-9))
            e_block[b] = max(e_block.get(b, -1e9), e)
    os.remove(hist)
    x_inst = j["x_inst_m"]
    t_collapse = j["t_collapse_s"]
    out = []
    row_i = 0
    for s in j["forecast"]["series"]:
        t = s["t_s"]
        while row_i + 1 < len(t_rows) and t_rows[row_i + 1] <= t + 1e-9:
            row_i += 1
        b_now = int(math.floor(t / args.every + 1e-9))
        n_back = int(round(2.0 / args.every))
        e_max = max(e_block.get(b, -1e9) for b in range(b_now - n_back, b_now + 1))
        outcome = 1 if (t_collapse is not None and t < t_collapse <= t + args.horizon + 1e-9) else 0
        out.append({"t": t, "p": s["p_collapse"], "o": outcome, "e": e_max, "xr": abs(x_rows[row_i]) / x_inst,
                    "alarm": s["alarm"]})
    # Collapsed during the record or in the free motion after it (t_collapse_s either way).
    return {"set": set_no, "comp": comp, "pga": pga, "collapsed": t_collapse is not None, "t_collapse": t_collapse,
            "t_imminent": j["alarm"]["t_first_imminent_s"], "forecasts": out}


def logistic_fit(X, y, iters=50):
    """Newton-Raphson on the log-likelihood with a tiny ridge; X rows include the constant 1."""
    n = len(X[0])
    w = [0.0] * n
    for _ in range(iters):
        g = [0.0] * n
        H = [[1e-6 if i == j else 0.0 for j in range(n)] for i in range(n)]
        for xi, yi in zip(X, y):
            z = sum(wj * xj for wj, xj in zip(w, xi))
            p = 1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, z))))
            for a in range(n):
                g[a] += (yi - p) * xi[a]
                for b in range(n):
                    H[a][b] += p * (1.0 - p) * xi[a] * xi[b]
        # Solve H d = g (Gaussian elimination, n = 3).
        A = [H[i][:] + [g[i]] for i in range(n)]
        for c in range(n):
            piv = max(range(c, n), key=lambda r: abs(A[r][c]))
            A[c], A[piv] = A[piv], A[c]
            for r in range(n):
                if r != c and A[c][c] != 0.0:
                    f = A[r][c] / A[c][c]
                    A[r] = [a - f * b for a, b in zip(A[r], A[c])]
        d = [A[i][n] / A[i][i] for i in range(n)]
        w = [wi + di for wi, di in zip(w, d)]
        if max(abs(di) for di in d) < 1e-10:
            break
    return w


def brier(ps, os_):
    return sum((p - o) ** 2 for p, o in zip(ps, os_)) / len(ps)


def lead_at_threshold(runs, key, p_star):
    leads, detected = [], 0
    for r in runs:
        if not r["collapsed"]:
            continue
        first = next((f["t"] for f in r["forecasts"] if key(f) >= p_star), None)
        if first is not None:
            detected += 1
            leads.append(r["t_collapse"] - first)
    return leads, detected


def median(v):
    if not v:
        return None
    s = sorted(v)
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rockwatch", default="build/release/host_tools/rockwatch")
    ap.add_argument("--out", default="forecast-evaluation")
    ap.add_argument("--members", type=int, default=100)
    ap.add_argument("--horizon", type=float, default=3.0)
    ap.add_argument("--every", type=float, default=0.1)
    ap.add_argument("--pgas", default="0.15,0.2,0.25,0.3,0.35,0.4")
    ap.add_argument("--sets", default="4-11",
                    help="suite sets FIRST-LAST (default 4-11: sets 1-3 were used to choose the forecaster's defaults)")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    pgas = [float(v) for v in args.pgas.split(",")]
    first, last = (int(v) for v in args.sets.split("-"))
    jobs = [(s, c, p) for s in range(first, last + 1) for c in ("X", "Y") for p in pgas]
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(args.jobs) as ex:
        runs = list(ex.map(lambda a: run_one(args, *a, tmp), jobs))
    F = [f for r in runs for f in r["forecasts"]]
    if not F or not any(f["o"] for f in F) or all(f["o"] for f in F):
        sys.exit("no forecasts, or every forecast with the same outcome: widen --pgas or --sets")
    ps = [f["p"] for f in F]
    os_ = [f["o"] for f in F]
    base = sum(os_) / len(os_)
    bs_ref = brier([base] * len(os_), os_)
    bs = brier(ps, os_)
    X = [[1.0, f["e"], f["xr"]] for f in F]
    w = logistic_fit(X, os_)
    pb = [1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, sum(wj * xj for wj, xj in zip(w, xi)))))) for xi in X]
    for f, q in zip(F, pb):
        f["pb"] = q
    bs_b = brier(pb, os_)
    # Reliability.
    bins = []
    for k in range(10):
        lo, hi = k / 10.0, (k + 1) / 10.0
        sel = [(p, o) for p, o in zip(ps, os_) if (lo <= p < hi) or (k == 9 and p == 1.0)]
        if sel:
            bins.append({"lo": lo, "hi": hi, "n": len(sel), "mean_p": sum(p for p, _ in sel) / len(sel),
                         "observed": sum(o for _, o in sel) / len(sel)})
    calibrated = all(abs(b["observed"] - b["mean_p"]) <= 0.1 for b in bins if b["n"] >= 30)
    # Lead times at <= 5 % false crossings among surviving runs.
    survivors = [r for r in runs if not r["collapsed"]]
    collapsing = [r for r in runs if r["collapsed"]]

    def threshold_for(key, allowed=None):
        maxima = sorted(max((key(f) for f in r["forecasts"]), default=0.0) for r in survivors)
        if allowed is None:
            allowed = int(math.floor(0.05 * len(maxima)))
        # Smallest p* on a 0.01 grid with at most `allowed` survivors ever at or above it.
        for k in range(1, 101):
            p_star = k / 100.0
            if sum(1 for m in maxima if m >= p_star) <= allowed:
                return p_star, sum(1 for m in maxima if m >= p_star)
        return 1.01, 0

    p_star, fa = threshold_for(lambda f: f["p"])
    leads, det = lead_at_threshold(runs, lambda f: f["p"], p_star)
    pb_star, fa_b = threshold_for(lambda f: f["pb"])
    leads_b, det_b = lead_at_threshold(runs, lambda f: f["pb"], pb_star)
    imm_leads = [r["t_collapse"] - r["t_imminent"] for r in collapsing if r["t_imminent"] is not None]
    imm_fa = sum(1 for r in survivors if r["t_imminent"] is not None)
    # The same comparison at IMMINENT's own false-alarm count (when it exceeds 5 %).
    q_star, fa_q = threshold_for(lambda f: f["p"], imm_fa)
    leads_q, det_q = lead_at_threshold(runs, lambda f: f["p"], q_star)
    qb_star, fa_qb = threshold_for(lambda f: f["pb"], imm_fa)
    leads_qb, det_qb = lead_at_threshold(runs, lambda f: f["pb"], qb_star)
    summary = {
        "runs": len(runs), "collapsing_runs": len(collapsing), "surviving_runs": len(survivors),
        "forecasts": len(F), "members": args.members, "horizon_s": args.horizon, "every_s": args.every,
        "base_rate": base, "brier": bs, "brier_base_rate": bs_ref, "brier_skill": 1.0 - bs / bs_ref,
        "baseline": {"weights_const_e_xr": w, "brier": bs_b, "brier_skill": 1.0 - bs_b / bs_ref},
        "brier_skill_vs_baseline": 1.0 - bs / bs_b,
        "reliability": bins, "calibrated": calibrated,
        "lead": {"p_star": p_star, "false_crossings": fa, "detected": det, "median_lead_s": median(leads)},
        "baseline_lead": {"p_star": pb_star, "false_crossings": fa_b, "detected": det_b,
                          "median_lead_s": median(leads_b)},
        "imminent": {"false_alarms": imm_fa, "detected": len(imm_leads), "median_lead_s": median(imm_leads)},
        "lead_at_imminent_false_alarms": {"p_star": q_star, "false_crossings": fa_q, "detected": det_q,
                                          "median_lead_s": median(leads_q)},
        "baseline_lead_at_imminent_false_alarms": {"p_star": qb_star, "false_crossings": fa_qb, "detected": det_qb,
                                                   "median_lead_s": median(leads_qb)},
    }
    with open(os.path.join(args.out, "forecast_evaluation.json"), "w") as f:
        json.dump(summary, f, indent=2)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 5))
        ax.plot([0, 1], [0, 1], "k--", lw=0.8)
        ax.plot([b["mean_p"] for b in bins], [b["observed"] for b in bins], "o-", label="ensemble")
        for b in bins:
            ax.annotate(str(b["n"]), (b["mean_p"], b["observed"]), fontsize=7, xytext=(3, -9),
                        textcoords="offset points")
        ax.set_xlabel("forecast P(collapse within %g s)" % args.horizon)
        ax.set_ylabel("observed frequency")
        ax.set_title("Reliability, %d forecasts, %d runs" % (len(F), len(runs)))
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "forecast_reliability.png"), dpi=120)
    except ImportError:
        print("note: no matplotlib, no forecast_reliability.png", file=sys.stderr)
    print("| bin | forecasts | mean P | observed |\n| --- | ---: | ---: | ---: |")
    for b in bins:
        print("| %.1f-%.1f | %d | %.3f | %.3f |" % (b["lo"], b["hi"], b["n"], b["mean_p"], b["observed"]))
    print()
    print(json.dumps({k: v for k, v in summary.items() if k != "reliability"}, indent=1))


if __name__ == "__main__":
    main()
