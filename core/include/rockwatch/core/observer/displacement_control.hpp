// The displacement transducer's control (core/wall_observer.hpp): when a reading is fused (not when it is stuck),
// what an accepted one records, what rejections mean (a fault on a quiet ground, motion the model does not have,
// a re-initialisation while the ground shakes), the sensor's loss and activity, and model doubt from its NIS.
// H, the innovation and the gate are displacement_fusion.hpp's.
// Part of WallObserver (observer/wall_observer_class.hpp); core/wall_observer.hpp includes every part.
#pragma once

#include "rockwatch/core/observer/wall_observer_class.hpp"

namespace rockwatch::core {

template <typename Stepper>
inline void WallObserver<Stepper>::control_x(Stepper& stepper, const WallSensorSample& s, std::int64_t age_us,
                                             Input ug, Input vg, bool quiet, ObserverStepReport& out) {
  // Stuck: the same reading again and again while the wall rocks.
  if (have_last_raw_ && s.x_mid_m == last_raw_x_) {
    identical_run_ += x_count_;
  } else {
    identical_run_ = 0;
  }
  have_last_raw_ = true;
  last_raw_x_ = s.x_mid_m;
  if (identical_run_ + 1 >= stuck_after_ && stepper.moving()) {
    ++counters_.stuck;
    out.flags |= observer_flag::stuck;
    return;
  }
  const Scalar z = Scalar(s.x_mid_m);
  const bool fused = fuse_x(stepper, z, age_us, ug, vg);
  learn_x_noise(stepper, z);
  if (fused) {
    const Scalar y = last_innovation_x_;
    ++counters_.x_updates;
    ++out.x_updates;
    out.corrected = out.corrected || stepper.moving();
    innovation_x_sq_sum_ = innovation_x_sq_sum_ + y * y;
    consecutive_rejections_ = 0;
    last_x_used_us_ = last_x_accepted_us_ = s.utime_us;
    have_x_used_ = have_x_accepted_ = true;
    lost_ = false;
    return;
  }
  ++counters_.rejected;
  out.flags |= observer_flag::rejected;
  const bool first_rejection = consecutive_rejections_ == 0;
  consecutive_rejections_ += x_count_;
  // The sensor is sending, just disagreeing: not lost (rejections are flagged on their own).
  last_x_used_us_ = s.utime_us;
  have_x_used_ = true;
  lost_ = false;
  if (quiet) {
    // The ground is quiet: a rigid wall does not start rocking by itself, so a reading that disagrees is a sensor
    // fault, not a re-initialisation — unless it keeps disagreeing and moves (a fault reads a constant or jumps
    // once): then the wall moves where the model says it cannot (a lower threshold, crushed hinges, an elastic
    // phase), the most informative reading there is (issue 40). The run's readings' spread decides. The same when
    // the model rocks and the wall rocks otherwise (the free rocking after the record: a model that chatters at its
    // hinge while the transducer reads 5 cm cycles once rejected every reading as a jump until the record ended).
    if (first_rejection) {
      quiet_lo_ = quiet_hi_ = z;
    } else {
      if (z < quiet_lo_) quiet_lo_ = z;
      if (z > quiet_hi_) quiet_hi_ = z;
    }
    if (quiet_spread_x_ > Scalar(0) && consecutive_rejections_ >= reinit_after_ &&
        quiet_hi_ - quiet_lo_ >= quiet_spread_x_) {
      ++counters_.quiet_motion;
      if (doubt_nis_ > Cov(0)) doubt_ = true;
      reinitialise(stepper, z, ug, vg, out);
      return;
    }
    if (!stepper.moving()) {
      ++counters_.motion_while_quiet;
      out.flags |= observer_flag::motion_while_quiet;
    } else {
      ++counters_.jumps;
      out.flags |= observer_flag::jump;
    }
    return;
  }
  if (consecutive_rejections_ >= reinit_after_) reinitialise(stepper, z, ug, vg, out);
}

// The displacement's innovation y and its variance s: the running NIS average, and model doubt while it is above
// doubt_nis (ObserverOptions).
template <typename Stepper>
inline void WallObserver<Stepper>::note_innovation(Cov y, Cov s) {
  if (!(doubt_nis_ > Cov(0)) || !(s > Cov(0))) return;
  Cov nis = y * y / s;
  if (nis > gate_) nis = gate_;
  // A slower sensor's reading weighs as the samples it stands for (reading_count), so that the window is a time.
  Cov alpha = doubt_alpha_;
  if (x_count_ > 1) {
    alpha = alpha * Cov(x_count_);
    if (alpha > Cov(1)) alpha = Cov(1);
  }
  nis_avg_ = nis_avg_ + (nis - nis_avg_) * alpha;
  doubt_ = nis_avg_ > doubt_nis_;
}

// The transducer's noise measured before the shaking (ObserverOptions::noise_learn_readings, SPEC §11 "The
// transducer's noise"): the readings of a wall the model has at rest on a quiet ground, by their second differences
// d = z_k − 2 z_{k−1} + z_{k−2}, whose mean square is 6 R for white noise while a slow motion (a crushed hinge's
// elastic sway at a few hertz, the offset's drift) adds only (ω Δt)² of its amplitude: noise, not motion, is what
// is measured. Once there are enough, an estimate Σd²/(6n) that is at least (1.5 x_noise)² and above x_noise² by more
// than 4 of its mean's standard deviations (≈ 1.97 x_noise²/√n for the overlapping d of white noise: n·(R̂ − R₀)² >
// 62·R₀², no root per reading) becomes R: a noise under 1.5 times the told one is harmless (the gate is at 4 σ), and
// the test is repeated at every reading. It only ever rises within a run.
template <typename Stepper>
inline void WallObserver<Stepper>::learn_x_noise(const Stepper& stepper, Scalar z) {
  // The open window implies a quiet ground: begin_step closes it at half the quiet level.
  if (!noise_window_ || stepper.moving()) return;
  if (noise_seen_ >= 2) {
    const Cov d = cov(z - noise_z1_ - noise_z1_ + noise_z2_);
    noise_sum_ = noise_sum_ + d * d;
  }
  ++noise_seen_;
  noise_z2_ = noise_z1_;
  noise_z1_ = z;
  // A wall that stands quiet for days (a monitor started long before the earthquake): the window closes once it holds
  // 1024 N readings (at most 2^20), where the estimate's σ is 1/32 of its σ at N; the count stays far from int32's
  // end and the fixed-point observer's single-precision Σd² from the 2^24 terms where additions stop counting.
  if (x_noise_readings() >= noise_window_max_) noise_window_ = false;
  if (x_noise_readings() < noise_learn_min_) return;
  const Cov n = Cov(x_noise_readings());
  const Cov r_hat = noise_sum_ / (Cov(6) * n);
  const Cov excess = r_hat - r_x0_;
  if (r_hat > r_x_ && excess > Cov(1.25) * r_x0_ && n * excess * excess > Cov(62) * r_x0_ * r_x0_) set_x_noise_var(r_hat);
}

// R of the displacement and every threshold counted in transducer σ.
template <typename Stepper>
inline void WallObserver<Stepper>::set_x_noise_var(Cov r) {
  r_x_ = r;
  inform_peak_x2_ = inform_peak_var_ * r;
  accel_inform_peak_x2_ = accel_inform_peak_var_ * r;
  quiet_spread_x_ = from_cov(quiet_spread_noises_ * root_c(r));
}

// After the step's updates, while in doubt: σ(κc), σ(κk) and σ(√r) at least their floors. The pending prediction
// (flush) leaves these diagonal entries as they are but for their walks; a larger diagonal keeps P positive
// semi-definite.
template <typename Stepper>
inline void WallObserver<Stepper>::hold_doubt_floors() {
  if (p_(C, C) < doubt_c_var_) p_(C, C) = doubt_c_var_;
  if (p_(K, K) < doubt_c_var_) p_(K, K) = doubt_c_var_;
  if (p_(E, E) < doubt_e_var_) p_(E, E) = doubt_e_var_;
}

// Whether a reading taken with the model at x may teach κc, κk (ObserverOptions::capacity_min_x_fraction,
// doubt_capacity_min_x_fraction): the restoring force's decline, not the elastic rise and plateau of a crushed hinge
// near x = 0. The doubt's fraction applies once model doubt has been raised in the run (as the published σ's model
// form does): a wall that has shown it is not the model stays so, and the learning between two doubt episodes is
// what taught the plateau (SPEC §11). capacity_min_x_fraction 0 (the default): always before the first doubt.
template <typename Stepper>
inline bool WallObserver<Stepper>::capacity_learns(Scalar x) const {
  const bool doubted = doubt_ || counters_.model_doubt > 0;
  const Scalar lowest = doubted && doubt_capacity_min_x_ > capacity_min_x_ ? doubt_capacity_min_x_ : capacity_min_x_;
  return !(abs(x) < lowest);
}

// The measurement has disagreed with the model for reinit_after samples while the ground shakes: the real wall
// moves where the model does not (or the sensor is back after a dropout). Restart the motion at the reading, keeping
// the model's ẋ, with a wide velocity prior; what was learned (ê, b̂) stays. Why the model's ẋ and not 0 (SPEC §11,
// "The re-initialisation keeps the model's velocity"): in a pulse the model drifts in x, yet the wall and the model
// are driven by the same ground, so the model's ẋ is nearer the wall's than rest is (a multibody collapse rocking at
// 1.3 m/s was restarted from ẋ = 0); at rest, the quiet path's only case, it is 0 anyway.
template <typename Stepper>
inline void WallObserver<Stepper>::reinitialise(Stepper& stepper, Scalar z, Input ug, Input vg,
                                                ObserverStepReport& out) {
  const Scalar x = z - b_;
  Traits::set_motion(stepper, x, Traits::xd(stepper), ug, vg);
  Traits::set_sqrt_r(stepper, e_);
  zero_motion_covariance();
  p_(X, X) = r_x_;
  p_(V, V) = reinit_v_var_;
  consecutive_rejections_ = 0;
  ++counters_.reinitialised;
  out.flags |= observer_flag::reinitialised;
  out.corrected = true;
}

// At the step's end: the displacement sensor active (a sample accepted within the dropout time) and lost (no usable
// sample for dropout_s). Loss counts from the last usable displacement sample, or from the first step when there was
// none. A sensor that keeps sending but is always gated out is not lost (it is flagged rejected), but not active.
template <typename Stepper>
inline void WallObserver<Stepper>::x_health(std::int64_t t_us, ObserverStepReport& out) {
  const std::int64_t since_us = time_difference_us(t_us, have_x_used_ ? last_x_used_us_ : first_t_us_);
  if (have_x_accepted_ && time_difference_us(t_us, last_x_accepted_us_) <= dropout_us_) {
    out.flags |= observer_flag::x_active;
  }
  if (since_us > dropout_us_) {
    if (!lost_) ++counters_.dropouts;
    lost_ = true;
  }
  if (lost_) out.flags |= observer_flag::sensor_lost;
}

}  // namespace rockwatch::core
