"""PEER .AT2 reading, PGA scaling and the 5-significant-digit rounding of everything the truths store."""
import math
import re

import numpy as np


def sig5(x):
    """Round to 5 significant digits (the precision of every stored number)."""
    return float("%.5g" % x)


def read_at2(path):
    """(dt [s], acceleration [g]) of a PEER NGA .AT2 file (header variants `NPTS= n, DT= d SEC`,
    `NPTS = n , DT = d SEC,` and `n d NPTS, DT`)."""
    with open(path, "r", encoding="latin-1") as f:
        lines = f.read().splitlines()
    head = lines[3]
    m_n = re.search(r"NPTS\s*=\s*(\d+)", head, re.I)
    m_d = re.search(r"DT\s*=\s*([0-9.Ee+-]+)", head, re.I)
    if m_n and m_d:
        npts, dt = int(m_n.group(1)), float(m_d.group(1))
    else:
        tok = head.split()
        npts, dt = int(tok[0]), float(tok[1])
    vals = []
    for ln in lines[4:]:
        vals.extend(float(v) for v in ln.split())
    acc = np.array(vals[:max(npts, len(vals))])
    return dt, acc


def arias_time(acc, dt, fraction):
    """Time at which the Arias intensity reaches `fraction` of its total."""
    ia = np.cumsum(acc * acc) * dt
    k = int(np.searchsorted(ia, fraction * ia[-1]))
    return min(k, len(acc) - 1) * dt


def scaled_ground(acc_g, dt, pga_g, g, window_s=None):
    """ü [m/s²] scaled to PGA pga_g (max |ü| over the whole record = pga_g·g), cut to [0, window_s], each value rounded
    to 5 significant digits (the ground the truth feels is exactly the ground stored)."""
    a = np.asarray(acc_g, dtype=float)
    scale = pga_g * g / float(np.max(np.abs(a)))
    if window_s is not None:
        a = a[: int(round(window_s / dt)) + 1]
    return np.array([sig5(v * scale) for v in a])
