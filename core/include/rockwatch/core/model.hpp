// Equation of motion of the two-block wall (SPEC §1–2):
//   (p1 + p2 x + p3 x²) ẍ + (p4 + p5 x) x = p6
// The coefficients are affine in ü and G = g + v̈, so they are split once, at initialisation, into constants
// per side; evaluating them per step is then a handful of multiply-adds in the stepper's scalar type.
#pragma once

#include <cmath>
#include <cstdint>

#include "rockwatch/core/wall.hpp"

namespace rockwatch::core {

// `linear` (default, the paper's model): p2 = p3 = p5 = 0. `full`: every term of SPEC §1.
enum class ModelKind : std::uint8_t { linear = 0, full = 1 };

template <typename Scalar>
struct Coefficients {
  Scalar p1, p2, p3;  // mass terms: M(x) = p1 + p2 x + p3 x²  [kg]
  Scalar p4, p5;      // stiffness terms: K(x) = p4 + p5 x      [N/m], [N/m²]
  Scalar p6;          // force at x = 0                        [N]
};

// Per-side constants of SPEC §1, with index 0 = side −1 (x < 0), 1 = side +1 (x > 0).
//   p1 = c1
//   p2 = s·c2,  p3 = c3
//   p4 = c4_fp[side] + c4_g·G + s·c4_u·ü
//   p5 = c5_u·ü − s·(c5_fp + c5_g·G)
//   p6 = −s·c6_fp[side] − c6_u·ü − s·c6_g·G
// Units: p-coefficients per metre of wall; G and ü in m/s².
template <typename Scalar>
struct ModelConstants {
  Scalar c1;
  Scalar c2, c3;
  Scalar c4_fp[2], c4_g, c4_u;
  Scalar c5_u, c5_fp, c5_g;
  Scalar c6_fp[2], c6_u, c6_g;
  ModelKind kind;

  template <typename Other>
  ModelConstants<Other> cast() const {
    ModelConstants<Other> o;
    o.c1 = Other(c1);
    o.c2 = Other(c2);
    o.c3 = Other(c3);
    for (int i = 0; i < 2; ++i) {
      o.c4_fp[i] = Other(c4_fp[i]);
      o.c6_fp[i] = Other(c6_fp[i]);
    }
    o.c4_g = Other(c4_g);
    o.c4_u = Other(c4_u);
    o.c5_u = Other(c5_u);
    o.c5_fp = Other(c5_fp);
    o.c5_g = Other(c5_g);
    o.c6_u = Other(c6_u);
    o.c6_g = Other(c6_g);
    o.kind = kind;
    return o;
  }
};

constexpr int side_index(Side s) { return s == Side::positive ? 1 : 0; }

inline ModelConstants<double> model_constants(const WallParameters& w, ModelKind kind) {
  const WallProperties p = wall_properties(w);
  const double b = w.b_m, h1 = w.h1_m, h2 = w.h2_m, fp = w.fp_npm;
  const double m1 = p.m1_kgpm, m2 = p.m2_kgpm, j1 = p.j1_kgm, j2 = p.j2_kgm;
  const double b2 = b * b, b3 = b2 * b;
  const double h1s = h1 * h1, h2s = h2 * h2;
  const double d[2] = {p.d_minus, p.d_plus};
  const bool full = kind == ModelKind::full;

  ModelConstants<double> c{};
  c.kind = kind;
  c.c1 = j1 / h1s + j2 / h2s + (m1 + m2) / 4.0 + b2 * m1 / (4.0 * h1s) + b2 * m2 / (4.0 * h2s) +
         b2 * m2 / (h1 * h2) + b2 * m2 / h1s;
  c.c2 = full ? b * (j1 + j2) / (h1s * h2s) - 3.0 * b * m2 / (4.0 * h1s) + b * m1 / (4.0 * h2s) -
                    b * m2 / (h1 * h2) +
                    b3 * (m1 / (4.0 * h1s * h2s) + m2 / (2.0 * h1 * h2s * h2) + 5.0 * m2 / (4.0 * h1s * h2s) +
                          m2 / (2.0 * h1s * h1 * h2))
              : 0.0;
  c.c3 = full ? -b2 * m2 * (1.0 / (2.0 * h1 * h2s * h2) + 1.0 / (h1s * h2s) + 1.0 / (2.0 * h1s * h1 * h2)) : 0.0;
  for (int i = 0; i < 2; ++i) {
    c.c4_fp[i] = -fp * (1.0 / h1 + 1.0 / h2 - (b2 / (h1 * h2)) * (d[i] / h1 + 1.0 / h2));
    c.c6_fp[i] = fp * b * (1.0 / h1 + d[i] / h2);
  }
  c.c4_g = -(m2 / (2.0 * h2) + m2 / h1 + m1 / (2.0 * h1) - (b2 / (h1 * h2)) * (m2 / (2.0 * h1) + m2 / h2 + m1 / (2.0 * h2)));
  c.c4_u = 0.5 * b * (m1 + m2) * (1.0 / h1s + 1.0 / h2s);
  c.c5_u = full ? b2 * (m1 + m2) / (2.0 * h1s * h2s) : 0.0;
  c.c5_fp = full ? b * fp * (1.0 / (h1 * h2s) + 1.0 / (h1s * h2)) : 0.0;
  c.c5_g = full ? b * (m1 / (2.0 * h1 * h2s) + m2 / (h1 * h2s) + m2 / (2.0 * h1s * h2)) : 0.0;
  c.c6_u = 0.5 * (m1 + m2);
  c.c6_g = b * (m1 / (2.0 * h1) + m2 / (2.0 * h2) + m2 / h1);
  return c;
}

// Coefficients on `side` for ground input ü [m/s²] and G = g + v̈ [m/s²].
template <typename Scalar>
Coefficients<Scalar> evaluate(const ModelConstants<Scalar>& c, Side side, Scalar ug_mps2, Scalar gravity_mps2) {
  const int i = side_index(side);
  const bool pos = side == Side::positive;
  Coefficients<Scalar> k;
  k.p1 = c.c1;
  k.p2 = pos ? c.c2 : -c.c2;
  k.p3 = c.c3;
  const Scalar u4 = c.c4_u * ug_mps2;
  k.p4 = c.c4_fp[i] + c.c4_g * gravity_mps2 + (pos ? u4 : -u4);
  const Scalar s5 = c.c5_fp + c.c5_g * gravity_mps2;
  k.p5 = c.c5_u * ug_mps2 - (pos ? s5 : -s5);
  const Scalar s6 = c.c6_fp[i] + c.c6_g * gravity_mps2;
  k.p6 = -(pos ? s6 : -s6) - c.c6_u * ug_mps2;
  return k;
}

// Generalised mass M(x) and restoring-plus-driving force F(x) = p6 − (p4 + p5 x) x of SPEC §4.
template <typename Scalar>
Scalar mass_at(const Coefficients<Scalar>& k, Scalar x_m) {
  return k.p1 + (k.p2 + k.p3 * x_m) * x_m;
}
template <typename Scalar>
Scalar force_at(const Coefficients<Scalar>& k, Scalar x_m) {
  return k.p6 - (k.p4 + k.p5 * x_m) * x_m;
}

// Ground acceleration that starts rocking towards `side` (paper eq. 19 as corrected in SPEC §2) [m/s²].
// Rocking towards x > 0 starts when ü < −threshold(+); towards x < 0 when ü > threshold(−).
inline double threshold_mps2(const ModelConstants<double>& c, Side side, double gravity_mps2) {
  return 2.0 * (c.c6_fp[side_index(side)] + c.c6_g * gravity_mps2) / (2.0 * c.c6_u);
}

// Static instability displacement magnitude on `side`: root of the restoring force with ü = v̈ = 0 (SPEC §2).
inline double x_inst_m(const ModelConstants<double>& c, Side side, double g_mps2) {
  const Coefficients<double> k = evaluate(c, side, 0.0, g_mps2);
  const double s = sign_of(side);
  if (k.p5 == 0.0) return std::fabs(k.p6 / k.p4);
  // p5 x² + p4 x − p6 = 0; take the root on this side nearest zero, in the cancellation-free form.
  const double disc = k.p4 * k.p4 + 4.0 * k.p5 * k.p6;
  if (disc < 0.0) return std::fabs(k.p6 / k.p4);
  const double q = -0.5 * (k.p4 + std::copysign(std::sqrt(disc), k.p4));
  const double r1 = q / k.p5, r2 = -k.p6 / q;
  const bool ok1 = s * r1 > 0.0, ok2 = s * r2 > 0.0;
  if (ok1 && ok2) return std::fmin(std::fabs(r1), std::fabs(r2));
  return std::fabs(ok1 ? r1 : r2);
}

// Potential energy on `side` for free motion (ü = v̈ = 0): V(x) = −∫₀ˣ F dx [J/m].
// Linear model: V = c_s|x| − ½ k x² with c_s = |p6|, k = |p4| (SPEC §2). The full model adds the p5 term
// (an extension: SPEC defines the barrier for the linear model only).
template <typename Scalar>
Scalar potential_energy(const Coefficients<Scalar>& free_k, Scalar x_m) {
  return -(free_k.p6 * x_m) + free_k.p4 * x_m * x_m / Scalar(2) + free_k.p5 * x_m * x_m * x_m / Scalar(3);
}

// Mechanical energy E = ½ M(x) ẋ² + V(x) in free motion [J/m].
template <typename Scalar>
Scalar mechanical_energy(const Coefficients<Scalar>& free_k, Scalar x_m, Scalar xd_mps) {
  return mass_at(free_k, x_m) * xd_mps * xd_mps / Scalar(2) + potential_energy(free_k, x_m);
}

// Energy barrier on `side`: V(x_inst) = c_s² / (2k) for the linear model [J/m].
inline double energy_barrier_jpm(const ModelConstants<double>& c, Side side, double g_mps2) {
  const Coefficients<double> k = evaluate(c, side, 0.0, g_mps2);
  return potential_energy(k, sign_of(side) * x_inst_m(c, side, g_mps2));
}

}  // namespace rockwatch::core
