"""Planar rigid-multibody engine for a two-block wall (Moreau–Jean time stepping, unilateral contacts).

Independent of rockwatch's model (docs/SPEC.md §1–§4): no small angles, no p-coefficients, no restitution
coefficient. Two rigid blocks in the vertical plane, 3 coordinates each (centre of mass X, Y and the angle φ,
counter-clockwise), per metre of wall. The frame moves with the ground (supports): each block feels the
inertial force −m·ü (ü > 0 is the ground accelerating towards +x, so the wall is pushed towards x < 0, as in
SPEC §1). Contacts:

* ground: block 1's bottom corners on the ground (y = 0), Coulomb friction on the interface;
* mid-height joint: block 2's bottom corners on block 1's top face and block 1's top corners on block 2's
  bottom face, Coulomb friction on the interface;
* top restraint: block 2's top corners against two vertical guide faces at x = ±b/2 (frictionless by default:
  the restraint holds the top horizontally and leaves it free vertically).

Each step (size h, symplectic: v first, then q_{k+1} = q_k + h v_{k+1}) solves for the contact impulses P the
velocity-level complementarity problem of Moreau–Jean with Newton's impact law (e = 0):
0 ≤ P_n ⊥ U_n(v_{k+1}) + g_k/h ≥ 0 (open gaps: the contact closes plastically within the step it would
penetrate; a penetration g_k < 0 is corrected by β·g_k/h), and Coulomb's law per interface |P_t| ≤ μ ΣP_n
(stick: U_t = 0; slide: P_t = −μ ΣP_n sign U_t). On a rigid face every contact point has the same tangential
velocity, so Coulomb per interface on the sum of its normal impulses is Coulomb per contact point.

The ``crushing`` interface replaces the corners of the ground and joint interfaces by n distributed no-tension
Kelvin–Voigt fibres (stiffness k per m² of interface, viscosity, compressive strength f_c): the implicit spring
0 ≤ P ⊥ U + C P + k g/(h k + c) ≥ 0 with C = 1/(h² k + h c) per fibre, and P ≤ h f_c w (w the fibre's tributary
width). A fibre at its strength crushes: its plastic depth grows so that its elastic force stays at f_c w; the
depth never recovers. This gives the elastic phase before uplift, the pivot moving inward as the corners crush,
and energy lost in the interface instead of by a restitution coefficient.

The complementarity problem is solved by an active-set method (statuses warm-started from the previous step,
every violated status flipped, a regularisation 1e-9·max diag W for redundant contacts), with a projected
Gauss–Seidel fallback if the active set cycles.
"""
import math

import numpy as np

# row kinds
NORMAL, TANGENT, EQUALITY = 0, 1, 2
# statuses: normal 0 off, 1 on, 2 at cap; tangent 0 free, 1 stick, 2 slide+, 3 slide-


def default_params():
    return {
        "b": 0.10, "h1": 1.75, "h2": 1.75, "rho": 1800.0, "g": 9.81,
        "Fp_N_per_m": 0.0,          # vertical load on block 2's top face centre
        "mu": 0.7,                  # Coulomb at the ground and the joint
        "mu_guide": 0.0,            # top guides: free vertically
        "h_step_s": 0.0005,         # time step (upper bound; a record's dt is divided evenly)
        "beta_stab": 0.2,           # penetration correction
        "interface": {"kind": "rigid"},
    }


def _rot(phi, x, y):
    c, s = math.cos(phi), math.sin(phi)
    return c * x - s * y, s * x + c * y


class TwoBlockWall:
    """State and one Moreau–Jean step of the two-block wall. Units SI, per metre of wall."""

    def __init__(self, params):
        p = dict(default_params())
        p.update(params)
        self.p = p
        self.b, self.h1, self.h2 = float(p["b"]), float(p["h1"]), float(p["h2"])
        self.g = float(p["g"])
        rho = float(p["rho"])
        b, h1, h2 = self.b, self.h1, self.h2
        self.m1, self.m2 = rho * b * h1, rho * b * h2
        self.J1 = self.m1 * (b * b + h1 * h1) / 12.0
        self.J2 = self.m2 * (b * b + h2 * h2) / 12.0
        self.Fp = float(p["Fp_N_per_m"])
        self.mu, self.mu_guide = float(p["mu"]), float(p["mu_guide"])
        self.beta = float(p["beta_stab"])
        self.minv = np.array([1 / self.m1, 1 / self.m1, 1 / self.J1, 1 / self.m2, 1 / self.m2, 1 / self.J2])
        self.mass = 1.0 / self.minv
        itf = p["interface"]
        self.kind = itf["kind"]
        if self.kind == "crushing":
            n = int(itf["n_fibres"])
            self.fib_s = [(-0.5 + i / (n - 1)) * b for i in range(n)]
            w = [b / (n - 1)] * n
            w[0] = w[-1] = 0.5 * b / (n - 1)
            self.fib_k = [float(itf["k_N_per_m3"]) * wi for wi in w]
            self.fib_c = [float(itf["c_Ns_per_m3"]) * wi for wi in w]
            self.fib_cap = [float(itf["fc_Pa"]) * wi for wi in w]
            self.crush_ground = [0.0] * n
            self.crush_joint = [0.0] * n
        elif self.kind != "rigid":
            raise ValueError("interface kind must be rigid or crushing")
        self.q = np.array([0.0, h1 / 2, 0.0, 0.0, h1 + h2 / 2, 0.0])
        self.v = np.zeros(6)
        self.status = {}
        self.driver = None  # (velocity) of the joint centre, for a static push
        self.last_driver_force = 0.0
        self.fallbacks = 0
        self.y0 = (h1 / 2, h1 + h2 / 2)

    # ---------------------------------------------------------------- kinematics
    def joint_centre_x(self, q=None):
        q = self.q if q is None else q
        a1x, _ = _rot(q[2], 0.0, self.h1 / 2)
        a2x, _ = _rot(q[5], 0.0, -self.h2 / 2)
        return 0.5 * (q[0] + a1x + q[3] + a2x)

    def sensor_point(self, q=None, v=None):
        """Block 1's top face centre (the accelerometer just below the joint): position, velocity, axis."""
        q = self.q if q is None else q
        v = self.v if v is None else v
        rx, ry = _rot(q[2], 0.0, self.h1 / 2)
        pos = (q[0] + rx, q[1] + ry)
        vel = (v[0] - v[2] * ry, v[1] + v[2] * rx)
        return pos, vel, (math.cos(q[2]), math.sin(q[2]))

    def energy(self):
        """Kinetic + gravity + overburden potential, relative to the initial rest configuration."""
        ke = 0.5 * float(np.dot(self.mass, self.v * self.v))
        ytop = self.q[4] + _rot(self.q[5], 0.0, self.h2 / 2)[1]
        pe = self.g * (self.m1 * (self.q[1] - self.y0[0]) + self.m2 * (self.q[4] - self.y0[1]))
        pe += self.Fp * (ytop - self.ytop0)
        return ke + pe

    @property
    def ytop0(self):
        return self.h1 + self.h2

    # ---------------------------------------------------------------- contacts
    def _contacts(self, h):
        """Rows: list of (jacobian 6-list, kind, offset, compliance C, cap, group, key, tag)."""
        q, b = self.q, self.b
        h1, h2 = self.h1, self.h2
        X1, Y1, f1, X2, Y2, f2 = q
        rows = []
        hb = 0.5 * b
        near = 0.004 + 0.0  # candidate distance

        def prow(blk, px, py, dx, dy):
            # jacobian of d·v(point p) for block blk (1 or 2)
            if blk == 1:
                rx, ry = px - X1, py - Y1
                return [dx, dy, rx * dy - ry * dx, 0.0, 0.0, 0.0]
            rx, ry = px - X2, py - Y2
            return [0.0, 0.0, 0.0, dx, dy, rx * dy - ry * dx]

        def rel(px, py, dx, dy, a, bb):
            # d·(v_a(p) − v_b(p))
            ja, jb = prow(a, px, py, dx, dy), prow(bb, px, py, dx, dy)
            return [ja[i] - jb[i] for i in range(6)]

        c1, s1 = math.cos(f1), math.sin(f1)
        c2, s2 = math.cos(f2), math.sin(f2)
        n1 = (-s1, c1)          # block 1 top face outward normal
        t1 = (c1, s1)
        n2 = (s2, -c2)          # block 2 bottom face outward normal
        t2 = (c2, s2)
        top1 = (X1 - s1 * h1 / 2, Y1 + c1 * h1 / 2)     # block 1 top face centre
        bot2 = (X2 + s2 * h2 / 2, Y2 - c2 * h2 / 2)     # block 2 bottom face centre
        bot1 = (X1 + s1 * h1 / 2, Y1 - c1 * h1 / 2)
        tol_face = 0.02 * b
        rigid = self.kind == "rigid"

        def normal_offset(gap):
            return gap / h if gap >= 0 else self.beta * gap / h

        # ---- ground
        if rigid:
            for sx in (-1, 1):
                px, py = X1 + c1 * sx * hb - s1 * (-h1 / 2), Y1 + s1 * sx * hb + c1 * (-h1 / 2)
                gap = py
                if gap < near:
                    rows.append((prow(1, px, py, 0.0, 1.0), NORMAL, normal_offset(gap), 0.0, math.inf, 0, ("g", sx), None))
        else:
            for j, sj in enumerate(self.fib_s):
                px, py = X1 + c1 * sj + s1 * h1 / 2, Y1 + s1 * sj - c1 * h1 / 2
                gap = py + self.crush_ground[j]
                if gap < near:
                    k, c = self.fib_k[j], self.fib_c[j]
                    C = 1.0 / (h * h * k + h * c)
                    rows.append((prow(1, px, py, 0.0, 1.0), NORMAL, k * gap / (h * k + c), C, h * self.fib_cap[j], 0,
                                 ("gf", j), ("g", j, py)))
        rows.append((prow(1, bot1[0], bot1[1], 1.0, 0.0), TANGENT, 0.0, 0.0, math.inf, 0, ("gt",), None))
        # ---- joint
        if rigid:
            for sx in (-1, 1):
                px, py = X2 + c2 * sx * hb - s2 * (-h2 / 2), Y2 + s2 * sx * hb + c2 * (-h2 / 2)
                dx, dy = px - top1[0], py - top1[1]
                gap = dx * n1[0] + dy * n1[1]
                along = dx * t1[0] + dy * t1[1]
                if gap < near and abs(along) <= hb + tol_face:
                    rows.append((rel(px, py, n1[0], n1[1], 2, 1), NORMAL, normal_offset(gap), 0.0, math.inf, 1, ("j2", sx), None))
            for sx in (-1, 1):
                px, py = X1 + c1 * sx * hb - s1 * (h1 / 2), Y1 + s1 * sx * hb + c1 * (h1 / 2)
                dx, dy = px - bot2[0], py - bot2[1]
                gap = dx * n2[0] + dy * n2[1]
                along = dx * t2[0] + dy * t2[1]
                if gap < near and abs(along) <= hb + tol_face:
                    rows.append((rel(px, py, n2[0], n2[1], 1, 2), NORMAL, normal_offset(gap), 0.0, math.inf, 1, ("j1", sx), None))
        else:
            for j, sj in enumerate(self.fib_s):
                px, py = X2 + c2 * sj + s2 * h2 / 2, Y2 + s2 * sj - c2 * h2 / 2
                dx, dy = px - top1[0], py - top1[1]
                gapg = dx * n1[0] + dy * n1[1]
                gap = gapg + self.crush_joint[j]
                along = dx * t1[0] + dy * t1[1]
                if gap < near and abs(along) <= hb + tol_face:
                    k, c = self.fib_k[j], self.fib_c[j]
                    C = 1.0 / (h * h * k + h * c)
                    rows.append((rel(px, py, n1[0], n1[1], 2, 1), NORMAL, k * gap / (h * k + c), C, h * self.fib_cap[j], 1,
                                 ("jf", j), ("j", j, None)))
        rows.append((rel(top1[0], top1[1], t1[0], t1[1], 2, 1), TANGENT, 0.0, 0.0, math.inf, 1, ("jt",), None))
        # ---- top guides (block 2's top corners against x = ∓b/2)
        for sx in (-1, 1):
            px, py = X2 + c2 * sx * hb - s2 * (h2 / 2), Y2 + s2 * sx * hb + c2 * (h2 / 2)
            gap = (px + hb) if sx < 0 else (hb - px)
            if gap < near:
                rows.append((prow(2, px, py, float(-sx), 0.0), NORMAL, normal_offset(gap), 0.0, math.inf, 2 + (sx > 0),
                             ("t", sx), None))
        if self.mu_guide > 0:
            for sx in (-1, 1):
                px, py = X2 + c2 * sx * hb - s2 * (h2 / 2), Y2 + s2 * sx * hb + c2 * (h2 / 2)
                rows.append((prow(2, px, py, 0.0, 1.0), TANGENT, 0.0, 0.0, math.inf, 2 + (sx > 0), ("tt", sx), None))
        if self.driver is not None:
            rows.append((prow(1, top1[0], top1[1], 1.0, 0.0), EQUALITY, -self.driver, 0.0, math.inf, -1, ("drv",), None))
        return rows

    # ---------------------------------------------------------------- solver
    def _solve(self, W, q, kinds, C, caps, groups, keys):
        m = len(q)
        mu_g = (self.mu, self.mu, self.mu_guide, self.mu_guide)
        status = self.status
        st = np.array([status.get(k, 0 if kinds[i] == NORMAL else 1) for i, k in enumerate(keys)], dtype=np.int64)
        is_n = kinds == NORMAL
        is_t = kinds == TANGENT
        is_e = kinds == EQUALITY
        finite_cap = np.isfinite(caps)
        st[is_n & (st == 2) & ~finite_cap] = 1
        eps = 1e-9 * float(W.diagonal().max())
        members = {}
        for i in range(m):
            if is_n[i]:
                members.setdefault(groups[i], []).append(i)
        t_rows = [i for i in range(m) if is_t[i]]
        diag_idx = np.arange(m)
        reg = np.where(is_n, C, 0.0) + eps
        tolv, tolp = 1e-10, 1e-12
        converged = False
        P = np.zeros(m)
        for it in range(40):
            wrow = (st == 1) | is_e
            A = W * wrow[:, None]
            A[diag_idx, diag_idx] = np.where(wrow, A[diag_idx, diag_idx] + reg, 1.0)
            rhs = np.where(wrow, -q, np.where(is_n & (st == 2), caps, 0.0))
            for i in t_rows:
                if st[i] >= 2:
                    sg = mu_g[groups[i]] if st[i] == 2 else -mu_g[groups[i]]
                    for j in members.get(groups[i], ()):
                        A[i, j] -= sg
            P = np.linalg.solve(A, rhs)
            U = W @ P + q
            w = U + C * P
            new = st.copy()
            on = is_n & (st == 1)
            new[on & (P < -tolp)] = 0
            new[on & finite_cap & (P > caps)] = 2
            new[is_n & (st == 0) & (w < -tolv)] = 1
            new[is_n & (st == 2) & (w > tolv)] = 1
            for i in t_rows:
                grp = groups[i]
                mu = mu_g[grp]
                N = 0.0
                for j in members.get(grp, ()):
                    if st[j] > 0:
                        N += P[j]
                s = st[i]
                if N <= 0.0 or mu <= 0.0:
                    new[i] = 0
                elif s == 0:
                    new[i] = 1
                elif s == 1 and abs(P[i]) > mu * N * (1 + 1e-9) + tolp:
                    new[i] = 2 if P[i] > 0 else 3
                elif s == 2 and U[i] > tolv:
                    new[i] = 1
                elif s == 3 and U[i] < -tolv:
                    new[i] = 1
            if np.array_equal(new, st):
                converged = True
                break
            st = new
        if not converged:  # the active set cycled: projected Gauss–Seidel
            self.fallbacks += 1
            P = self._pgs(W, q, kinds, C, caps, groups, members, {0: mu_g[0], 1: mu_g[1], 2: mu_g[2], 3: mu_g[3]}, P)
            for i in range(m):
                if kinds[i] == NORMAL:
                    st[i] = 0 if P[i] <= 0 else (2 if P[i] >= caps[i] else 1)
                elif kinds[i] == TANGENT:
                    st[i] = 1
        stl = st.tolist()
        self.status = {keys[i]: stl[i] for i in range(m)}
        return P

    def _pgs(self, W, q, kinds, C, caps, groups, members, mu_g, P0):
        m = len(q)
        P = np.maximum(P0, 0.0) * (kinds == NORMAL) + P0 * (kinds != NORMAL)
        P = P.copy()
        Wl = W.tolist()
        for sweep in range(5000):
            delta = 0.0
            for i in range(m):
                wi = Wl[i]
                u = q[i] + sum(wi[j] * P[j] for j in range(m))
                d = wi[i] + (C[i] if kinds[i] == NORMAL else 0.0)
                if d <= 0:
                    continue
                if kinds[i] == NORMAL:
                    new = min(max(P[i] - (u + C[i] * P[i]) / d, 0.0), caps[i])
                elif kinds[i] == TANGENT:
                    lim = mu_g[groups[i]] * sum(P[j] for j in members.get(groups[i], ()))
                    new = min(max(P[i] - u / d, -lim), lim)
                else:
                    new = P[i] - u / d
                delta = max(delta, abs(new - P[i]))
                P[i] = new
            if delta < 1e-13:
                break
        return P

    # ---------------------------------------------------------------- step
    def step(self, h, ug):
        """One step of size h with ground acceleration ug (m/s², at the step's middle)."""
        rows = self._contacts(h)
        X1, Y1, f1, X2, Y2, f2 = self.q
        # external forces: gravity, inertia of the moving frame, overburden at block 2's top face centre
        rtx, _ = _rot(f2, 0.0, self.h2 / 2)
        f = np.array([-self.m1 * ug, -self.m1 * self.g, 0.0,
                      -self.m2 * ug, -self.m2 * self.g - self.Fp, -rtx * self.Fp])
        vfree = self.v + h * self.minv * f
        H = np.array([r[0] for r in rows])
        cols = np.array([(r[1], r[2], r[3], r[4]) for r in rows]).T
        kinds = cols[0].astype(np.int64)
        off, C, caps = cols[1], cols[2], cols[3]
        groups = [r[5] for r in rows]
        keys = [r[6] for r in rows]
        HM = H * self.minv
        W = HM @ H.T
        qv = H @ vfree + off
        P = self._solve(W, qv, kinds, C, caps, groups, keys)
        self.v = vfree + HM.T @ P
        self.q = self.q + h * self.v
        for i, r in enumerate(rows):
            if r[6][0] == "drv":
                self.last_driver_force = P[i] / h
        if self.kind == "crushing":
            self._crush_update(rows, P, h)
        return P

    def _crush_update(self, rows, P, h):
        # a fibre at its strength crushes: the plastic depth keeps its elastic force at the strength
        X1, Y1, f1, X2, Y2, f2 = self.q
        c1, s1 = math.cos(f1), math.sin(f1)
        c2, s2 = math.cos(f2), math.sin(f2)
        top1 = (X1 - s1 * self.h1 / 2, Y1 + c1 * self.h1 / 2)
        for i, r in enumerate(rows):
            tag = r[7]
            if tag is None or P[i] < r[4] * (1 - 1e-9):
                continue
            j = tag[1]
            sj = self.fib_s[j]
            k = self.fib_k[j]
            if tag[0] == "g":
                gap = Y1 + s1 * sj - c1 * self.h1 / 2
                self.crush_ground[j] = max(self.crush_ground[j], -gap - self.fib_cap[j] / k)
            else:
                px, py = X2 + c2 * sj + s2 * self.h2 / 2, Y2 + s2 * sj - c2 * self.h2 / 2
                gap = (px - top1[0]) * (-s1) + (py - top1[1]) * c1
                self.crush_joint[j] = max(self.crush_joint[j], -gap - self.fib_cap[j] / k)

    def reset_status(self):
        self.status = {}

    def tipped(self):
        return abs(self.q[2]) > 0.6 or abs(self.q[5]) > 0.6 or self.q[1] < 0.0
