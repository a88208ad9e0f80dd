// The displacement transducer's fusion (core/wall_observer.hpp): x_mid = x + b + noise, H = [1 0 0 1 0 0], the
// innovation of a reading carried forward to the step end along ẋ̂, its variance, the χ² gate and the correction.
// When a reading is fused, and what a rejection means, is displacement_control.hpp's.
// Part of WallObserver (observer/wall_observer_class.hpp); core/wall_observer.hpp includes every part.
#pragma once

#include "rockwatch/core/observer/wall_observer_class.hpp"

namespace rockwatch::core {

// One displacement reading z taken age_us before the step end: true when it passed the gate and corrected the
// stepper. Its innovation and variance are kept (the sensor's status) and noted for model doubt whether it passed or
// not.
template <typename Stepper>
inline bool WallObserver<Stepper>::fuse_x(Stepper& stepper, Scalar z, std::int64_t age_us, Input ug, Input vg) {
  const Scalar x = Traits::x(stepper), xd = Traits::xd(stepper);
  const Scalar age_s = Scalar(age_us) * us_to_s_;
  // The reading was taken age_s before the step end: carried forward along the estimated velocity.
  const Scalar y = z + xd * age_s - (x + b_);
  // H = [1 0 0 1 0 0]: P h is the sum of P's columns X and B, without a product.
  Cov ph[kStates];
  for (int a = 0; a < kStates; ++a) ph[a] = p_(a, X) + p_(a, B);
  Vec dz = Vec::Zero();
  last_innovation_x_ = y;
  const Cov s_x = ph[X] + ph[B] + r_x_;
  note_innovation(cov(y), s_x);
  var_x_ = s_x;
  rejected_x_ = !scalar_update(ph, s_x, cov(y), dz, informative(x), capacity_learns(x));
  if (rejected_x_) return false;
  apply(stepper, dz, ug, vg);
  return true;
}

}  // namespace rockwatch::core
