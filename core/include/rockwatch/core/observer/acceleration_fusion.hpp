// The mid-height accelerometer's fusion (core/wall_observer.hpp): a_mid = ü + ẍ − G·x/h1 on block 1 while rocking,
// ẍ = κc·f_s − κk·k_s·x on the current side, so H is non-zero in x, κc and κk:
//   ∂a/∂x = −(κk·k_s + G/h1),  ∂a/∂κc = f_s = −s·c_s,  ∂a/∂κk = −k_s·x;
// the innovation, its variance, the χ² gate and the correction. When a reading is fused, and what rejections mean,
// is acceleration_control.hpp's.
// Part of WallObserver (observer/wall_observer_class.hpp); core/wall_observer.hpp includes every part.
#pragma once

#include "rockwatch/core/observer/wall_observer_class.hpp"

namespace rockwatch::core {

// One acceleration reading at the step end (ground ug_s, input ug, vg): true when it passed the gate and corrected
// the stepper. learn_a: whether the wall's parameters may learn from it (informative()). Its innovation and variance
// are kept (the sensor's status) whether it passed or not.
template <typename Stepper>
inline bool WallObserver<Stepper>::fuse_a(Stepper& stepper, const WallSensorSample& s, Scalar ug_s, Input vg,
                                          Input ug, bool learn_a) {
  const int i = side_index(stepper.side());
  const Scalar x = Traits::x(stepper);
  const Scalar gravity_over_h1 = g_over_h1_ + Traits::input(vg) * inv_h1_;  // G/h1 = (g + v̈)/h1
  const Scalar predicted = ug_s + Traits::xdd(stepper) - gravity_over_h1 * x;
  const Scalar y = Scalar(s.a_mid_mps2) - predicted;
  // H non-zero in X, C, K only: P h from three columns.
  const Cov hx = -(kkc_ * k0_[i] + cov(gravity_over_h1)), hc = f0_[i], hk = -(k0_[i] * cov(x));
  Cov ph[kStates];
  for (int a = 0; a < kStates; ++a) ph[a] = p_(a, X) * hx + p_(a, C) * hc + p_(a, K) * hk;
  Vec dz = Vec::Zero();
  last_innovation_a_ = y;
  const Cov s_a = hx * ph[X] + hc * ph[C] + hk * ph[K] + r_a_;
  var_a_ = s_a;
  rejected_a_ = !scalar_update(ph, s_a, cov(y), dz, learn_a, capacity_learns(x));
  if (rejected_a_) return false;
  apply(stepper, dz, ug, vg);
  return true;
}

}  // namespace rockwatch::core
