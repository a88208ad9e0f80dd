// The wall observer's class (core/wall_observer.hpp, which describes the filter): its interface — init, the sensor
// samples in (push), a step (substep: prediction, at most one sensor sample; end_sample), the published estimates —
// and its members. The work is in the parts that define its private members (core/wall_observer.hpp includes them
// all): prediction.hpp (the covariance through a step), fusion_update.hpp (the scalar update every sensor shares),
// and per sensor a fusion file (H, innovation, gate) and a control file (when to fuse, health rules, resets):
// displacement_*.hpp, acceleration_*.hpp.
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include <Eigen/Core>

#include "rockwatch/core/fixed_point64.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/observer/observer_options.hpp"
#include "rockwatch/core/observer/observer_types.hpp"
#include "rockwatch/core/observer/stepper_traits.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/work_meter.hpp"

namespace rockwatch::core {

template <typename Stepper>
class WallObserver {
 public:
  using Traits = ObserverStepperTraits<Stepper>;
  using Scalar = typename Traits::Scalar;
  using Input = typename Traits::Input;
  using Report = typename Traits::Report;
  using Cov = typename Traits::Cov;
  using StepOutcome = ObserverStepReport;
  static constexpr int kStates = 6;
  using Mat = Eigen::Matrix<Cov, kStates, kStates>;
  using Vec = Eigen::Matrix<Scalar, kStates, 1>;
  // Sensor samples waiting for the ground stream: as many as the engine's queue of input samples holds
  // (StepperAlarmChain::kMaxPendingSamples), so that samples finished at later calls (carry-over) find theirs.
  static constexpr int kQueueCapacity = 64;
  // What each piece costs when metered (StepperAlarmChain; work units = Cortex-M4 instructions for the fixed-point
  // observer, upper bounds measured on the emulated M4: docs/FIXED_POINT.md "Bounded work per call").
  static constexpr ObserverWorkCosts kWork = Traits::kWork;
  enum : int { X = 0, V = 1, E = 2, B = 3, C = 4, K = 5 };

  // Initialisation time (double): the stepper's setup (its dt is the step) and the wall. Starts at rest with
  // ê = √r of the setup and b̂ = 0.
  ObserverError init(const ObserverOptions& o, const StepperSetup<double>& setup, const WallParameters& wall) {
    const ObserverError err = validate_observer_options(o);
    if (err != ObserverError::ok) return err;
    if (!(setup.dt_s > 0.0 && setup.dt_s <= 0.1)) return ObserverError::timing_out_of_range;
    const double h = setup.dt_s;
    const ModelConstants<double>& c = setup.model;
    for (int i = 0; i < 2; ++i) {
      const double s = i == 1 ? 1.0 : -1.0;
      const double k = (c.c4_fp[i] + c.c4_g * setup.g_mps2) / c.c1;  // p4/p1 at ü = 0, G = g [1/s²]
      k0_[i] = Cov(k);
      f0_[i] = Cov(-s * (c.c6_fp[i] + c.c6_g * setup.g_mps2) / c.c1);  // ẍ at the hinge, ü = 0 [m/s²]
      x_inst0_[i] = Cov(setup.x_inst_m[i]);
    }
    h_ = Cov(h);
    half_h_ = Cov(h / 2.0);
    quarter_h2_ = Cov(h * h / 4.0);
    const double sa2 = o.process_accel_mps2 * o.process_accel_mps2;
    q_ = Mat::Zero();
    q_(X, X) = Cov(sa2 * h * h * h * h / 4.0);
    q_(X, V) = q_(V, X) = Cov(sa2 * h * h * h / 2.0);
    q_(V, V) = Cov(sa2 * h * h);
    q_(E, E) = Cov(o.r_walk * o.r_walk);
    q_(B, B) = Cov(o.bias_walk_m * o.bias_walk_m);
    q_(C, C) = q_(K, K) = Cov(o.capacity_walk * o.capacity_walk);
    capacity_sigma0_ = Cov(o.capacity_sigma0);
    capacity_correlation_ = Cov(o.capacity_correlation);
    alarm_capacity_sigmas_ = Cov(o.alarm_capacity_sigmas);
    r_x_ = Cov(o.x_noise_m * o.x_noise_m);
    r_a_ = Cov(o.a_noise_mps2 * o.a_noise_mps2);
    gate_ = Cov(o.gate_chi2);
    g_over_h1_ = Scalar(setup.g_mps2 / wall.h1_m);
    inv_h1_ = Scalar(1.0 / wall.h1_m);
    v_min_ = Scalar(o.v_min_mps);
    inform_var_ = Cov(o.inform_sigmas * o.inform_sigmas);
    inform_peak_var_ = Cov(o.inform_peak_noises * o.inform_peak_noises);
    inform_peak_x2_ = inform_peak_var_ * r_x_;
    accel_inform_peak_var_ = Cov(o.accel_inform_peak_noises * o.accel_inform_peak_noises);
    accel_inform_peak_x2_ = accel_inform_peak_var_ * r_x_;
    r_x0_ = r_x_;
    noise_learn_min_ = o.noise_learn_readings;
    noise_window_max_ = noise_learn_min_ < 1024 ? 1024 * noise_learn_min_ : std::int32_t(1) << 20;
    quiet_spread_noises_ = Cov(o.quiet_motion_spread_noises);
    x_range_ = o.x_range_m;
    a_range_ = o.a_range_mps2;
    us_to_s_ = Scalar(1e-6);
    reinit_v_var_ = Cov(0.05 * 0.05);
    const double threshold = std::fmin(threshold_mps2(c, Side::negative, setup.g_mps2),
                                       threshold_mps2(c, Side::positive, setup.g_mps2));
    quiet_ug_ = Scalar(o.quiet_fraction * threshold);
    noise_quiet_ug_ = Scalar(0.5 * o.quiet_fraction * threshold);
    dropout_us_ = std::int64_t(o.dropout_s * 1e6 + 0.5);
    max_age_us_ = std::int64_t(o.max_age_s * 1e6 + 0.5);
    count_interval_us_ = std::int64_t(o.count_interval_s * 1e6 + 0.5);
    reinit_after_ = o.reinit_after;
    doubt_nis_ = Cov(o.doubt_nis);
    doubt_alpha_ = Cov(1.0 / o.doubt_window);
    doubt_c_var_ = Cov(o.doubt_capacity_sigma * o.doubt_capacity_sigma);
    {
      const double x_inst_min = std::fmin(setup.x_inst_m[0], setup.x_inst_m[1]);
      capacity_min_x_ = Scalar(o.capacity_min_x_fraction * x_inst_min);
      doubt_capacity_min_x_ = Scalar(o.doubt_capacity_min_x_fraction * x_inst_min);
    }
    doubt_e_var_ = Cov(o.doubt_r_sigma * o.doubt_r_sigma);
    model_form_var_ = Cov(o.model_form_sigma * o.model_form_sigma);
    doubt_model_form_var_ = Cov(o.doubt_model_form_sigma * o.doubt_model_form_sigma);
    quiet_spread_x_ = Scalar(o.quiet_motion_spread_noises * o.x_noise_m);
    reopen_after_ = o.capacity_reopen_after;
    rest_after_ = o.rest_from_accel_after;
    stuck_after_ = o.stuck_after;
    e0_ = Scalar(setup.sqrt_r);
    e_sigma0_ = Cov(o.r_sigma0);
    b_sigma0_ = Cov(o.bias_sigma0_m);
    start();
    return ObserverError::ok;
  }

  // A new run: ê = √r of the setup, b̂ = 0, priors, queue empty, counters zero.
  void start() {
    e_ = e0_;
    b_ = Scalar(0);
    p_ = Mat::Zero();
    p_(E, E) = e_sigma0_ * e_sigma0_;
    p_(B, B) = b_sigma0_ * b_sigma0_;
    kc_ = kk_ = Scalar(1);
    refresh_parameters();
    set_capacity_prior(capacity_sigma0_ * capacity_sigma0_);
    x_prev_ = Scalar(0);
    reset_transition();
    head_ = count_ = 0;
    counters_ = ObserverCounters{};
    last_x_used_us_ = last_x_accepted_us_ = last_a_used_us_ = 0;
    have_x_used_ = have_x_accepted_ = have_a_used_ = have_first_t_ = false;
    first_t_us_ = 0;
    pending_flags_ = 0;
    lost_ = false;
    consecutive_rejections_ = 0;
    consecutive_a_rejections_ = 0;
    rest_votes_ = 0;
    identical_run_ = 0;
    have_x_reading_ = have_a_reading_ = false;
    last_x_interval_us_ = last_a_interval_us_ = 0;
    x_count_ = a_count_ = 1;
    have_last_raw_ = false;
    last_raw_x_ = 0.0;
    impact_last_step_ = false;
    last_impact_us_ = INT64_MIN;
    peak_x_ = Scalar(0);
    run_peak_x_ = Scalar(0);
    last_innovation_x_ = Scalar(0);
    last_innovation_a_ = Scalar(0);
    var_x_ = var_a_ = Cov(0);
    rejected_x_ = rejected_a_ = false;
    same_side_a_ = false;
    innovation_x_sq_sum_ = Scalar(0);
    nis_avg_ = Cov(1);
    doubt_ = false;
    quiet_lo_ = quiet_hi_ = Scalar(0);
    noise_window_ = noise_learn_min_ > 0;
    noise_sum_ = Cov(0);
    noise_seen_ = 0;
    noise_z1_ = noise_z2_ = Scalar(0);
    if (r_x_ != r_x0_) set_x_noise_var(r_x0_);
  }

  // The wall's motion restarted from rest (long gap, publisher restart): what was learned (ê, b̂) stays.
  void restart_motion() {
    flush();
    zero_motion_covariance();
    consecutive_rejections_ = 0;
  }

  // A sensor sample arrives. Checked, then queued until the ground stream reaches its time. Returns the flags it
  // raised (not_finite, out_of_range, queue_overflow, sensor_flag).
  std::uint32_t push(WallSensorSample s) {
    ++counters_.samples;
    std::uint32_t flags = 0;
    if (s.sensor_status != 0) {
      ++counters_.sensor_flags;
      flags |= observer_flag::sensor_flag;
    }
    if (s.x_valid && !(s.x_mid_m == s.x_mid_m && s.x_mid_m - s.x_mid_m == 0.0)) {
      s.x_valid = false;
      ++counters_.not_finite;
      flags |= observer_flag::not_finite;
    } else if (s.x_valid && !(std::fabs(s.x_mid_m) <= x_range_)) {
      s.x_valid = false;
      ++counters_.out_of_range;
      flags |= observer_flag::out_of_range;
    }
    if (s.a_valid && !(s.a_mid_mps2 == s.a_mid_mps2 && s.a_mid_mps2 - s.a_mid_mps2 == 0.0)) {
      s.a_valid = false;
      ++counters_.not_finite;
      flags |= observer_flag::not_finite;
    } else if (s.a_valid && !(std::fabs(s.a_mid_mps2) <= a_range_)) {
      s.a_valid = false;
      ++counters_.out_of_range;
      flags |= observer_flag::out_of_range;
    }
    if (count_ == kQueueCapacity) {  // no ground samples to apply them to: the oldest goes
      head_ = (head_ + 1) % kQueueCapacity;
      --count_;
      ++counters_.queue_overflow;
      flags |= observer_flag::queue_overflow;
    }
    queue_[(head_ + count_) % kQueueCapacity] = s;
    ++count_;
    pending_flags_ |= flags;
    return flags;
  }

  // After the stepper's step that ends at `t_us` with input (ug, vg) at its end (report: what the stepper did): the
  // observer's sub-step (substep(): the covariance's prediction through the step, then at most one sensor sample),
  // then the end of the sample (the covariance brought up to date). Corrects the stepper's state and √r. For tests
  // and tools that step the observer by hand; StepperAlarmChain runs substep() after every sub-step and end_sample()
  // once per input sample.
  ObserverStepReport after_step(Stepper& stepper, const Report& report, Input ug, Input vg, std::int64_t t_us,
                                std::int64_t step_us) {
    const ObserverStepReport out = substep(stepper, report, ug, vg, t_us, step_us);
    end_sample();
    return out;
  }

  // The most one substep() costs [work units]: its prediction, one sensor sample applied, and every other queued
  // sample passed over. StepperAlarmChain reserves it before a sub-step and gives back what substep() did not use.
  static constexpr std::int32_t kSubstepWorstUnits =
      kWork.substep + kWork.update + (kQueueCapacity - 1) * kWork.superseded;

  // The observer's share of one sub-step, all of it (bounded work; the chain never stops inside it): the prediction
  // through the step, composed into the sample's transition; then at most ONE sensor sample — the newest whose time
  // the step's end has reached — applied (or dropped: stale, the wall collapsed, or `shed`: the engine's queue is
  // full), the older due ones passed over (counted `superseded`); then the step's bookkeeping and its report.
  // Why one: so that a sub-step's work has a small fixed bound (kSubstepWorstUnits) whatever arrived, and a budgeted
  // call can pay a sub-step whole. Why the newest, as PX4's EKF2 pops its ring buffers: a sensor sampled faster than
  // the sub-steps, or a backlog (sensor samples older than the first ground sample), is never worked through with a
  // growing lag; at most one sample a sub-step is what a sensor at or below the sub-step rate gives anyway (every
  // record and study: SPEC §9). Samples not yet due wait in the ring. `units`: what it cost (kWork), for the chain's
  // meter.
  ObserverStepReport substep(Stepper& stepper, const Report& report, Input ug, Input vg, std::int64_t t_us,
                             std::int64_t step_us, bool shed = false, std::int32_t* units = nullptr) {
    begin_step(stepper, report, ug, vg, t_us, step_us);
    const std::int32_t used = kWork.substep + fuse_newest_due(stepper, shed);
    if (units != nullptr) *units = used;
    return end_step(stepper);
  }
  void end_sample() { flush(); }


  // Estimates (double, for publishing), computed in the covariance's arithmetic Cov (double for the double observer,
  // as before; single precision on the M4F's FPU for the fixed-point one: 7 significant digits, what a published
  // estimate needs, without soft double's divisions and roots), then widened.
  double r_estimate() const {
    const Cov e = ec_;
    return pub(e * e);
  }
  double sqrt_r_estimate() const { return to_d(e_); }
  double bias_m() const { return to_d(b_); }
  // Model doubt (ObserverOptions::doubt_nis) and the displacement's running NIS average behind it.
  bool model_doubt() const { return doubt_; }
  double nis_average() const { return pub(nis_avg_); }  // Cov: double, or the M4F's single precision
  // The displacement transducer's σ the filter uses: x_noise, or the larger one measured before the shaking
  // (ObserverOptions::noise_learn_readings) [m]; and how many readings at rest measured it.
  double x_noise_m() const { return pub(root_c(r_x_)); }
  std::int32_t x_noise_readings() const { return noise_seen_ > 2 ? noise_seen_ - 2 : 0; }  // (second differences)
  double sigma_x_m() const { return root(p_(X, X)); }
  double sigma_xd_mps() const { return root(p_(V, V)); }
  // The published σ(r) (SPEC §11): the filter's, and once model doubt has been raised in the run doubt_r_sigma on √r
  // in quadrature (the floor doubt holds while it lasts, kept in what is published after it: a wall that has shown it
  // is not the model stays so, and its energy loss is not one r).
  double sigma_r() const {
    const Cov form = counters_.model_doubt > 0 ? doubt_e_var_ : Cov(0);
    return pub(Cov(2) * ec_ * root_c(p_(E, E) + form));
  }
  // The filter's own σ(r): what its consistency (NEES) is judged by.
  double sigma_r_filter() const { return pub(Cov(2) * ec_ * root_c(p_(E, E))); }
  double sigma_bias_m() const { return root(p_(B, B)); }
  // The capacity (SPEC §9), side +1 (the negative side's: x_inst_estimate_m(Side::negative)); c [m/s²] and k [1/s²]
  // at ü = v̈ = 0 per unit p1, ω = √k [rad/s], x_inst = c/k [m]; σ by first-order propagation of the covariance.
  double capacity_scale() const { return to_d(kc_); }
  double stiffness_scale() const { return to_d(kk_); }
  double sigma_capacity_scale() const { return root(p_(C, C)); }
  double sigma_stiffness_scale() const { return root(p_(K, K)); }
  double c_estimate_mps2(Side s = Side::positive) const { return pub(kcc_ * abs_cov(f0_[side_index(s)])); }
  double sigma_c_mps2(Side s = Side::positive) const { return pub(root_c(p_(C, C)) * abs_cov(f0_[side_index(s)])); }
  double k_estimate_ps2(Side s = Side::positive) const { return pub(k_c(s)); }
  double sigma_k_ps2(Side s = Side::positive) const { return pub(sigma_k_c(s)); }
  double omega_estimate_rps(Side s = Side::positive) const { return pub(std::sqrt(k_c(s))); }
  double sigma_omega_rps(Side s = Side::positive) const {
    const Cov w = std::sqrt(k_c(s));
    return w > Cov(0) ? pub(sigma_k_c(s) / (Cov(2) * w)) : 0.0;
  }
  double x_inst_estimate_m(Side s = Side::positive) const { return pub(x_inst_c(s)); }
  // The published σ(x_inst): the filter's (the variance of κc/κk by first-order propagation) and the model's form in
  // quadrature (SPEC §11). The form's share of x̂_inst: doubt_model_form_sigma once model doubt was raised; before,
  // the larger of model_form_sigma and doubt_model_form_sigma × (1 − u), u = the largest |x| of the run / x̂_inst
  // (at most 1): a capacity is the restoring force extrapolated beyond the largest displacement the wall has shown,
  // and a wall that has not been near it may yet be one whose curve is not the model's (a crushed hinge's
  // extrapolated plateau: 25-41 % high with no doubt raised, issue 40's held-out survivors).
  double sigma_x_inst_m(Side s = Side::positive) const {
    const Cov f = sigma_x_inst_c(s), x = x_inst_c(s);
    return pub(root_c(f * f + model_form_var_c(x) * x * x));
  }
  // The model's largest |x| since the run started [m]: how far beyond it x̂_inst is extrapolated (sigma_x_inst_m).
  double run_peak_x_m() const { return to_d(run_peak_x_); }
  // The filter's own σ(x_inst), without the model's form: what its consistency (NEES) is judged by.
  double sigma_x_inst_filter_m(Side s = Side::positive) const { return pub(sigma_x_inst_c(s)); }
  // The x_inst the alarm may rely on: x_inst,est − k_σ·σ(x_inst) (ObserverOptions::alarm_capacity_sigmas), at least
  // 0.3 × nominal.
  double x_inst_alarm_m(Side s = Side::positive) const { return pub(x_inst_alarm_c(s)); }
  // What the alarm's constants are scaled by (StepperAlarmChain::step_observed): x_inst_alarm / x_inst,nominal and κk.
  // False when the observer has nothing of its own (the nominal wall: margin 0 and κ = 1 would give 1, 1 anyway).
  bool alarm_scales(double& q, double& kk) const {
    q = pub(x_inst_alarm_c(Side::positive) / x_inst0_[1]);
    kk = to_d(kk_);
    return q > 0.0 && kk > 0.0;
  }
  // The energy barrier per unit p1, c²/(2k) [m²/s²].
  double barrier_estimate_m2ps2(Side s = Side::positive) const {
    const Cov c = kcc_ * abs_cov(f0_[side_index(s)]), k = k_c(s);
    return k > Cov(0) ? pub(c * c / (Cov(2) * k)) : 0.0;
  }
  // Each sensor's fusion status (ObserverSensorStatus): its last innovation, variance, test ratio and verdict, and
  // its last accepted reading's time. The test ratio in the covariance's arithmetic (single precision on the M4F).
  ObserverSensorStatus x_status() const {
    return sensor_status(last_innovation_x_, var_x_, rejected_x_, have_x_accepted_, last_x_accepted_us_);
  }
  ObserverSensorStatus a_status() const {
    return sensor_status(last_innovation_a_, var_a_, rejected_a_, have_a_used_, last_a_used_us_);
  }
  double last_innovation_x_m() const { return to_d(last_innovation_x_); }
  double last_innovation_a_mps2() const { return to_d(last_innovation_a_); }
  double rms_innovation_x_m() const {
    return counters_.x_updates > 0 ? std::sqrt(to_d(innovation_x_sq_sum_) / double(counters_.x_updates)) : 0.0;
  }
  bool sensor_lost() const { return lost_; }
  const ObserverCounters& counters() const { return counters_; }
  const Mat& covariance() const { return p_; }
  Scalar e() const { return e_; }
  Scalar b() const { return b_; }
  Scalar kc() const { return kc_; }
  Scalar kk() const { return kk_; }

 private:
  static double to_d(double v) { return v; }
  // The published σ from a variance: in double for the double observer; for the fixed-point one in single
  // precision (the M4F's VSQRT.F32: 7 significant digits, what a published σ needs, for ~100 instructions instead of
  // soft double's square root, ~1 000). Negative variances (rounding) publish 0.
  static double root(Cov v) {
    if constexpr (std::is_same_v<Cov, double>) {
      return std::sqrt(std::fmax(0.0, v));
    } else {
      if (!(v > Cov(0))) return 0.0;
      return static_cast<double>(std::sqrt(v));
    }
  }
  template <typename F>
  static double to_d(const F& v) {
    return v.to_double();
  }
  static Scalar abs(Scalar v) { return v < Scalar(0) ? -v : v; }
  static Cov abs_cov(Cov v) { return v < Cov(0) ? -v : v; }
  static double pub(Cov v) { return static_cast<double>(v); }
  // The parameters in the covariance's arithmetic, converted once when they change (start, apply).
  void refresh_parameters() {
    ec_ = cov(e_);
    kcc_ = cov(kc_);
    kkc_ = cov(kk_);
  }
  static Cov root_c(Cov v) {
    if constexpr (std::is_same_v<Cov, double>) {
      return std::sqrt(std::fmax(0.0, v));
    } else {
      return v > Cov(0) ? std::sqrt(v) : Cov(0);
    }
  }
  Cov k_c(Side s) const { return kkc_ * abs_cov(k0_[side_index(s)]); }
  Cov sigma_k_c(Side s) const { return root_c(p_(K, K)) * abs_cov(k0_[side_index(s)]); }
  Cov x_inst_c(Side s) const { return kcc_ / kkc_ * x_inst0_[side_index(s)]; }
  // The model form's variance per x̂_inst² (sigma_x_inst_m): the doubt's, or the larger of the form's and the doubt's
  // scaled by how far x_inst lies beyond the run's largest |x|.
  Cov model_form_var_c(Cov x_inst) const {
    if (counters_.model_doubt > 0) return doubt_model_form_var_;
    const Cov peak = cov(run_peak_x_);
    const Cov beyond = x_inst > peak ? (x_inst - peak) / x_inst : Cov(0);
    const Cov extrapolated = doubt_model_form_var_ * beyond * beyond;
    return extrapolated > model_form_var_ ? extrapolated : model_form_var_;
  }
  Cov sigma_x_inst_c(Side s) const {
    const Cov ratio = kcc_ / kkc_;
    const Cov var = p_(C, C) - Cov(2) * ratio * p_(C, K) + ratio * ratio * p_(K, K);
    return x_inst0_[side_index(s)] / kkc_ * root_c(var);
  }
  ObserverSensorStatus sensor_status(Scalar y, Cov s, bool rejected, bool fused, std::int64_t fused_us) const {
    ObserverSensorStatus st;
    const Cov yc = cov(y);
    st.innovation = to_d(y);
    st.innovation_variance = pub(s);
    st.test_ratio = s > Cov(0) ? pub(yc * yc / (gate_ * s)) : 0.0;
    st.rejected = rejected;
    st.fused = fused;
    st.last_fused_us = fused ? fused_us : 0;
    return st;
  }
  Cov x_inst_alarm_c(Side s) const {
    const Cov lowest = Cov(0.3) * x_inst0_[side_index(s)];
    const Cov v = x_inst_c(s) - alarm_capacity_sigmas_ * sigma_x_inst_c(s);
    return v > lowest ? v : lowest;
  }
 public:
  // The state's fixed point to the covariance's single precision and back (the M4's libgcc converts int64 ↔ float
  // through soft double, ~100 instructions each). To: the high and low words of the raw value's magnitude converted
  // by the FPU (VCVT.F32.U32: correctly rounded on host and M4 alike), hi·2³² + lo, times 2^−53 (exact), the sign:
  // within one unit in the last place (2 roundings; correctly rounded below 2^32 units, |v| < 4.8e-7). Back: v·2^53
  // (exact) truncated towards zero, in integer code, saturating at ±1024 (Q10.53's range), NaN 0. Identities for
  // the double observer.
  static Cov cov(Scalar v) {
    if constexpr (std::is_same_v<Scalar, Cov>) {
      return v;
    } else {
      static_assert(Scalar::kFracBits == 53, "the observer's scalar is Q10.53");
      const std::int64_t raw = v.raw();
      const auto u = static_cast<std::uint64_t>(raw);
      const std::uint64_t m = raw < 0 ? std::uint64_t(0) - u : u;
      const auto hi = static_cast<std::uint32_t>(m >> 32), lo = static_cast<std::uint32_t>(m & 0xFFFFFFFFu);
      const float magnitude = (static_cast<float>(hi) * 0x1p32f + static_cast<float>(lo)) * 0x1p-53f;
      return raw < 0 ? -magnitude : magnitude;
    }
  }
  static Scalar from_cov(Cov v) {
    if constexpr (std::is_same_v<Scalar, Cov>) {
      return v;
    } else {
      const auto bits = __builtin_bit_cast(std::uint32_t, v);
      const bool negative = (bits >> 31) != 0;
      const int biased = static_cast<int>((bits >> 23) & 0xFFu);
      if (biased == 0xFF && (bits & 0x7FFFFFu) != 0) return Scalar(0);  // NaN
      const std::uint64_t m = (bits & 0x7FFFFFu) | 0x800000u;
      const int sh = biased - 97;  // v·2^53 = m·2^(biased − 150 + 53)
      if (biased == 0 || sh <= -24) return Scalar(0);  // below 2^−53 (zero, subnormal): truncated to 0
      if (sh >= 40) return negative ? Scalar::lowest() : Scalar::highest();  // |v| ≥ 1024 (or ±Inf)
      const std::uint64_t magnitude = sh >= 0 ? m << sh : m >> -sh;
      const auto r = static_cast<std::int64_t>(magnitude);
      return Scalar::from_raw(negative ? -r : r);
    }
  }


 private:
  // The pieces of substep(). begin_step: the prediction through the step, composed into the sample's transition.
  void begin_step(Stepper& stepper, const Report& report, Input ug, Input vg, std::int64_t t_us, std::int64_t step_us) {
    step_out_ = ObserverStepReport{};
    step_out_.flags = pending_flags_;
    pending_flags_ = 0;
    step_impact_ = report.impacts_total > 0;
    if (step_impact_) last_impact_us_ = t_us;
    predict(stepper, report);
    step_ug_ = ug;
    step_vg_ = vg;
    step_t_us_ = t_us;
    step_us_ = step_us;
    step_quiet_ = abs(Traits::input(ug)) < quiet_ug_;
    // The shaking has begun (half the quiet level: a wall whose threshold is lower than told may rock on a ground the
    // model calls quiet, and its motion is not noise): the transducer's noise is measured.
    if (!(abs(Traits::input(ug)) < noise_quiet_ug_) || stepper.moving()) noise_window_ = false;
  }
  // The newest queued sample with utime <= the step's end, the older due ones passed over; returns its cost (0 when
  // none is due). The ring is in arrival order: a sample behind one not yet due waits, as before.
  std::int32_t fuse_newest_due(Stepper& stepper, bool shed) {
    ObserverStepReport& out = step_out_;
    if (count_ == 0 || queue_[head_].utime_us > step_t_us_) return 0;
    std::int32_t passed = 0;
    while (count_ > 1 && queue_[(head_ + 1) % kQueueCapacity].utime_us <= step_t_us_) {
      head_ = (head_ + 1) % kQueueCapacity;
      --count_;
      ++passed;
    }
    counters_.superseded += passed;
    const std::int32_t passed_units = passed * kWork.superseded;
    const WallSensorSample s = queue_[head_];
    head_ = (head_ + 1) % kQueueCapacity;
    --count_;
    if (shed) {  // the engine sheds: the sample is dropped, not applied (its check paid, as a stale one's)
      ++counters_.queue_overflow;
      out.flags |= observer_flag::queue_overflow;
      return passed_units + kWork.dropped;
    }
    const std::int64_t age_us = time_difference_us(step_t_us_, s.utime_us);
    if (age_us > max_age_us_) {
      ++counters_.stale;
      out.flags |= observer_flag::stale;
      return passed_units + kWork.dropped;
    }
    if (age_us > step_us_) {
      ++counters_.misaligned;
      out.flags |= observer_flag::misaligned;
    }
    if (stepper.collapsed()) return passed_units + kWork.dropped;  // nothing left to estimate
    // The updates need the covariance of now: the sample's transition so far applied.
    flush();
    // Each sensor's control decides whether and how its reading is fused (displacement first: the accelerometer's
    // rules ask whether the displacement agreed).
    if (s.x_valid) {
      x_count_ = reading_count(s.utime_us, last_x_reading_us_, last_x_interval_us_, have_x_reading_);
      control_x(stepper, s, age_us, step_ug_, step_vg_, step_quiet_, out);
    }
    if (s.a_valid) a_count_ = reading_count(s.utime_us, last_a_reading_us_, last_a_interval_us_, have_a_reading_);
    control_a(stepper, s, out);
    return passed_units + kWork.update;
  }
  // The step's bookkeeping and its report.
  ObserverStepReport end_step(const Stepper& stepper) {
    ObserverStepReport& out = step_out_;
    const std::int64_t t_us = step_t_us_;
    impact_last_step_ = step_impact_;
    if (!have_first_t_) {
      have_first_t_ = true;
      first_t_us_ = t_us;
    }
    x_health(t_us, out);
    if (a_used_recent(t_us)) out.flags |= observer_flag::a_active;
    if (doubt_) {
      out.flags |= observer_flag::model_doubt;
      ++counters_.model_doubt;
      hold_doubt_floors();
    }
    x_prev_ = Traits::x(stepper);
    return out;
  }

  // Prediction (observer/prediction.hpp).
  void zero_motion_covariance();
  void predict(const Stepper& stepper, const Report& report);
  void reset_transition();
  void zero_motion_transition();
  void compose(const Cov* fx, const Cov* fv);
  Cov current_vv() const;
  void flush();
  void transition(int i, Scalar x0, Scalar x1, Cov* fx, Cov* fv) const;
  // The update every sensor shares (observer/fusion_update.hpp).
  bool scalar_update(Cov (&ph)[kStates], Cov s, Cov y, Vec& correction, bool learn = true, bool learn_capacity = true);
  bool capacity_learns(Scalar x) const;
  bool informative(Scalar x) const { return informative(x, inform_peak_x2_); }
  bool informative(Scalar x, Cov peak_x2) const;
  void symmetrise();
  void apply(Stepper& stepper, const Vec& dz, Input ug, Input vg);
  static bool clamp_to(Scalar& v, Scalar lo, Scalar hi);
  void project_capacity_ratio(Scalar q);
  // The displacement transducer: fusion (observer/displacement_fusion.hpp) and control
  // (observer/displacement_control.hpp).
  bool fuse_x(Stepper& stepper, Scalar z, std::int64_t age_us, Input ug, Input vg);
  void control_x(Stepper& stepper, const WallSensorSample& s, std::int64_t age_us, Input ug, Input vg, bool quiet,
                 ObserverStepReport& out);
  void note_innovation(Cov y, Cov s);
  void learn_x_noise(const Stepper& stepper, Scalar z);
  void set_x_noise_var(Cov r);
  // How many samples a reading at t_us counts in the counts: floor(Δt / count_interval_us_), 1 to 8
  // (ObserverOptions::count_interval_s), Δt the shorter of this reading's interval and the one before it, so that
  // the sensor's rate decides and a single gap (a lost packet, a dropout) does not count as many readings; records
  // t_us and the interval. Constant work: at most seven comparisons, no division (the M4 has no 64-bit divide).
  std::int32_t reading_count(std::int64_t t_us, std::int64_t& last_us, std::int64_t& last_dt_us, bool& have_last) {
    std::int32_t n = 1;
    std::int64_t dt_us = 0;
    if (have_last) {
      dt_us = time_difference_us(t_us, last_us);
      const std::int64_t d_us = dt_us < last_dt_us ? dt_us : last_dt_us;  // last_dt_us 0 until two intervals
      if (count_interval_us_ > 0) {
        std::int64_t next_us = 2 * count_interval_us_;
        while (n < 8 && d_us >= next_us) {
          ++n;
          next_us += count_interval_us_;
        }
      }
    }
    last_us = t_us;
    last_dt_us = dt_us;
    have_last = true;
    return n;
  }
  void hold_doubt_floors();
  void reinitialise(Stepper& stepper, Scalar z, Input ug, Input vg, ObserverStepReport& out);
  void x_health(std::int64_t t_us, ObserverStepReport& out);
  // The accelerometer: fusion (observer/acceleration_fusion.hpp) and control (observer/acceleration_control.hpp).
  bool fuse_a(Stepper& stepper, const WallSensorSample& s, Scalar ug_s, Input vg, Input ug, bool learn_a);
  void control_a(Stepper& stepper, const WallSensorSample& s, ObserverStepReport& out);
  void reopen_capacity(Cov kappa_error);
  // κc and κk's prior block: variance `var` each, covariance capacity_correlation × var (ObserverOptions); the rest of
  // their rows and columns as they are (zero at a start or a re-opening).
  void set_capacity_prior(Cov var) {
    p_(C, C) = p_(K, K) = var;
    p_(C, K) = p_(K, C) = capacity_correlation_ * var;
  }
  void put_to_rest(Stepper& stepper, Input ug, Input vg);
  bool a_used_recent(std::int64_t t_us) const;

  // Constants (init).
  Cov k0_[2]{};        // the nominal k_s = p4/p1 at ü = 0, G = g per side [1/s²]
  Cov x_inst0_[2]{};   // the nominal x_inst per side [m]
  Cov h_{}, half_h_{}, quarter_h2_{};  // the step h, h/2, h²/4 [s, s, s²]
  Cov capacity_sigma0_{}, capacity_correlation_{};
  Cov alarm_capacity_sigmas_ = Cov(0.5);
  Mat q_{};            // process noise per step
  Cov f0_[2]{};        // ẍ at the hinge with ü = 0 per side [m/s²]
  Cov r_x_{}, r_a_{}, gate_{}, reinit_v_var_{};
  Scalar g_over_h1_{}, v_min_{}, us_to_s_{}, quiet_ug_{};
  Scalar noise_quiet_ug_{};  // the transducer's noise is measured while |ü| stays below this: half quiet_ug_ [m/s²]
  Scalar inv_h1_{};     // 1/h1 [1/m]
  Cov inform_var_{}, inform_peak_var_{};  // inform_sigmas², inform_peak_noises² [-]
  Cov inform_peak_x2_{};  // inform_peak_noises² × x_noise² [m²]
  Cov accel_inform_peak_var_{};  // accel_inform_peak_noises² [-]
  // The transducer's noise measured before the shaking (ObserverOptions::noise_learn_readings): the told x_noise²,
  // the window (open from the start until the ground leaves quiet or the model moves), Σd² of the readings' second
  // differences and the readings seen (their count is two fewer).
  Cov r_x0_{}, quiet_spread_noises_{};
  std::int32_t noise_learn_min_ = 0, noise_window_max_ = 0, noise_seen_ = 0;
  bool noise_window_ = false;
  Cov noise_sum_{};
  Scalar noise_z1_{}, noise_z2_{};  // the window's last two readings [m]
  Cov accel_inform_peak_x2_{};  // accel_inform_peak_noises² × x_noise² [m²]
  Scalar e0_{};
  Cov e_sigma0_{}, b_sigma0_{};
  double x_range_ = 0.5, a_range_ = 80.0;
  std::int64_t dropout_us_ = 250000, max_age_us_ = 50000;
  std::int64_t count_interval_us_ = 10000;  // ObserverOptions::count_interval_s [µs] (0: every reading one sample)
  std::int64_t last_x_reading_us_ = 0, last_a_reading_us_ = 0;  // the sensors' previous readings [µs]
  std::int64_t last_x_interval_us_ = 0, last_a_interval_us_ = 0;  // and the intervals before them [µs]
  bool have_x_reading_ = false, have_a_reading_ = false;
  std::int32_t x_count_ = 1, a_count_ = 1;  // the current reading's weight in the counts (reading_count)
  std::int32_t reinit_after_ = 8, stuck_after_ = 40, reopen_after_ = 16, rest_after_ = 8;
  Cov doubt_nis_{}, doubt_alpha_{}, doubt_c_var_{}, doubt_e_var_{};  // model doubt (ObserverOptions) [-]
  // |x| below which a reading does not teach κc, κk: always, and while in doubt (the larger applies) [m]
  Scalar capacity_min_x_{}, doubt_capacity_min_x_{};
  Cov model_form_var_{}, doubt_model_form_var_{};  // model_form_sigma², doubt_model_form_sigma² [-]
  Scalar quiet_spread_x_{};  // quiet_motion_spread_noises × x_noise [m]
  // State.
  Scalar e_{}, b_{};
  Scalar kc_{1}, kk_{1};  // κc, κk [-]
  Cov ec_{}, kcc_{1}, kkc_{1};  // e, κc, κk in Cov (refresh_parameters)
  Scalar x_prev_{};       // x at the end of the previous step (after its corrections) [m]
  Mat p_{};
  // The prediction pending since the last flush (predict, compose, flush): rows X and V of Φ, Φ = I, the noise of
  // x, ẋ (XX, XV, VV), whether it is zero, and the steps whose parameter walks are still to add.
  Cov phi_x_[kStates]{}, phi_v_[kStates]{};
  bool phi_identity_ = true;
  Cov qa_[3]{};
  bool qa_zero_ = true;
  int walk_steps_ = 0;
  // The step in progress (begin_step .. end_step): its report, input, end, length, and whether the ground is quiet
  // and the step held an impact.
  ObserverStepReport step_out_{};
  Input step_ug_{}, step_vg_{};
  std::int64_t step_t_us_ = 0, step_us_ = 0;
  bool step_quiet_ = false, step_impact_ = false;
  WallSensorSample queue_[kQueueCapacity]{};
  int head_ = 0, count_ = 0;
  std::uint32_t pending_flags_ = 0;
  ObserverCounters counters_{};
  bool have_first_t_ = false;
  std::int64_t first_t_us_ = 0;
  bool have_x_used_ = false, have_x_accepted_ = false, have_a_used_ = false, lost_ = false;
  std::int64_t last_x_used_us_ = 0, last_x_accepted_us_ = 0, last_a_used_us_ = 0;  // sample times [µs]
  std::int32_t consecutive_rejections_ = 0, identical_run_ = 0;
  Cov nis_avg_{1};         // the displacement's NIS, averaged over about doubt_window samples [-]
  bool doubt_ = false;     // model doubt (nis_avg_ > doubt_nis_, or motion read on a quiet ground)
  Scalar quiet_lo_{}, quiet_hi_{};  // the readings' range over the run of rejections while quiet [m]
  std::int32_t consecutive_a_rejections_ = 0;  // accelerations gated out in a row (informative motion, x agreeing)
  std::int32_t rest_votes_ = 0;  // accelerations in a row that read a wall at rest while the model rocked
  bool have_last_raw_ = false;
  double last_raw_x_ = 0.0;
  bool impact_last_step_ = false;
  std::int64_t last_impact_us_ = INT64_MIN;  // the end of the last step with an impact [µs]
  Scalar peak_x_{};  // the model's largest |x| since the last impact (the half-cycle's amplitude) [m]
  Scalar run_peak_x_{};  // the model's largest |x| since start() (how far the capacity is extrapolated) [m]
  Scalar last_innovation_x_{}, last_innovation_a_{}, innovation_x_sq_sum_{};
  // The last reading tried per sensor (ObserverSensorStatus): its innovation's variance and whether it was gated out.
  Cov var_x_{}, var_a_{};  // [m², m²/s⁴]
  bool rejected_x_ = false, rejected_a_ = false;
  // The last acceleration's a − ü has the sign the model's predicts (the same side); kept only while no displacement
  // is read (lost_), the only time it is asked.
  bool same_side_a_ = false;
};

}  // namespace rockwatch::core

