// The wall observer's measurement update shared by every sensor (core/wall_observer.hpp): one scalar Kalman update
// with its χ² gate (scalar_update), whether the motion may inform the wall's parameters (informative), and the
// correction fed back into the stepper (apply: the state, √r, the capacity, an impact the correction implies).
// Each sensor's H and innovation are in its fusion file (displacement_fusion.hpp, acceleration_fusion.hpp).
// Part of WallObserver (observer/wall_observer_class.hpp); core/wall_observer.hpp includes every part.
#pragma once

#include "rockwatch/core/observer/wall_observer_class.hpp"

namespace rockwatch::core {

// One scalar measurement with P h = ph already formed (h sparse: the callers add P's columns), s = hᵀ P h + r,
// innovation y. Returns false when gated out. Only the upper triangle of P is computed (then mirrored).
// learn = false: the wall's parameters (e, κc, κk) are considered, not estimated (Schmidt–Kalman: their gain is
// zero and the covariance follows the Joseph form of that gain, so it stays the covariance of the errors);
// learn_capacity = false: κc, κk alone (capacity_learns()).
// 1/s for the gains k = P h / s: one division for the whole gain (six products instead of six divisions).
template <typename Stepper>
inline bool WallObserver<Stepper>::scalar_update(Cov (&ph)[kStates], Cov s, Cov y, Vec& correction, bool learn,
                                                 bool learn_capacity) {
  if (!(s > Cov(0))) return false;
  if (y * y > gate_ * s) return false;
  const Cov inv_s = Cov(1) / s;
  Cov k[kStates];
  for (int a = 0; a < kStates; ++a) k[a] = ph[a] * inv_s;
  if (learn && learn_capacity) {
    for (int a = 0; a < kStates; ++a) {
      correction(a) = from_cov(k[a] * y);
      for (int c = a; c < kStates; ++c) p_(a, c) = p_(a, c) - k[a] * ph[c];
    }
  } else {
    if (!learn) k[E] = Cov(0);
    k[C] = k[K] = Cov(0);
    // (I − k hᵀ) P (I − k hᵀ)ᵀ + r k kᵀ = P − k (Ph)ᵀ − (Ph) kᵀ + s k kᵀ, on the entries a gain touches.
    for (int a = 0; a < kStates; ++a) {
      correction(a) = from_cov(k[a] * y);
      for (int c = a; c < kStates; ++c) {
        if (k[a] == Cov(0) && k[c] == Cov(0)) continue;
        p_(a, c) = p_(a, c) - k[a] * ph[c] - ph[a] * k[c] + s * k[a] * k[c];
      }
    }
  }
  symmetrise();
  return true;
}

template <typename Stepper>
inline bool WallObserver<Stepper>::informative(Scalar x, Cov peak_x2) const {
  const Cov a = cov(abs(x) > peak_x_ ? abs(x) : peak_x_);
  return a * a >= peak_x2;
}

template <typename Stepper>
inline void WallObserver<Stepper>::symmetrise() {
  for (int a = 0; a < kStates; ++a) {
    for (int c = a + 1; c < kStates; ++c) p_(c, a) = p_(a, c);
  }
  for (int a = 0; a < kStates; ++a) {
    if (p_(a, a) < Cov(0)) p_(a, a) = Cov(0);
  }
}

template <typename Stepper>
inline void WallObserver<Stepper>::apply(Stepper& stepper, const Vec& dz, Input ug, Input vg) {
  const Scalar x = Traits::x(stepper) + dz(X), xd = Traits::xd(stepper) + dz(V);
  bool clamped = false;
  e_ = e_ + dz(E);
  if (e_ < Scalar(0)) {
    e_ = Scalar(0);
    clamped = true;
  }
  if (e_ > Scalar(1)) {
    e_ = Scalar(1);
    clamped = true;
  }
  b_ = b_ + dz(B);
  kc_ = kc_ + dz(C);
  kk_ = kk_ + dz(K);
  clamped = clamp_to(kc_, Scalar(0.25), Scalar(4)) || clamped;
  clamped = clamp_to(kk_, Scalar(0.25), Scalar(4)) || clamped;
  // x_inst = κc/κk·x_inst,nominal within [0.3, 2]× nominal (SPEC §11 "The capacity's bounds").
  if (kc_ < Scalar(0.3) * kk_) {
    project_capacity_ratio(Scalar(0.3));
    clamped = true;
  } else if (kc_ > Scalar(2) * kk_) {
    project_capacity_ratio(Scalar(2));
    clamped = true;
  }
  refresh_parameters();
  if (clamped) {
    ++counters_.clamped;
    pending_flags_ |= observer_flag::estimate_clamped;
  }
  Traits::set_sqrt_r(stepper, e_);
  // The stepper's capacity only when it moved (a considered-parameters update leaves κc, κk as they were): the
  // same constants, without recomputing them.
  if (clamped || dz(C) != Scalar(0) || dz(K) != Scalar(0)) Traits::set_capacity(stepper, kc_, kk_, ug, vg);
  if (stepper.moving()) {
    const Scalar x_before = Traits::x(stepper);
    Scalar xd_after = xd;
    // The correction carried the wall across the hinge in the direction it moves: the wall hit the hinge between
    // the model's state and the measured one, an impact the stepper did not see (it would otherwise be lost: the
    // motion is placed on the new side with the velocity it had before). Its map: ẋ⁺ = e·ẋ⁻, covariance through
    // the reset's Jacobian (δẋ⁺ = e δẋ⁻ + ẋ⁻ δe; the timing term is not needed, x is the measured one).
    const bool crossed = (x_before > Scalar(0) && x < Scalar(0) && xd < Scalar(0)) ||
                         (x_before < Scalar(0) && x > Scalar(0) && xd > Scalar(0));
    if (crossed) {
      xd_after = e_ * xd;
      // P is up to date here (an update flushed it): the reset's Jacobian composed and applied at once.
      Cov jx[kStates] = {}, jv[kStates] = {};
      const Cov e = ec_, xdc = cov(xd);
      jx[X] = Cov(1);
      jv[V] = e;
      const bool certain = xdc * xdc >= inform_var_ * p_(V, V) && abs(xd) >= v_min_ && informative(x_before);
      if (certain) jv[E] = xdc;
      compose(jx, jv);
      flush();
      if (!certain) {
        const Cov jump = (Cov(1) - e) * xdc;
        p_(V, V) = p_(V, V) + jump * jump;
      }
      peak_x_ = Scalar(0);
      ++counters_.impacts;
      ++counters_.impacts_in_corrections;
    }
    Traits::set_motion(stepper, x, xd_after, ug, vg);
  }
}

// κc, κk moved onto κc = q·κk along their covariance: the least move in P⁻¹'s metric (the constrained Kalman
// estimate), so the one the readings pin least moves most. Motion at a fraction of x_inst pins the threshold (κc) and
// hardly the decline (κk): moving κc alone, as the bound once did, turned "the restoring force declines less than
// modelled" into "the wall is half as strong" (a thick multibody wall: κk at its floor, κc pulled to 0.5 by the
// 2× bound, the model falling away from a transducer that read it well). When the projection leaves κk's range, or
// the covariance has no spread along the bound, κc moves (κc = q·κk), as before. P is kept. Not while the
// transducer is lost (an accelerometer alone, SPEC §11): there x is the model's, and which of κc, κk the readings pin
// is not known; measured, the projection there traded two held-out collapses for one kept one.
template <typename Stepper>
inline void WallObserver<Stepper>::project_capacity_ratio(Scalar q) {
  const Cov qc = cov(q);
  const Cov pc = p_(C, C) - qc * p_(C, K), pk = p_(C, K) - qc * p_(K, K);
  const Cov s = pc - qc * pk;  // dᵀ P d, d = (1, −q)
  if (!lost_ && s > Cov(1e-12)) {
    const Cov v = cov(kc_ - q * kk_);
    // κk's move; κc's, v·pc/s, puts it on the bound: κc = q·κk, set exactly below.
    const Scalar kk = kk_ - from_cov(v * pk / s), kc = q * kk;
    if (kk >= Scalar(0.25) && kk <= Scalar(4) && kc >= Scalar(0.25) && kc <= Scalar(4)) kk_ = kk;
  }
  kc_ = q * kk_;
}

template <typename Stepper>
inline bool WallObserver<Stepper>::clamp_to(Scalar& v, Scalar lo, Scalar hi) {
  if (v < lo) {
    v = lo;
    return true;
  }
  if (v > hi) {
    v = hi;
    return true;
  }
  return false;
}

}  // namespace rockwatch::core
