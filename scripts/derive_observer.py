#!/usr/bin/python3
"""Symbolic derivation of the wall observer's model (SPEC §8, §9; core/wall_observer.hpp) with SymPy.

Writes core/include/rockwatch/core/observer/generated/observer_model.hpp: the Newmark step of the observer's model,
the rows X and V of its Jacobian (the covariance transition), the impact's saltation matrix and the two sensors'
measurement functions with their H rows, as plain double functions. The generated header is committed; run

    /usr/bin/python3 scripts/derive_observer.py            # rewrite the header
    /usr/bin/python3 scripts/derive_observer.py --check    # exit 1 when the committed header is not what this writes

after changing the model. tests/core/test_observer_model.cpp checks the generated functions against finite
differences of core::RockingStepper<double> (the stepper the observer corrects) and that the committed header is
what this script writes. The filter keeps its hand-written code (observer/prediction.hpp,
observer/acceleration_fusion.hpp): it runs in the stepper's arithmetic (single precision and Q10.53 on the M4F) in
an order chosen for its operation count, and its outputs are pinned bit for bit (the generated expressions, in
another order, would round differently); the generated code is the reference the same formulas are checked by.

The model, per unit p1, on side s at ü = 0 and G = g (what the observer linearises around):
    ẍ = κc·f_s − κk·k_s·x            f_s = −s·c_s, k_s = p4/p1 (the nominal wall's), κc, κk the corrections
state z = (x, ẋ, e, b, κc, κk) with e = √r and b the transducer's zero offset. One Newmark step (β = 1/4, γ = 1/2)
of length h, as core/newmark.hpp's linear solve:
    x̃ = x₀ + h ẋ₀ + h²/4 ẍ₀,   x₁ = (x̃ + h²/4 κc f_s) / (1 + h²/4 κk k_s),   ẋ₁ = ẋ₀ + h/2 (ẍ₀ + ẍ₁).
An impact: guard x = 0, reset ẋ⁺ = e ẋ⁻ onto the other side; the saltation matrix
    Ξ = ∂R/∂z + (f⁺ − ∂R/∂z f⁻) ∇g / (∇g · f⁻).
Measurements: the displacement transducer x_mid = x + b; the accelerometer on block 1 at the mid-height hinge
    a_mid = ü + ẍ − G x / h1.
"""
import argparse
import difflib
import pathlib
import sys

import sympy as sp
from sympy.printing.c import C99CodePrinter

ROOT = pathlib.Path(__file__).resolve().parent.parent
HEADER = ROOT / "core/include/rockwatch/core/observer/generated/observer_model.hpp"

x, xd, e, b, kc, kk = sp.symbols("x xd e b kappa_c kappa_k", real=True)
STATE = [x, xd, e, b, kc, kk]
STATE_NAMES = ["X", "V", "E", "B", "C", "K"]
h, k_s, f_s = sp.symbols("h k_s f_s", real=True)
ug, g_over_h1 = sp.symbols("ug g_over_h1", real=True)
v_before, f_after, f_before = sp.symbols("v_before f_after f_before", real=True)


def acceleration(xx):
    """ẍ of the observer's model on the current side at ü = 0, G = g."""
    return kc * f_s - kk * k_s * xx


def newmark_step():
    """(x₁, ẋ₁) of one Newmark step from (x, ẋ) — core/newmark.hpp's linear solve, p1 divided out."""
    beta_h2 = h**2 / 4
    xdd0 = acceleration(x)
    predicted = x + h * xd + beta_h2 * xdd0
    x1 = (predicted + beta_h2 * kc * f_s) / (1 + beta_h2 * kk * k_s)
    xd1 = xd + h / 2 * (xdd0 + acceleration(x1))
    return sp.simplify(x1), sp.simplify(xd1)


def saltation():
    """Rows X and V of the impact's saltation matrix over z (the parameters pass unchanged)."""
    # Just before the impact the wall is at the hinge (x = 0) with velocity ẋ⁻ and acceleration a⁻ = κc f⁻; just
    # after it, on the other side, ẋ⁺ = e ẋ⁻ and a⁺ = κc f⁺ (x = 0: the stiffness term vanishes).
    a_before, a_after = kc * f_before, kc * f_after
    reset = sp.Matrix([x, e * xd])  # R(x, ẋ, e): x stays 0, the velocity is reduced
    dr = reset.jacobian(STATE)
    flow_before = sp.Matrix([xd, a_before])
    flow_after = sp.Matrix([e * xd, a_after])
    grad_g = sp.Matrix([[1, 0, 0, 0, 0, 0]])  # guard g(z) = x
    dr_flow = dr[:, :2] * flow_before
    xi = dr + (flow_after - dr_flow) * grad_g / flow_before[0]
    xi = xi.subs(xd, v_before)
    return [sp.simplify(xi[r, c]) for r in range(2) for c in range(6)]


def measurements():
    """(x_mid, H_x) and (a_mid, H_a) over z."""
    x_mid = x + b
    a_mid = ug + acceleration(x) - g_over_h1 * x
    return (x_mid, [sp.diff(x_mid, s) for s in STATE]), (a_mid, [sp.diff(a_mid, s) for s in STATE])


class Printer(C99CodePrinter):
    """Integer powers as products (no pow()), rationals as double literals."""

    def _print_Pow(self, expr):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 0 < exp <= 4:
            return "(" + "*".join([self.parenthesize(base, 100)] * int(exp)) + ")"
        if exp.is_Integer and -4 <= exp < 0:
            return "(1.0/(" + "*".join([self.parenthesize(base, 100)] * int(-exp)) + "))"
        return super()._print_Pow(expr)


def emit(outputs, names):
    """Statements computing `outputs` into `names`, common subexpressions first."""
    printer = Printer()
    subs, reduced = sp.cse(outputs, symbols=sp.numbered_symbols("t"))
    lines = [f"  const double {s} = {printer.doprint(v)};" for s, v in subs]
    lines += [f"  {n} = {printer.doprint(v)};" for n, v in zip(names, reduced)]
    return "\n".join(lines)


def header_text():
    x1, xd1 = newmark_step()
    fx = [sp.diff(x1, s) for s in STATE]
    fv = [sp.diff(xd1, s) for s in STATE]
    (x_mid, hx), (a_mid, ha) = measurements()
    xi = saltation()
    step_body = emit([x1, xd1], ["x1_m", "xd1_mps"])
    jac_body = emit(fx + fv, [f"fx[{i}]" for i in range(6)] + [f"fv[{i}]" for i in range(6)])
    salt_body = emit(xi, [f"jx[{i}]" for i in range(6)] + [f"jv[{i}]" for i in range(6)])
    xm_body = emit([x_mid] + hx, ["const double value"] + [f"h[{i}]" for i in range(6)])
    am_body = emit([a_mid] + ha, ["const double value"] + [f"h[{i}]" for i in range(6)])
    state = ", ".join(f"{n} = {i}" for i, n in enumerate(STATE_NAMES))
    return f"""// GENERATED by scripts/derive_observer.py (SymPy) — do not edit; change the script and re-run it.
//
// The wall observer's model (SPEC §8, §9) derived symbolically: the Newmark step of ẍ = κc·f_s − κk·k_s·x (per unit
// p1, side s, ü = 0, G = g), the rows X and V of its Jacobian over z = (x, ẋ, e, b, κc, κk), the impact's saltation
// matrix and the two sensors' measurement functions with their H rows. Double, for tests and tools: the filter keeps
// its hand-written linearisation (observer/prediction.hpp, observer/acceleration_fusion.hpp: the same formulas in the
// stepper's arithmetic, ordered for the M4F, outputs pinned bit for bit); tests/core/test_observer_model.cpp checks
// these against finite differences of the stepper.
#pragma once

namespace rockwatch::core::observer_model {{

// The state's indices (WallObserver's X, V, E, B, C, K).
enum : int {{ {state} }};

// One Newmark step (β = 1/4, γ = 1/2) of length h [s] from (x [m], xd [m/s]) with stiffness k_s [1/s²] and hinge
// acceleration f_s [m/s²] of the side, scaled by κc, κk: core/newmark.hpp's linear solve.
inline void newmark_step(double h, double k_s, double f_s, double kappa_c, double kappa_k, double x, double xd,
                         double& x1_m, double& xd1_mps) {{
{step_body}
}}

// Rows X (fx) and V (fv) of ∂(x₁, ẋ₁)/∂z for that step (the other rows are the identity's).
inline void newmark_jacobian(double h, double k_s, double f_s, double kappa_c, double kappa_k, double x, double xd,
                             double (&fx)[6], double (&fv)[6]) {{
{jac_body}
}}

// Rows X (jx) and V (jv) of the saltation matrix of an impact: velocity v_before [m/s] just before it, hinge
// accelerations f_before, f_after [m/s²] of the sides before and after it (nominal; κc scales them), e = √r.
inline void impact_saltation(double v_before, double f_before, double f_after, double e, double kappa_c,
                             double (&jx)[6], double (&jv)[6]) {{
{salt_body}
}}

// The displacement transducer: x_mid = x + b [m], and H = ∂x_mid/∂z.
inline double displacement_measurement(double x, double b, double (&h)[6]) {{
{xm_body}
  return value;
}}

// The accelerometer on block 1 at the mid-height hinge: a_mid = ü + ẍ − G x/h1 [m/s²] (g_over_h1 = G/h1), and
// H = ∂a_mid/∂z.
inline double acceleration_measurement(double ug, double g_over_h1, double k_s, double f_s, double kappa_c,
                                       double kappa_k, double x, double (&h)[6]) {{
{am_body}
  return value;
}}

}}  // namespace rockwatch::core::observer_model
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the committed header, write nothing")
    args = parser.parse_args()
    text = header_text()
    if args.check:
        current = HEADER.read_text() if HEADER.exists() else ""
        if current != text:
            sys.stdout.writelines(difflib.unified_diff(current.splitlines(True), text.splitlines(True),
                                                       str(HEADER), "derived"))
            return 1
        print(f"{HEADER.relative_to(ROOT)}: up to date")
        return 0
    HEADER.parent.mkdir(parents=True, exist_ok=True)
    HEADER.write_text(text)
    print(f"wrote {HEADER.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
