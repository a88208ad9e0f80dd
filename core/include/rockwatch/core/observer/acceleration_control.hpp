// The mid-height accelerometer's control (core/wall_observer.hpp): when a reading is fused (while rocking, never in
// or right after a step with an impact: the impact is a spike, SPEC §8), whether it may teach the capacity, what an
// accepted one records, and what rejections mean: the capacity re-opened (the wall's capacity lies outside what its
// covariance allows) or the model put to rest (the accelerometer reads a wall at rest). Its activity at the step's
// end. H, the innovation and the gate are acceleration_fusion.hpp's.
// Part of WallObserver (observer/wall_observer_class.hpp); core/wall_observer.hpp includes every part.
#pragma once

#include "rockwatch/core/observer/wall_observer_class.hpp"

namespace rockwatch::core {

template <typename Stepper>
inline void WallObserver<Stepper>::control_a(Stepper& stepper, const WallSensorSample& s, ObserverStepReport& out) {
  // An acceleration taken before the last impact (queued, applied after it) belongs to the other side: its ẍ
  // differs by about 2·c_s from the model's now. Only samples taken after the step that held the impact are used.
  const bool after_impact = s.utime_us > last_impact_us_;
  if (!(s.a_valid && !step_impact_ && !impact_last_step_ && after_impact && stepper.moving())) return;
  const Input ug = step_ug_, vg = step_vg_;
  const Scalar ug_s = Traits::input(step_ug_);
  const Scalar x = Traits::x(stepper);
  const bool learn = informative(x);  // the capacity's re-open rule: the displacement's gate
  const bool learn_a = accel_inform_peak_x2_ == inform_peak_x2_ ? learn : informative(x, accel_inform_peak_x2_);
  if (!fuse_a(stepper, s, ug_s, vg, ug, learn_a)) {
    ++counters_.rejected;
    out.flags |= observer_flag::rejected;
    const bool x_agrees = consecutive_rejections_ == 0;  // the last displacement update passed
    // The displacement agrees and the motion is large enough to inform the capacity, yet the accelerometer keeps
    // disagreeing: the capacity is further from the estimate than its covariance says. With the displacement sensor
    // lost (no reading, accepted or gated out, for dropout_s: x_health), only on a reading whose a − ü has the model's
    // sign (same_side_a_): with an
    // accelerometer alone the model's x is not pinned, and a disagreement of the other sign is the model's phase (the
    // side: a − ü changes sign with it, by about 2·c_s), not its capacity; re-opened on those, a survivor's κk fell
    // to its clamp (issue 40, SPEC §11 "An accelerometer alone"). A reading of a wall at rest is not a capacity's
    // disagreement at all (fuse_a clears same_side_a_ for it).
    if (reopen_after_ > 0 && x_agrees && learn && (!lost_ || same_side_a_) &&
        (consecutive_a_rejections_ += a_count_) >= reopen_after_) {
      reopen_capacity(cov(last_innovation_a_) / f0_[side_index(stepper.side())]);  // ∂a/∂κc = f_s
    }
    // The reading is what a wall at rest gives (a = ü, block 1 vertical): the model rocks where the real wall
    // does not. Every such reading in a row, with the displacement agreeing, is a vote; rest_after_ votes put the
    // model to rest, where its state is known (x = ẋ = 0), and the stepper's start logic takes it from there.
    const Cov y_rest = cov(Scalar(s.a_mid_mps2) - ug_s);
    if (rest_after_ > 0 && x_agrees && y_rest * y_rest <= gate_ * r_a_) {
      if ((rest_votes_ += a_count_) >= rest_after_) put_to_rest(stepper, ug, vg);
    } else {
      rest_votes_ = 0;
    }
    return;
  }
  consecutive_a_rejections_ = 0;
  rest_votes_ = 0;
  ++counters_.a_updates;
  ++out.a_updates;
  out.corrected = true;
  last_a_used_us_ = s.utime_us;
  have_a_used_ = true;
}

// Re-open the capacity: κc and κk forget their correlations and take a variance of at least (the disagreement in
// units of κc)², never less than the prior's, so that the next accelerations pass the gate and move them; x, ẋ, e
// and b keep what they know. `kappa_error`: the last innovation over ∂a/∂κc = −s·c_s [-].
template <typename Stepper>
inline void WallObserver<Stepper>::reopen_capacity(Cov kappa_error) {
  for (int j = 0; j < kStates; ++j) {
    p_(C, j) = p_(j, C) = Cov(0);
    p_(K, j) = p_(j, K) = Cov(0);
  }
  const Cov prior = capacity_sigma0_ * capacity_sigma0_, need = kappa_error * kappa_error;
  set_capacity_prior(need > prior ? need : prior);
  consecutive_a_rejections_ = 0;
  ++counters_.capacity_reopened;
}

// The accelerometer has read a wall at rest rest_after_ times in a row while the model rocked: the model rests.
// What was learned (ê, b̂, κc, κk) stays.
template <typename Stepper>
inline void WallObserver<Stepper>::put_to_rest(Stepper& stepper, Input ug, Input vg) {
  Traits::set_motion(stepper, Scalar(0), Scalar(0), ug, vg);
  zero_motion_covariance();
  rest_votes_ = 0;
  ++counters_.rest_from_accel;
}

template <typename Stepper>
inline bool WallObserver<Stepper>::a_used_recent(std::int64_t t_us) const {
  return have_a_used_ && time_difference_us(t_us, last_a_used_us_) <= dropout_us_;
}

}  // namespace rockwatch::core
