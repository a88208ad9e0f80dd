#!/usr/bin/python3
"""Validation of wall_truth's engine (tests/truth/README.md records the numbers).

  /usr/bin/python3 tests/truth/validate.py --quick     # the ctest: rest, r per impact, x_inst, C = Python, a kept case
  /usr/bin/python3 tests/truth/validate.py             # also: step convergence, free rocking and verdicts beside
                                                       # rockwatch (needs build/release/host_tools/rockwatch), the
                                                       # other families' properties
Exit 0 when every check passes, 1 otherwise; 77 (skipped) without numpy unless CI=true (then 1).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
except ImportError:  # pragma: no cover
    print("validate.py: numpy is missing (Debian: python3-numpy)")
    sys.exit(1 if os.environ.get("CI") == "true" else 77)

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from wall_truth import records, runs  # noqa: E402
from wall_truth.engine import TwoBlockWall, default_params  # noqa: E402
from wall_truth.kernel import FastWall  # noqa: E402
import make_truths  # noqa: E402

ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
G = 9.81
THR_SPEC_G = 0.114286      # SPEC §2, paper wall (for comparison only)
R_IMPULSE_SPEC = 0.952236  # SPEC §3 (for comparison only)
FAILS = []


def check(ok, what):
    print(("PASS " if ok else "FAIL ") + what, flush=True)
    if not ok:
        FAILS.append(what)


def paper(h=make_truths.H_RIGID, **kw):
    tp = default_params()
    tp["h_step_s"] = h
    tp.update(kw)
    return tp


def r_impulse_spec(b, h1, h2):
    """SPEC §3's impulse restitution (per metre of wall, density cancels): e = (Jt − Vt)/(Jt + Vt), r = e²."""
    m1, m2 = b * h1, b * h2
    j1, j2 = m1 * (b * b + h1 * h1) / 12.0, m2 * (b * b + h2 * h2) / 12.0
    jt = j1 / h1 ** 2 + j2 / h2 ** 2 + (m1 + m2) / 4.0
    vt = m1 * b * b / (4.0 * h1 ** 2) + m2 * (b / h1 + b / (2.0 * h2)) ** 2
    e = (jt - vt) / (jt + vt)
    return e * e


def hold(tp, ug_g, t_end=2.0, ramp=0.05):
    """max |x| under a constant ground acceleration ug_g·g, ramped in over `ramp` s."""
    w = runs.make_wall(tp)
    h = tp["h_step_s"]
    n = int(round(t_end / h))
    m = 0.0
    for k in range(0, n, 16):
        u0 = ug_g * G * min(1.0, k * h / ramp)
        u1 = ug_g * G * min(1.0, (k + 16) * h / ramp)
        w.steps(h, 16, u0, u1)
        m = max(m, abs(w.joint_centre_x()))
        if m > 0.05:
            break
    return m


def uplift_threshold(tp, lo=0.05, hi=0.2):
    """Smallest constant ü (g) that moves the joint by more than 0.1 mm within 2 s (bisection, 1e-4 g)."""
    while hi - lo > 1e-4:
        mid = 0.5 * (lo + hi)
        if hold(tp, mid, 2.0) > 1e-4:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def quick():
    tp = paper()
    # 1. at rest below the uplift threshold, rocking above it (both directions)
    for s in (1, -1):
        below = hold(tp, s * 0.95 * THR_SPEC_G)
        above = hold(tp, s * 1.05 * THR_SPEC_G)
        check(below < 1e-6 and above > 1e-3, "rest: constant ü = %+.2f × 0.114286 g: max|x| %.2e m; at %+.2f ×: %.2e m"
              % (0.95 * s, below, 1.05 * s, above))
    # 2. static push: x_inst ≈ b, uplift force
    xs, fs, xi, _ = runs.static_push(tp, 1)
    xsn, fsn, xin, _ = runs.static_push(tp, -1)
    check(abs(xi - 0.1) <= 0.002 and abs(xin - 0.1) <= 0.002,
          "static push: x_inst +%.5f / -%.5f m (b = 0.1; SPEC full model 0.100000, linear 0.1003276)" % (xi, xin))
    print("     lateral force at the joint when it starts to move: %.2f N/m (SPEC p6 353.16)" % fs[0])
    # 3. energy ratio per impact, free rocking from 0.05 m
    sb = runs.snapback(tp, 0.05, rate=200.0)
    rl = runs.impact_energy_ratios(sb)
    r = float(np.median(rl))
    check(0.94 <= r <= 0.965, "energy ratio per impact (first 5, median) %.4f [%s] (SPEC r_impulse %.6f, r_ana 0.993491)"
          % (r, ", ".join("%.4f" % v for v in rl), R_IMPULSE_SPEC))
    # 4. the C kernel is the Python engine
    dev = c_vs_python(0.3)
    check(dev < 1e-9, "C kernel = Python engine over 0.3 s of forced rocking: max |Δq| %.2e" % dev)
    # 5. the kept data keep their layout (the contract with the studies that read them)
    problems = layout_problems()
    check(not problems, "tests/data/truths layout: index.csv, 4 files and the truth.json keys per case%s" % (
        "" if not problems else ": " + "; ".join(problems[:5])))
    # 7. another wall (make_truths --wall): the engine's energy ratio per impact against SPEC §3's impulse formula for
    #    that geometry (the formula is written here from SPEC, not taken from rockwatch), and the families around it
    wall = make_truths.parse_wall("b=0.21,h=2.7,rho=1900")
    tw = paper(b=wall["b"], h1=wall["h1"], h2=wall["h2"], rho=wall["rho"])
    xw, _, xwp, _ = runs.static_push(tw, 1)
    rw_list = runs.impact_energy_ratios(runs.snapback(tw, round(0.5 * xwp, 4), rate=200.0))
    rw = float(np.median(rw_list))
    r_formula = r_impulse_spec(wall["b"], wall["h1"], wall["h2"])
    check(abs(rw - r_formula) <= 0.01 and abs(xwp - wall["b"]) <= 0.02 * wall["b"],
          "another wall (b 0.21, h 2.7 m): energy ratio per impact %.4f against SPEC's r_impulse %.4f for it; "
          "x_inst %.5f m (b %.2f)" % (rw, r_formula, xwp, wall["b"]))
    fams = make_truths.families_for_wall(make_truths.RECORDS, wall)
    geo_ok = all(abs(tp["h1"] + tp["h2"] - 2.7) < 1e-9 and tp["b"] == 0.21 and tp["rho"] == 1900.0
                 for ts in fams.values() for _, tp, _ in ts)
    kinds = {f: sorted({tp["interface"]["kind"] for _, tp, _ in ts}) for f, ts in fams.items()}
    loads = [tp["Fp_N_per_m"] for _, tp, _ in fams["overburden"]]
    check(geo_ok and kinds == {"multibody": ["rigid"], "crushed": ["crushing"], "crack_height": ["rigid"],
                               "overburden": ["rigid"]} and loads == [2100.0, 4200.0]
          and sum(len(r) for _, _, r in fams["crushed"]) == 8,
          "make_truths --wall: the four families around b 0.21, h 2.7 m (overburdens %s N/m)" % loads)
    errors = []
    for bad in ("b=0.21,h=2.7", "b=0.21,h=2.7,rho=x", "b=0.21,h=2.7,h1=1,rho=1900", "b=2,h=2.7,rho=1900", "q=1"):
        try:
            make_truths.parse_wall(bad)
        except ValueError as e:
            errors.append(str(e).startswith("--wall: "))
    check(errors == [True] * 5, "make_truths --wall: bad walls refused, naming the field (%d of 5)" % sum(errors))
    # 6. a kept case regenerates
    case = kept_case()
    if case is None:
        check(False, "a kept case regenerates: no tests/data/truths/index.csv")
    else:
        t0 = time.time()
        p = make_truths.regenerate(case)
        check(not p, "kept case %s regenerates from its truth.json (%.1f s)%s" % (
            os.path.relpath(case, ROOT), time.time() - t0, "" if not p else ": " + "; ".join(p)))


def c_vs_python(t_end, h=2.5e-4, itf=None):
    out = 0.0
    for itf in ([{"kind": "rigid"}, make_truths.crushing(1e9, 3e-3, 0.5e6, n=7)] if itf is None else [itf]):
        tp = paper(h, interface=itf)
        ws = [TwoBlockWall(tp), FastWall(tp)]
        for w in ws:
            w.driver = 0.02
            for k in range(int(0.5 / h)):
                w.step(h, 0.0)
            w.driver = None
            w.v[:] = 0.0
            w.reset_status()
            for k in range(int(t_end / h)):
                w.step(h, 2.5 * math.sin(2 * math.pi * 2.0 * k * h))
        out = max(out, float(np.max(np.abs(ws[0].q - ws[1].q))))
    return out


TRUTH_KEYS = ["family", "case", "engine", "truth_params", "wall_told", "record", "scale_pga_g", "collapsed",
              "t_collapse_s", "t_exceed_s", "max_abs_x_m", "x_inst_equiv_m", "r_equiv", "robust", "sensor"]


def layout_problems():
    import csv
    root = os.path.join(ROOT, "tests", "data", "truths")
    idx = os.path.join(root, "index.csv")
    if not os.path.exists(idx):
        return ["no index.csv"]
    out = []
    rows = list(csv.DictReader(open(idx)))
    if not rows or list(rows[0].keys()) != make_truths.INDEX_COLS:
        out.append("index.csv columns")
    listed = set()
    for r in rows:
        d = os.path.join(root, r["family"], r["case"])
        listed.add((r["family"], r["case"]))
        for f in ("ground.csv", "sensors.csv", "snapback.csv", "truth.json"):
            if not os.path.exists(os.path.join(d, f)):
                out.append("%s/%s: no %s" % (r["family"], r["case"], f))
        if not os.path.exists(os.path.join(d, "truth.json")):
            continue
        j = json.load(open(os.path.join(d, "truth.json")))
        miss = [k for k in TRUTH_KEYS if k not in j]
        if miss:
            out.append("%s/%s: truth.json lacks %s" % (r["family"], r["case"], ", ".join(miss)))
        if not os.path.exists(os.path.join(ROOT, "tests", "data", "records", j.get("record", ""))):
            out.append("%s/%s: record %s not in tests/data/records" % (r["family"], r["case"], j.get("record")))
        with open(os.path.join(d, "ground.csv")) as f:
            if f.readline().strip() != "t_s,ug_mps2":
                out.append("%s/%s: ground.csv header" % (r["family"], r["case"]))
        for name in ("sensors.csv", "snapback.csv"):
            with open(os.path.join(d, name)) as f:
                if f.readline().strip() != "t_s,x_mid_m,a_mid_mps2":
                    out.append("%s/%s: %s header" % (r["family"], r["case"], name))
    for fam in os.listdir(root):
        if os.path.isdir(os.path.join(root, fam)):
            for case in os.listdir(os.path.join(root, fam)):
                if (fam, case) not in listed:
                    out.append("%s/%s not in index.csv" % (fam, case))
    return out


def kept_case():
    idx = os.path.join(ROOT, "tests", "data", "truths", "index.csv")
    if not os.path.exists(idx):
        return None
    import csv
    rows = [r for r in csv.DictReader(open(idx)) if r["family"] == "multibody" and r["collapsed"] == "true"]
    if not rows:
        return None
    rows.sort(key=lambda r: float(r["t_collapse_s"]))
    r = rows[0]
    return os.path.join(ROOT, "tests", "data", "truths", r["family"], r["case"])


def crossings(t, x):
    return [t[k - 1] + (t[k] - t[k - 1]) * x[k - 1] / (x[k - 1] - x[k]) for k in range(1, len(x)) if x[k - 1] * x[k] < 0]


def peaks(x):
    return [abs(x[k]) for k in range(1, len(x) - 1) if abs(x[k]) >= abs(x[k - 1]) and abs(x[k]) > abs(x[k + 1])]


def full(rw):
    # convergence in the step
    print("\n-- step convergence (paper wall released from 0.05 m): crossings of x = 0 [s], r per impact")
    for h in (5e-4, 2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5):
        sb = runs.snapback(paper(h), 0.05, t_end=3.0, rate=1000.0)
        cr = crossings(sb.t, sb.x)[:5]
        print("  h %.3e s: %s  r %s" % (h, " ".join("%.4f" % c for c in cr),
                                          " ".join("%.4f" % v for v in runs.impact_energy_ratios(sb))))
    itf = make_truths.crushing(1e9, 1e-2, 0.3e6)
    print("-- step convergence, crushing interface k 1e9 N/m³, fc 0.3 MPa, c/k 1e-2 s, released from 0.042 m")
    for h in (5e-4, 2.5e-4, 1.25e-4, 6.25e-5):
        sb = runs.snapback(paper(h, interface=itf), 0.042, t_end=3.0, rate=1000.0)
        cr = crossings(sb.t, sb.x)[:5]
        print("  h %.3e s: %s  r %s" % (h, " ".join("%.4f" % c for c in cr),
                                          " ".join("%.4f" % v for v in runs.impact_energy_ratios(sb))))
    thr = uplift_threshold(paper())
    check(abs(thr - THR_SPEC_G) < 0.002, "uplift threshold (constant ü, bisection) %.4f g (SPEC %.6f g)" % (thr, THR_SPEC_G))
    # free rocking beside rockwatch
    sb = runs.snapback(paper(), 0.05, t_end=8.0, rate=1000.0)
    cr, pk = crossings(sb.t, sb.x), peaks(sb.x)
    print("\n-- free rocking from x0 = 0.05 m, 8 s: crossings of x = 0 [s] and peak |x| [m]")
    print("  truth      : %s" % " ".join("%.3f" % c for c in cr[:8]))
    print("               %s" % " ".join("%.4f" % p for p in pk[:8]))
    if rw and os.path.exists(rw):
        with tempfile.TemporaryDirectory() as td:
            for r in ("ana", "impulse"):
                out = os.path.join(td, "free_%s.csv" % r)
                subprocess.run([rw, "simulate", "--x0", "0.05", "--r", r, "--t-end", "8", "--out", out], check=True,
                               stdout=subprocess.DEVNULL)
                d = np.genfromtxt(out, delimiter=",", names=True)
                names = d.dtype.names
                t, x = d[names[0]], d["x_m"] if "x_m" in names else d[names[3]]
                crr, pkr = crossings(t, x), peaks(x)
                print("  r %-8s: %s" % (r, " ".join("%.3f" % c for c in crr[:8])))
                print("               %s" % " ".join("%.4f" % p for p in pkr[:8]))
        verdicts_beside(rw)
    else:
        print("  (rockwatch not built: %s)" % rw)
    # the other truths
    print("\n-- the other families' truths")
    for fam, truths in make_truths.FAMILIES.items():
        for name, tp, _ in truths:
            tr = make_truths.Truth(name, tp)
            el = hold(tp, 0.5 * THR_SPEC_G)
            thr = uplift_threshold(tp, 0.02, 0.5) if tp["interface"]["kind"] == "rigid" else float("nan")
            print("  %-12s %-22s x_inst %.5f/%.5f m  peak resistance %7.1f N/m  r_equiv %.4f  "
                  "max|x| at 0.5×0.114 g %.2e m  rigid uplift %.4f g" % (
                      fam, name, tr.x_inst[0], tr.x_inst[1], tr.f_max[0] or float("nan"), tr.r_equiv, el, thr))


def verdicts_beside(rw):
    """Every kept multibody/crack/overburden case's verdict beside rockwatch simulate on its ground.csv."""
    import csv
    idx = os.path.join(ROOT, "tests", "data", "truths", "index.csv")
    if not os.path.exists(idx):
        return
    print("\n-- verdicts on the kept cases beside `rockwatch simulate --record ground.csv --units mps2 --r impulse"
          " --json` (the paper wall, as the monitor is told)")
    agree = {}
    for r in csv.DictReader(open(idx)):
        d = os.path.join(ROOT, "tests", "data", "truths", r["family"], r["case"])
        p = subprocess.run([rw, "simulate", "--record", os.path.join(d, "ground.csv"), "--units", "mps2", "--r",
                            "impulse", "--json"], capture_output=True, text=True)
        if p.returncode != 0:
            print("  %s/%s: rockwatch failed: %s" % (r["family"], r["case"], p.stderr.strip()[:200]))
            agree.setdefault(r["family"], [0, 0, 0])[2] += 1
            continue
        j = json.loads(p.stdout)
        rc = bool(j["collapsed"] or j.get("collapse_after_end"))
        tc = r["collapsed"] == "true"
        a = agree.setdefault(r["family"], [0, 0, 0])
        a[0] += rc == tc
        a[1] += 1
        print("  %-12s %-48s truth %-8s rockwatch %-8s max|x| %.4f / %.4f m" % (
            r["family"], r["case"], "collapse" if tc else "survive", "collapse" if rc else "survive",
            json.load(open(os.path.join(d, "truth.json")))["max_abs_x_m"], j["max_abs_x_m"]))
    for fam, (n_ok, n, nf) in agree.items():
        print("  %s: rockwatch's verdict = the truth's on %d of %d%s" % (fam, n_ok, n, "" if not nf else
                                                                          " (%d not run)" % nf))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rockwatch", default=os.path.join(ROOT, "build", "release", "host_tools", "rockwatch"))
    a = ap.parse_args()
    t0 = time.time()
    quick()
    if not a.quick:
        full(a.rockwatch)
    print("%s (%.0f s)" % ("all checks passed" if not FAILS else "%d check(s) failed" % len(FAILS), time.time() - t0))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
