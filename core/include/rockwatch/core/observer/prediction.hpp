// The wall observer's prediction (core/wall_observer.hpp): the covariance through one step of the stepper — the
// linearised Newmark step of the current side, the saltation matrix at an impact, the zeroing at rest — composed per
// input sample and applied at once (flush). The mean is not predicted here: it is the stepper's state.
//
// Rows X and V of one step's transition (transition()): with k = κk·k_s, D = 1 + h²k/4, f_c = ∂ẍ/∂κc = −s·c_s,
//   ∂x₁/∂x₀ = (1 − h²k/4)/D, ∂x₁/∂ẋ₀ = h/D, ∂ẋ₁/∂x₀ = −(h/2)k(1 + ∂x₁/∂x₀), ∂ẋ₁/∂ẋ₀ = 1 − (h/2)k ∂x₁/∂ẋ₀,
//   ∂x₁/∂κc = h² f_c/(2D),  ∂ẋ₁/∂κc = h/2·(2 f_c − k ∂x₁/∂κc),
//   ∂x₁/∂κk = −h² k_s (x₀ + x₁)/(4D),  ∂ẋ₁/∂κk = h/2·(−k_s (x₀ + x₁) − k ∂x₁/∂κk);
// at an impact (guard x = 0, reset ẋ⁺ = e·ẋ⁻) the saltation matrix
//   δx⁺ = e δx⁻,  δẋ⁺ = (a⁺ − e a⁻)/ẋ⁻ · δx⁻ + e δẋ⁻ + ẋ⁻ δe.
// scripts/derive_observer.py derives the same symbolically (observer/generated/observer_model.hpp), checked against
// finite differences of the stepper by tests/core/test_observer_model.cpp; the code below is kept by hand: it runs in
// the stepper's arithmetic (single precision on the M4F) in an order chosen for its operation count.
// Part of WallObserver (observer/wall_observer_class.hpp); core/wall_observer.hpp includes every part.
#pragma once

#include "rockwatch/core/observer/wall_observer_class.hpp"

namespace rockwatch::core {

template <typename Stepper>
inline void WallObserver<Stepper>::zero_motion_covariance() {
  for (int j = 0; j < kStates; ++j) {
    p_(X, j) = p_(j, X) = Cov(0);
    p_(V, j) = p_(j, V) = Cov(0);
  }
}

// The prediction through one step. Not applied to P at once: the step's transition F (the identity but in rows X
// and V: the Newmark step, the impact's saltation matrix, the zeroing at rest) is composed into the sample's
// transition Φ ← F Φ, and the process noise of x, ẋ into Q ← F Q Fᵀ + q (a 2 × 2 block), so that P ← Φ P Φᵀ + Q
// is done once per input sample (flush(): at the sample's end, or before a measurement update) instead of at
// every sub-step. The parameters' random walks (diagonal of q) are added at the flush, n steps' worth; their
// coupling into x, ẋ within the sample (of order walk²·F(V,E)) is left out. Exact otherwise: the same P as
// propagating step by step (to rounding).
template <typename Stepper>
inline void WallObserver<Stepper>::predict(const Stepper& stepper, const Report& report) {
  if (stepper.collapsed()) return;
  if (!stepper.moving() || report.started) zero_motion_transition();
  if (stepper.moving()) {
    const int i = side_index(stepper.side());
    Cov fx[kStates], fv[kStates];
    transition(i, x_prev_, Traits::x(stepper), fx, fv);
    compose(fx, fv);
    if (report.impacts_total > 0) {
      // Saltation through the first impact of the step (the side after it is the current one).
      ++counters_.impacts;
      // ẋ⁻ informs e in proportion to itself (a grazing impact says nothing about r); only the timing term
      // divides by it, so that one uses ẋ⁻ floored at v_min.
      const Scalar v = Traits::v_before(report);
      Scalar v_floored = v;
      if (abs(v) < v_min_) v_floored = v < Scalar(0) ? -v_min_ : v_min_;
      const Cov kc = kcc_, e = ec_, vc = cov(v);
      const Cov a_after = kc * f0_[i], a_before = kc * f0_[1 - i];
      Cov jx[kStates] = {}, jv[kStates] = {};
      jx[X] = e;
      jv[V] = e;
      // The impact informs e only when it is certain: |ẋ⁻| well above its own uncertainty (inform_sigmas σ).
      // Below, whether the real wall hit the hinge at all is a coin toss decided by the sensor noise (a wall
      // rocking at sub-noise amplitude, or one the corrections push across the hinge): the linearised jump would
      // attribute that noise to e and drag r̂ far from the truth with a confident σ. There the velocity jump
      // (1 − e)·ẋ⁻ is treated as noise instead.
      const Cov peak = cov(peak_x_);
      const bool certain = vc * vc >= inform_var_ * current_vv() && abs(v) >= v_min_ &&
                           peak * peak >= inform_peak_x2_;
      peak_x_ = Scalar(0);
      if (certain) jv[E] = vc;
      // The saltation's timing term (a⁺ − e·a⁻)/ẋ⁻: with the displacement sensor lost (x_health: an accelerometer
      // alone, a transducer gone) only for a certain impact. A model chattering at its hinge (a wall
      // just past its threshold: an impact every step, |ẋ⁻| at the floor v_min) multiplied P by the term every step,
      // σ(ẋ) 60 m/s within 0.2 s, and nothing pinned x to bring it back (SPEC §11 "An accelerometer alone"). The
      // velocity jump of such an impact is noise (below) as it is for e. With a transducer its readings pin x and the
      // term is kept as it was.
      if (certain || !lost_) jv[X] = (a_after - e * a_before) / cov(v_floored);
      compose(jx, jv);
      if (!certain) {
        const Cov jump = (Cov(1) - e) * vc;
        qa_[2] = qa_[2] + jump * jump;
        qa_zero_ = false;
      }
    }
    qa_[0] = qa_[0] + q_(X, X);
    qa_[1] = qa_[1] + q_(X, V);
    qa_[2] = qa_[2] + q_(V, V);
    qa_zero_ = false;
  }
  ++walk_steps_;
  if (!stepper.moving()) zero_motion_transition();
  const Scalar x_now = abs(Traits::x(stepper));
  if (!stepper.moving()) peak_x_ = Scalar(0);
  else if (x_now > peak_x_) peak_x_ = x_now;
  if (x_now > run_peak_x_) run_peak_x_ = x_now;
}

// Φ = I, Q = 0: nothing pending.
template <typename Stepper>
inline void WallObserver<Stepper>::reset_transition() {
  for (int c = 0; c < kStates; ++c) phi_x_[c] = phi_v_[c] = Cov(0);
  phi_x_[X] = phi_v_[V] = Cov(1);
  phi_identity_ = true;
  qa_[0] = qa_[1] = qa_[2] = Cov(0);
  qa_zero_ = true;
  walk_steps_ = 0;
}

// The motion known exactly (at rest): rows X and V of Φ and the pending noise zero (P's rows and columns X, V
// become zero at the flush, as zero_motion_covariance()).
template <typename Stepper>
inline void WallObserver<Stepper>::zero_motion_transition() {
  for (int c = 0; c < kStates; ++c) phi_x_[c] = phi_v_[c] = Cov(0);
  phi_identity_ = false;
  qa_[0] = qa_[1] = qa_[2] = Cov(0);
  qa_zero_ = true;
}

// Φ ← F Φ and Q ← F Q Fᵀ for an F that is the identity but in rows X, V (fx, fv): with Φ = [A B; 0 I] and
// F = [a b; 0 I] (blocks of rows X, V and of the other four), F Φ = [a A, a B + b; 0 I]. 24 products.
template <typename Stepper>
inline void WallObserver<Stepper>::compose(const Cov* fx, const Cov* fv) {
  if (!qa_zero_) {  // Q ← a Q aᵀ (a: F's 2 × 2 block of x, ẋ)
    const Cov t00 = fx[X] * qa_[0] + fx[V] * qa_[1], t01 = fx[X] * qa_[1] + fx[V] * qa_[2];
    const Cov t10 = fv[X] * qa_[0] + fv[V] * qa_[1], t11 = fv[X] * qa_[1] + fv[V] * qa_[2];
    qa_[0] = t00 * fx[X] + t01 * fx[V];
    qa_[1] = t00 * fv[X] + t01 * fv[V];
    qa_[2] = t10 * fv[X] + t11 * fv[V];
  }
  if (phi_identity_) {
    for (int c = 0; c < kStates; ++c) {
      phi_x_[c] = fx[c];
      phi_v_[c] = fv[c];
    }
    phi_identity_ = false;
    return;
  }
  Cov nx[kStates], nv[kStates];
  for (int c = 0; c < kStates; ++c) {
    const bool motion = c == X || c == V;
    nx[c] = fx[X] * phi_x_[c] + fx[V] * phi_v_[c];
    nv[c] = fv[X] * phi_x_[c] + fv[V] * phi_v_[c];
    if (!motion) {
      nx[c] = nx[c] + fx[c];
      nv[c] = nv[c] + fv[c];
    }
  }
  for (int c = 0; c < kStates; ++c) {
    phi_x_[c] = nx[c];
    phi_v_[c] = nv[c];
  }
}

// P(V, V) as it stands now: (Φ P Φᵀ)(V, V) + Q(V, V), without applying Φ. 42 products.
template <typename Stepper>
inline auto WallObserver<Stepper>::current_vv() const -> Cov {
  if (phi_identity_) return p_(V, V) + qa_[2];
  Cov acc = Cov(0);
  for (int r = 0; r < kStates; ++r) {
    Cov w = Cov(0);
    for (int c = 0; c < kStates; ++c) w = w + p_(r, c) * phi_v_[c];
    acc = acc + phi_v_[r] * w;
  }
  return acc + qa_[2];
}

// P ← Φ P Φᵀ + Q, the parameters' walks, then Φ = I: rows X, V of Φ P (R, 2 × 6), which are P's new rows X, V in
// the other four columns, and R Φᵀ its new 2 × 2 block of x, ẋ. 90 products; nothing when nothing is pending.
template <typename Stepper>
inline void WallObserver<Stepper>::flush() {
  if (!phi_identity_) {
    Cov rx[kStates], rv[kStates];
    for (int c = 0; c < kStates; ++c) {
      Cov ax = Cov(0), av = Cov(0);
      for (int j = 0; j < kStates; ++j) {
        ax = ax + phi_x_[j] * p_(j, c);
        av = av + phi_v_[j] * p_(j, c);
      }
      rx[c] = ax;
      rv[c] = av;
    }
    Cov xx = Cov(0), xv = Cov(0), vv = Cov(0);
    for (int j = 0; j < kStates; ++j) {
      xx = xx + rx[j] * phi_x_[j];
      xv = xv + rx[j] * phi_v_[j];
      vv = vv + rv[j] * phi_v_[j];
    }
    for (int c = 0; c < kStates; ++c) {
      if (c == X || c == V) continue;
      p_(X, c) = p_(c, X) = rx[c];
      p_(V, c) = p_(c, V) = rv[c];
    }
    p_(X, X) = xx;
    p_(X, V) = p_(V, X) = xv;
    p_(V, V) = vv;
  }
  if (!qa_zero_) {
    p_(X, X) = p_(X, X) + qa_[0];
    p_(X, V) = p_(X, V) + qa_[1];
    p_(V, X) = p_(X, V);
    p_(V, V) = p_(V, V) + qa_[2];
  }
  for (int k = 0; k < walk_steps_; ++k) {  // n additions: the same sum as step by step, and no product
    p_(E, E) = p_(E, E) + q_(E, E);
    p_(B, B) = p_(B, B) + q_(B, B);
    p_(C, C) = p_(C, C) + q_(C, C);
    p_(K, K) = p_(K, K) + q_(K, K);
  }
  reset_transition();
}

// Rows X, V of the covariance transition of one step on side i from x0 to x1 (the linearised Newmark step with the
// estimated stiffness, and its derivatives by κc and κk: see the header); the other rows are the identity's.
// One division (1/D), products otherwise.
template <typename Stepper>
inline void WallObserver<Stepper>::transition(int i, Scalar x0, Scalar x1, Cov* fx, Cov* fv) const {
  const Cov k = kkc_ * k0_[i];
  const Cov q = quarter_h2_ * k;
  const Cov inv_d = Cov(1) / (Cov(1) + q);
  const Cov f11 = (Cov(1) - q) * inv_d, f12 = h_ * inv_d;
  for (int c = 0; c < kStates; ++c) fx[c] = fv[c] = Cov(0);
  fx[X] = f11;
  fx[V] = f12;
  fv[X] = -(half_h_ * k) * (Cov(1) + f11);
  fv[V] = Cov(1) - half_h_ * k * f12;
  const Cov fc = f0_[i];
  const Cov dx_c = (quarter_h2_ * (fc + fc)) * inv_d;
  fx[C] = dx_c;
  fv[C] = half_h_ * (fc + fc - k * dx_c);
  const Cov sum = cov(x0 + x1);
  const Cov dx_k = -(quarter_h2_ * k0_[i] * sum) * inv_d;
  fx[K] = dx_k;
  fv[K] = half_h_ * (-(k0_[i] * sum) - k * dx_k);
}

}  // namespace rockwatch::core
