#!/usr/bin/env python3
"""Calibration candidates for the ensemble forecast (issue 29, docs/benchmarks-history.md "The second calibration").

Reads the forecast.csv of `rockwatch study --forecast` runs and scores recalibrations of the raw P with the study's
folds: leave one record out, every fitted parameter (the logistic coefficients, an isotonic map) fitted on the other
records' forecasts only. Prints per plan the max |observed - mean P| over the bins of width 0.1 holding >= 30
forecasts, the Brier skill against the sample's base rate, and with --bins each bin as forecasts/distinct runs,
mean P -> observed (* over 0.1).

  scripts/forecast-calibration-candidates.py fc_a/forecast.csv fc_b/forecast.csv --methods first,inter_cap2,first+iso

Methods: a stage 1 (first: 1, logit p~, rho, |x|/x_inst, the first calibration; inter_capC: + logit p~ * min(rho, C),
C a number or `inf`; quad: + (logit p~)^2/10; spline: + hinges (logit p~ - k)+ at -2, 0, 2; beta: + ln(1 - p~);
interx: + logit p~ * |x|/x_inst; several joined by &: beta&inter_cap2), optionally +iso (isotonic regression,
pool-adjacent-violators, of the outcome on stage-1 P of the training records, interpolated between blocks and clamped
to its range) or +iso50 (the same on 50 quantile bins). --lead adds the study's 5 % rule. Needs numpy (Debian:
python3-numpy).
"""
import argparse
import csv

import numpy as np


def load(path):
    rows = list(csv.DictReader(open(path)))
    return dict(rec=np.array([r["record"] for r in rows]), run=np.array([int(r["run"]) for r in rows]),
                t=np.array([float(r["t_s"]) for r in rows]),
                collapsed=np.array([r["collapsed"] == "true" for r in rows]),
                t_collapse=np.array([float(r["t_collapse_s"]) if r["t_collapse_s"] else np.nan for r in rows]),
                p=np.array([float(r["p_collapse"]) for r in rows]),
                e=np.array([float(r["energy_ratio_max_2s"]) for r in rows]),
                x=np.array([float(r["x_over_x_inst"]) for r in rows]),
                y=np.array([int(r["outcome"]) for r in rows]))


def sig(z):
    return 1.0 / (1.0 + np.exp(-np.clip(z, -50, 50)))


def fit_lr(X, y, pen):
    """Newton-Raphson maximum likelihood with a ridge `pen` per weight, steps longer than 10 shortened (as C++)."""
    w = np.zeros(X.shape[1])
    for _ in range(100):
        p = sig(X @ w)
        g = X.T @ (y - p) - pen * w
        H = (X * (p * (1 - p))[:, None]).T @ X + np.diag(pen)
        d = np.linalg.solve(H, g)
        m = np.abs(d).max()
        w += d * (10 / m if m > 10 else 1)
        if m < 1e-10:
            break
    return w


def features(d, kind, members):
    q = np.clip(d["p"], 0.5 / members, 1 - 0.5 / members)
    L = np.log(q / (1 - q))
    cols = [np.ones_like(L), L, d["e"], d["x"]]
    for term in kind.split("&"):  # terms added together: beta&inter_cap2
        if term.startswith("inter_cap"):
            cols.append(L * np.minimum(d["e"], float(term[len("inter_cap"):])))
        elif term == "quad":
            cols.append(L * L / 10)
        elif term == "spline":
            cols += [np.maximum(L - k, 0) for k in (-2.0, 0.0, 2.0)]
        elif term == "beta":
            cols.append(np.log(1 - q))
        elif term == "interx":
            cols.append(L * d["x"])
        elif term != "first":
            raise SystemExit(f"unknown stage 1: {term}")
    return np.column_stack(cols)


def pav(x, y, bins=None):
    """Isotonic regression: block means (x, y) of the pool-adjacent-violators fit, on `bins` quantile bins if given."""
    o = np.argsort(x, kind="stable")
    if bins:
        chunks = np.array_split(o, bins)
        bx = np.array([x[c].mean() for c in chunks])
        by = np.array([y[c].mean() for c in chunks])
        bw = np.array([len(c) for c in chunks], float)
    else:
        bx, inv = np.unique(x, return_inverse=True)
        bw = np.bincount(inv).astype(float)
        by = np.bincount(inv, weights=y) / bw
    S, C, X = [], [], []
    for xi, yi, wi in zip(bx, by, bw):
        S.append(yi * wi); C.append(wi); X.append(xi * wi)
        while len(S) > 1 and S[-2] / C[-2] >= S[-1] / C[-1]:
            s, c, xx = S.pop(), C.pop(), X.pop()
            S[-1] += s; C[-1] += c; X[-1] += xx
    return np.array(X) / np.array(C), np.array(S) / np.array(C)


def leave_one_record_out(d, method, members):
    kind, _, second = method.partition("+")
    X = features(d, kind, members)
    pen = np.full(X.shape[1], 1e-6)
    pen[4:] = 1e-2  # a mild ridge on the added terms
    out = np.empty(len(d["y"]))
    for r in np.unique(d["rec"]):
        test = d["rec"] == r
        train = ~test
        w = fit_lr(X[train], d["y"][train], pen)
        p1 = sig(X @ w)
        if second:
            kx, ky = pav(p1[train], d["y"][train].astype(float), 50 if second == "iso50" else None)
            out[test] = np.interp(p1[test], kx, ky)
        else:
            out[test] = p1[test]
    return out


def score(d, P):
    y = d["y"]
    base = y.mean()
    skill = 1 - np.mean((P - y) ** 2) / (base * (1 - base))
    b = np.minimum(9, np.floor(P * 10 + 1e-12).astype(int))
    worst, cells = 0.0, []
    for k in range(10):
        m = b == k
        n = int(m.sum())
        if n == 0:
            continue
        err = abs(y[m].mean() - P[m].mean())
        if n >= 30:
            worst = max(worst, err)
        cells.append(f"{k / 10:.1f}: {n}/{len(np.unique(d['run'][m]))} {P[m].mean():.3f}->{y[m].mean():.3f}"
                     + ("*" if n >= 30 and err > 0.1 else ""))
    return worst, skill, cells


def lead_5_percent(d, P):
    """The study's 5 % rule: per record left out, p* the smallest multiple of 0.01 that at most floor(5 %) of the
    other records' surviving runs ever reach; then its survivors flagged, collapses flagged in time, median lead.
    Runs without a forecast are not in forecast.csv: they are not counted (the study counts them as survivors)."""
    runs = np.unique(d["run"])
    first = {r: np.flatnonzero(d["run"] == r) for r in runs}
    rec = {r: d["rec"][first[r][0]] for r in runs}
    top = {r: P[first[r]].max() for r in runs}
    col = {r: bool(d["collapsed"][first[r][0]]) for r in runs}
    flagged = survivors = hits = collapses = 0
    leads = []
    for g in np.unique(d["rec"]):
        maxima = np.array([top[r] for r in runs if rec[r] != g and not col[r]])
        allowed = int(np.floor(0.05 * len(maxima)))
        p_star = next((k / 100 for k in range(1, 101) if (maxima >= k / 100 - 1e-12).sum() <= allowed), None)
        for r in runs:
            if rec[r] != g:
                continue
            if not col[r]:
                survivors += 1
                flagged += p_star is not None and top[r] >= p_star - 1e-12
                continue
            collapses += 1
            if p_star is None:
                continue
            i = first[r]
            t = d["t"][i][P[i] >= p_star - 1e-12]
            if len(t) and t[0] < d["t_collapse"][i[0]]:
                hits += 1
                leads.append(d["t_collapse"][i[0]] - t[0])
    median = f"{np.median(leads):.2f} s" if leads else "-"
    return f"{flagged}/{survivors} survivors, {hits}/{collapses} collapses, median lead {median}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("csv", nargs="+", help="forecast.csv of rockwatch study --forecast")
    ap.add_argument("--methods", default="first,first+iso,first+iso50,quad,spline,beta,interx,inter_capinf,"
                                         "inter_cap2,inter_cap2+iso50")
    ap.add_argument("--members", type=int, default=100, help="the study's --forecast-members (the clamp)")
    ap.add_argument("--bins", action="store_true", help="print every bin")
    ap.add_argument("--lead", action="store_true", help="print the 5 %% rule's false alarms and leads")
    a = ap.parse_args()
    data = [load(p) for p in a.csv]
    for m in a.methods.split(","):
        line = []
        for path, d in zip(a.csv, data):
            worst, skill, cells = score(d, leave_one_record_out(d, m, a.members))
            line.append(f"{worst:.3f} / {skill:.3f}")
            if a.lead:
                print(f"  {m} {path}: at <= 5 %: {lead_5_percent(d, leave_one_record_out(d, m, a.members))}")
            if a.bins:
                print(f"  {m} {path}: " + " | ".join(cells))
        print(f"{m:22s} " + "   ".join(line), flush=True)


if __name__ == "__main__":
    main()
