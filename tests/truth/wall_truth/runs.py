"""What a truth is run through: settling, static push, snap-back release, a record; the sensor model; r from impacts."""
import math

import numpy as np

from .engine import TwoBlockWall
from .kernel import FastWall


def make_wall(tp, engine="c"):
    """A settled wall (crushing interfaces settle 1 s under their own weight; the reference energy is taken there)."""
    w = (FastWall if engine == "c" else TwoBlockWall)(tp)
    h = float(tp["h_step_s"])
    if w.kind == "crushing":
        n = int(round(1.0 / h))
        for _ in range(n):
            w.step(h, 0.0)
        w.v[:] = 0.0
    w.e_rest = w.energy()
    return w


def _nsub(dt, h_max):
    return max(1, int(math.ceil(dt / h_max - 1e-9)))


def static_push(tp, side=1, x_end=None, v_push=0.02, engine="c"):
    """Quasi-static push: the mid-height joint's centre driven at v_push (m/s) towards `side`; returns (x, F) every
    1 ms (F [N/m] the driving force, along `side`) and x_inst: |x| where the lateral resistance first falls to 0."""
    w = make_wall(tp, engine)
    h = float(tp["h_step_s"])
    x_end = 1.4 * w.b if x_end is None else x_end
    n = _nsub(0.001, h)
    hh = 0.001 / n
    xs, fs = [], []
    k = 0
    while abs(w.joint_centre_x()) < x_end and not w.tipped():
        k += 1
        w.driver = side * v_push * min(1.0, k / 200.0)  # ramped over 0.2 s
        if engine == "c":
            w.steps(hh, n, 0.0, 0.0)
        else:
            for _ in range(n):
                w.step(hh, 0.0)
        xs.append(side * w.joint_centre_x())
        fs.append(side * w.last_driver_force)
    xs, fs = np.array(xs), np.array(fs)
    x_inst = None
    for i in range(1, len(xs)):
        if xs[i] > 0.002 and fs[i - 1] > 0 >= fs[i]:
            x_inst = float(xs[i - 1] + (xs[i] - xs[i - 1]) * fs[i - 1] / (fs[i - 1] - fs[i]))
            break
    return xs, fs, x_inst, w


def sensor_accel(w, vp_prev, vp, dt, ug):
    """True specific force along the accelerometer's axis (block 1, just below the joint, +x at rest, tilting with
    the block): (absolute acceleration − gravity)·axis, the relative acceleration averaged over the sample interval."""
    _, _, (ex, ey) = w.sensor_point()
    ax = ug + (vp[0] - vp_prev[0]) / dt
    ay = (vp[1] - vp_prev[1]) / dt + w.g
    return ax * ex + ay * ey


class Response:
    pass


def run(tp, ug, dt, x_inst, t_extra=5.0, wall=None, engine="c", kappa=2.0, stop_on_collapse=True):
    """The truth through ground motion ug (m/s², samples every dt from t = 0), then t_extra s of free motion.
    Returns a Response with the samples (t, x, a_true, E) up to collapse, and the verdict."""
    w = make_wall(tp, engine) if wall is None else wall
    h_max = float(tp["h_step_s"])
    n = _nsub(dt, h_max)
    h = dt / n
    xi_p, xi_n = (x_inst if isinstance(x_inst, (tuple, list)) else (x_inst, x_inst))
    n_total = len(ug) + int(round(t_extra / dt))
    ts, xs, acs, es = [], [], [], []
    _, vp_prev, _ = w.sensor_point()
    vp_prev = tuple(vp_prev)
    r = Response()
    r.collapsed, r.t_collapse, r.t_exceed, r.max_abs_x, r.tipped = False, None, None, 0.0, False
    x_prev = w.joint_centre_x()
    for k in range(n_total):
        t = k * dt
        u0 = ug[k] if k < len(ug) else 0.0
        if k > 0:
            u_prev = ug[k - 1] if k - 1 < len(ug) else 0.0
            if engine == "c":
                w.steps(h, n, u_prev, u0)
            else:
                for j in range(n):
                    w.step(h, u_prev + (j + 0.5) / n * (u0 - u_prev))
        x = w.joint_centre_x()
        _, vp, _ = w.sensor_point()
        a = sensor_accel(w, vp_prev, vp, dt, u0) if k > 0 else u0 * math.cos(w.q[2]) + w.g * math.sin(w.q[2])
        vp_prev = tuple(vp)
        ts.append(t)
        xs.append(x)
        acs.append(a)
        es.append(w.energy() - w.e_rest)
        ax = abs(x)
        r.max_abs_x = max(r.max_abs_x, ax)
        lim = xi_p if x >= 0 else xi_n
        if r.t_exceed is None and ax >= lim:
            r.t_exceed = _cross_time(t - dt, abs(x_prev), t, ax, lim) if k > 0 else t
        if ax >= kappa * lim or w.tipped():
            r.collapsed = True
            r.tipped = w.tipped()
            r.t_collapse = _cross_time(t - dt, abs(x_prev), t, ax, kappa * lim) if ax >= kappa * lim else t
            if stop_on_collapse:
                break
        x_prev = x
    r.t = np.array(ts)
    r.x = np.array(xs)
    r.a = np.array(acs)
    r.E = np.array(es)
    r.wall = w
    return r


def _cross_time(t0, y0, t1, y1, level):
    if y1 == y0:
        return t1
    return float(t0 + (t1 - t0) * min(1.0, max(0.0, (level - y0) / (y1 - y0))))


def snapback(tp, x0, t_end=8.0, rate=200.0, engine="c"):
    """A lab's free-rocking test: pushed quasi-statically to x0 (towards +x), held still, released at t = 0."""
    _, _, _, w = static_push(tp, side=1 if x0 > 0 else -1, x_end=abs(x0), engine=engine)
    w.driver = None
    w.v[:] = 0.0
    w.reset_status()
    dt = 1.0 / rate
    return run(tp, np.zeros(int(round(t_end / dt)) + 1), dt, (1e9, 1e9), t_extra=0.0, wall=w, engine=engine)


def impact_energy_ratios(resp, window_s=0.01, n_max=5):
    """Energy ratio after/before each crossing of x = 0 (an impact), the energies (kinetic + potential, relative to
    rest; at x = 0 all kinetic) taken window_s before and after the crossing; crossings with E < 1e-6 J/m skipped."""
    x, E, t = resp.x, resp.E, resp.t
    dt = t[1] - t[0]
    m = max(1, int(round(window_s / dt)))
    out = []
    for k in range(1, len(x)):
        if x[k - 1] * x[k] < 0 and k - 1 - m >= 0 and k + m < len(x):
            eb, ea = E[k - 1 - m], E[k + m]
            if eb > 1e-6:
                out.append(ea / eb)
        if len(out) >= n_max:
            break
    return out


def sensor_rows(resp, seed, offset=0.002, sx=0.0005, sa=0.05, stride=1):
    """Every stride-th sample: t, x_mid = x + offset + N(0, sx), a_mid = a + N(0, sa); seeded (numpy's PCG64)."""
    t, x, a = resp.t[::stride], resp.x[::stride], resp.a[::stride]
    rng = np.random.Generator(np.random.PCG64(seed))
    nx = rng.normal(0.0, sx, len(t))
    na = rng.normal(0.0, sa, len(t))
    return t, x + offset + nx, a + na
