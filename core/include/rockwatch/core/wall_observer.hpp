// The wall observer: fuses wall-mounted sensors (SPEC §8) with the rocking model so that the monitor follows the
// real wall, not a nominal one running open loop on the ground motion.
//
// A hybrid extended Kalman filter on z = (x, ẋ, e, b, κc, κk):
//   x, ẋ   the mid-height hinge displacement and velocity [m, m/s]; their mean IS the rocking stepper's state (the
//          stepper propagates it with its impacts, start and rest logic; the observer corrects it after each step);
//   e      √r, the velocity ratio at impact [-] (r̂ = ê², fed back into the stepper after every correction);
//   b      the zero offset of the displacement transducer [m];
//   κc, κk multiplicative corrections to the nominal wall's capacity c_s and stiffness k (SPEC §9: ẍ = −γü − s·c_s
//          + k·x on side s, divided by p1), prior 1 ± capacity_sigma0 each; the stepper propagates the mean with
//          κc·c_s and κk·k (set_capacity_scales after every correction), so x_inst = κc/κk·x_inst,nominal,
//          ω = √(κk·k), the energy barrier per unit p1 (κc c_s)²/(2 κk k). Estimates leaving the physical range
//          (κ outside [0.25, 4], κc/κk outside [0.3, 2], e outside [0, 1]) are clamped and flagged (estimate_clamped).
// Between impacts the covariance follows the linearised model of the current side (the stepper's own Newmark step
// with the estimated stiffness κk·k_s, k_s = p4/p1 at ü = 0, G = g) with white model-acceleration noise; the columns
// of κc and κk are the derivatives of that Newmark step: with f_c = ∂ẍ/∂κc = −s·c_s, D = 1 + h²κk k_s/4,
//   ∂x₁/∂κc = h² f_c/(2D),  ∂ẋ₁/∂κc = h/2·(2 f_c − κk k_s ∂x₁/∂κc),
//   ∂x₁/∂κk = −h² k_s (x₀ + x₁)/(4D),  ∂ẋ₁/∂κk = h/2·(−k_s (x₀ + x₁) − κk k_s ∂x₁/∂κk). At an impact it
// follows the impact map through its saltation matrix: the guard is x = 0 and the reset ẋ⁺ = e·ẋ⁻, so
//   δx⁺ = e δx⁻,  δẋ⁺ = (a⁺ − e a⁻)/ẋ⁻ · δx⁻ + e δẋ⁻ + ẋ⁻ δe
// (a∓ the accelerations on the two sides at the hinge). The ẋ⁻ δe term is what makes r identifiable: the motion
// after an impact measures e. At rest the state is known (x = ẋ = 0), so a displacement reading there measures
// only the bias: the zero-offset estimate comes from the rests.
// Measurements (SPEC §8): the displacement transducer x_mid = x + b + noise (H = [1 0 0 1]); the accelerometer at
// the hinge on block 1, a_mid = ü + ẍ − G·x/h1 with ẍ = f − k x on the current side (H = [−(k_s + g/h1) 0 0 0]),
// used only while rocking and not in a step with an impact (the impact is a spike, SPEC §8). Every innovation is
// gated by χ² (1 degree of freedom); consecutive rejections while the ground shakes re-initialise the motion from
// the measurement (the real wall rocks where the model does not, or the sensor came back after a dropout).
//
// Time alignment: sensor samples are queued (fixed ring) with their utime and applied after the ground step whose
// time reaches theirs — never before (a future sample is never used) — extrapolated to the step end by ẋ̂·age.
// Samples older than max_age are dropped (stale); older than one step are applied but flagged (misaligned).
//
// Scalar: the stepper's (ObserverStepperTraits): double for core::RockingStepper<double>, ObserverQ10_53 for the
// fixed-point stepper (the state e, b, κc, κk, the innovations); Cov, the covariance's, gains' and linearisations':
// double, and single precision for the fixed-point stepper (the M4F's FPU; -ffp-contract=off). Core rules:
// header-only, no heap, no exceptions, no I/O; init() is initialisation-time code (double), the rest is bounded work
// (at most kQueueCapacity updates per step, each a few 6 × 6 products).
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include <Eigen/Core>

#include "rockwatch/core/fixed_point64.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/work_meter.hpp"

namespace rockwatch::core {

// The fixed-point observer's state format (corrections, e, b, κc, κk, innovations): ±1024, resolution 1.1e-16. Its
// covariance is single precision (ObserverStepperTraits<FixedRockingStepper>::Cov); a correction k·y comes back into
// this format saturating at ±1024.
using ObserverQ10_53 = Fixed64<10, 53>;

// Settings, SI units. Defaults: a displacement transducer of 0.5 mm noise and an accelerometer of 0.05 m/s².
struct ObserverOptions {
  double x_noise_m = 0.5e-3;            // σ of the displacement transducer [m]
  double a_noise_mps2 = 0.05;           // σ of the mid-height accelerometer [m/s²]
  double process_accel_mps2 = 0.2;      // σ of the model's acceleration error per step [m/s²] (docs/BENCHMARKS.md: the choice)
  double r_sigma0 = 0.1;                // initial σ of √r [-]
  double r_walk = 1e-5;                 // random walk of √r per step [-]
  double bias_sigma0_m = 5e-3;          // initial σ of the transducer's zero offset [m]
  double bias_walk_m = 1e-7;            // random walk of the zero offset per step [m]
  double gate_chi2 = 16.0;              // innovation gate, χ² with one degree of freedom (16: 4σ) [-]
  std::int32_t reinit_after = 8;        // consecutive rejections (ground shaking) that re-initialise the motion
  // Consecutive accelerometer rejections, while the displacement agrees and the motion informs the capacity, that
  // re-open the capacity's covariance (0: never). An accelerometer sees c and k directly (ẍ jumps by 2c at the
  // hinge), so a wall whose capacity lies far outside the prior (an overburden: κ ≈ 1.65 at 2 kN/m, 1.97 at 3 kN/m
  // against 1 ± 0.15) has every acceleration gated out; only the few that happen to agree were used, and their
  // selection drove κc, κk the wrong way (to 0.4 on set 11 Y at 0.28 g). SPEC §8; docs/BENCHMARKS.md
  // "Observer evaluation": 16 against 8 (more false alarms on Fp 3 kN/m) and never.
  std::int32_t capacity_reopen_after = 16;
  // Consecutive accelerometer readings that say the wall is at rest (a − ü within the gate of the accelerometer's
  // noise) while the model rocks and its rocking prediction is gated out, the displacement agreeing, that put the
  // model to rest (0: never). A rocking wall's acceleration differs from the ground's by ẍ − G·x/h1, ≈ c_s (1.7 m/s²
  // for the paper wall, 30 σ), which a transducer cannot see when the motion is sub-millimetre: the model chattered
  // where the real wall stood still (or had stopped), and every acceleration was rejected. SPEC §8; docs/BENCHMARKS.md
  // "Observer evaluation": 8 against 4 and never.
  std::int32_t rest_from_accel_after = 8;
  double dropout_s = 0.25;              // no usable displacement sample for this long: sensor lost [s]
  double max_age_s = 0.05;              // older samples (behind the ground stream) are dropped [s]
  double x_range_m = 0.5;               // |x_mid| beyond this: out of range [m]
  double a_range_mps2 = 80.0;           // |a_mid| beyond this: out of range [m/s²]
  std::int32_t stuck_after = 40;        // identical consecutive displacement readings while rocking: stuck
  double quiet_fraction = 0.5;          // the ground is quiet when |ü| < this × the smaller start threshold [-]
  double v_min_mps = 0.01;              // |ẋ⁻| floor in the saltation matrix (bounds it at grazing impacts) [m/s]
  double inform_sigmas = 3.0;           // an impact informs √r only when |ẋ⁻| ≥ this × σ(ẋ⁻) and ≥ v_min [-]
  double inform_peak_noises = 10.0;     // … and the half-cycle before it peaked at ≥ this × x_noise [-]
  // The same gate for the accelerometer's updates of κc, κk [-]. At the start of motion (x ≈ 0) a − ü measures the
  // threshold c_s/γ, i.e. κc alone; x_inst = κc/κk · x_inst,nominal then moves with κc while κk keeps its prior. That
  // is right for a wall thinner or thicker than its drawings (κk ≈ 1) and wrong for an overburden or other heights
  // (κk moves with κc): 0 (learn from the first motion) meets the 3 % x_inst goal on the thickness cases but costs the
  // overburden cases their false-alarm rate (Fp 2 kN/m + accel 0.018 → 0.137). For a wall whose overburden and
  // heights are known. SPEC §8; docs/BENCHMARKS.md "Observer evaluation", "The capacity from the first motion".
  double accel_inform_peak_noises = 10.0;
  double capacity_sigma0 = 0.15;        // prior σ of κc and κk (the wall's c and k relative to the nominal) [-]
  double capacity_walk = 0.0;           // random walk of κc and κk per step [-]
  // The alarm's margin on the estimated capacity k_σ: it uses x_inst,est − k_σ·σ(x_inst) (and λ_w times it, the
  // energy barrier and the time to instability of that x_inst with the estimated k), at least 0.3 × nominal.
  // Measured on `rockwatch study --alarms --observer` (3520 runs, 972 true collapses; recall 1.0 for every k_σ):
  //   k_σ      0      0.5    1      2
  //   false    3.2 %  4.3 %  6.1 %  14.1 %   (nominal constants before: 5.0 %)
  //   lead p05 0.398  0.405  0.419  0.446 s  (median 0.63, 0.65, 0.69, 0.88 s)
  // On the 16 mismatch cases of issue 27 (14 080 runs, 3092 true collapses; recall 3091/3092 at both):
  //   k_σ 0.5: false 3.8 %, ≤ 0.03 in 6 of 16 cases; lead median 0.634 s, p05 0.368 s, ≥ 0.6 s in 10 of 16
  //   k_σ 0:   false 3.0 %, ≤ 0.03 in 10 of 16 cases; lead median 0.613 s, p05 0.359 s, ≥ 0.6 s in the same 10
  // 0 (issue 27): the cases short of 0.6 s lead (stiffer walls, which rock faster) are short at either value.
  double alarm_capacity_sigmas = 0.0;
  // Model doubt (issue 40, SPEC §11): the wall is not the model. The displacement's normalised innovation squared
  // y²/S (χ² with one degree of freedom: mean 1 when the model and its covariance are right), capped at the gate and
  // averaged over about `doubt_window` samples (exponentially), above `doubt_nis` says the innovations are larger
  // than the covariance allows: flagged (model_doubt) and counted, and while it lasts σ(κc), σ(κk) are held at least
  // `doubt_capacity_sigma` and σ(√r) at least `doubt_r_sigma`, so that a misfit the filter cannot represent (other
  // heights, crushed hinges, corner impacts) does not go into the capacity with full confidence. 0 turns it off.
  double doubt_nis = 4.0;
  std::int32_t doubt_window = 64;         // samples of the displacement's NIS average [-]
  double doubt_capacity_sigma = 0.05;     // σ floor of κc, κk while in doubt [-]
  double doubt_r_sigma = 0.02;            // σ floor of √r while in doubt [-]
  // The model's form (issue 40, SPEC §11): no wall is the two-rigid-block model, so the published σ(x_inst) adds, in
  // quadrature to the filter's own, `model_form_sigma` × x̂_inst, and `doubt_model_form_sigma` × x̂_inst once model
  // doubt has been raised in the run (a wall that has shown it is not the model: its capacity is an extrapolation of
  // the wrong curve). The filter, its gains and the alarm's margin (alarm_capacity_sigmas) keep the filter's σ
  // (sigma_x_inst_filter_m). Measured on the truths of tests/data/truths (docs/BENCHMARKS.md "Model error"): the rigid
  // families' x̂_inst ends 0.5–3.3 % off at the median (at most 7.7 %), with filter σ as small as 0.1 % (z up to 24);
  // crushed hinges up to 130 % (survivors: the rigid model extrapolates a plateau). 0.03 and 0.2 put x_inst within 3 σ
  // at the end in 16 of 16 cases of every family (before: 9–13), after five impacts in 11–15 of 11–15.
  double model_form_sigma = 0.03;
  double doubt_model_form_sigma = 0.2;
  // A wall that moves where the model says it cannot (issue 40): while the model rests and the ground is quiet,
  // `reinit_after` displacement rejections in a row whose readings spread over at least this many σ of the
  // transducer are motion, not a fault (a fault reads a constant or jumps once): the motion is re-initialised from
  // the measurement and model doubt is raised. 0: every such reading stays a fault (before issue 40). 20 (1 cm at the
  // default noise), not 8: a crushed hinge's elastic phase moves the wall a few millimetres below the threshold, and
  // re-initialising the rigid model there taught it a wrong capacity (x_inst median error 35 % against 20 % on the
  // crushed truths; docs/BENCHMARKS.md "Model error").
  double quiet_motion_spread_noises = 20.0;
};

// Why init() refused. Values are stable: append, never renumber.
enum class ObserverError : std::uint8_t {
  ok = 0,
  noise_out_of_range = 1,     // x_noise in [1e-6, 0.1] m, a_noise in [1e-4, 10] m/s², process in [1e-4, 100] m/s²
  prior_out_of_range = 2,     // r_sigma0 in (0, 1], bias_sigma0 in (0, 0.1] m, walks ≥ 0 and small
  gate_out_of_range = 3,      // gate in [1, 1000], reinit_after in [1, 1000], stuck_after in [2, 100000],
                              // capacity_reopen_after, rest_from_accel_after in [0, 1000]
  timing_out_of_range = 4,    // dropout in (0, 60] s, max_age in [0, 10] s, step in (0, 0.1] s
  range_out_of_range = 5,     // x_range in (0, 2] m, a_range in (0, 128] m/s², quiet fraction in [0, 1], v_min > 0,
                              // inform_peak_noises, accel_inform_peak_noises in [0, 1000]
  doubt_out_of_range = 6,     // doubt_nis 0 or in [1, 1000], doubt_window in [1, 100000], doubt sigmas in [0, 1],
                              // quiet_motion_spread_noises in [0, 1000], model_form sigmas in [0, 1]
};

inline const char* observer_error_message(ObserverError e) {
  switch (e) {
    case ObserverError::ok: return "ok";
    case ObserverError::noise_out_of_range:
      return "observer noise out of range (x_noise in [1e-6, 0.1] m, a_noise in [1e-4, 10] m/s2, process in [1e-4, 100] m/s2)";
    case ObserverError::prior_out_of_range:
      return "observer prior out of range (r_sigma0 in (0, 1], bias_sigma0 in (0, 0.1] m, walks in [0, 0.01], "
             "capacity_sigma0 in [1e-4, 1], alarm_capacity_sigmas in [0, 10])";
    case ObserverError::gate_out_of_range:
      return "observer gate out of range (gate_chi2 in [1, 1000], reinit_after in [1, 1000], stuck_after in [2, 100000], "
             "capacity_reopen_after and rest_from_accel_after in [0, 1000])";
    case ObserverError::timing_out_of_range:
      return "observer timing out of range (dropout in (0, 60] s, max_age in [0, 10] s)";
    case ObserverError::range_out_of_range:
      return "observer ranges invalid (x_range in (0, 2] m, a_range in (0, 128] m/s2, quiet_fraction in [0, 1], "
             "inform_peak_noises and accel_inform_peak_noises in [0, 1000])";
    case ObserverError::doubt_out_of_range:
      return "observer model doubt out of range (doubt_nis 0 or in [1, 1000], doubt_window in [1, 100000], "
             "doubt_capacity_sigma and doubt_r_sigma in [0, 1], quiet_motion_spread_noises in [0, 1000], "
             "model_form_sigma and doubt_model_form_sigma in [0, 1])";
  }
  return "?";
}

inline ObserverError validate_observer_options(const ObserverOptions& o) {
  auto in = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  if (!(in(o.x_noise_m, 1e-6, 0.1) && in(o.a_noise_mps2, 1e-4, 10.0) && in(o.process_accel_mps2, 1e-4, 100.0)))
    return ObserverError::noise_out_of_range;
  if (!(o.r_sigma0 > 0.0 && o.r_sigma0 <= 1.0 && o.bias_sigma0_m > 0.0 && o.bias_sigma0_m <= 0.1 &&
        in(o.r_walk, 0.0, 0.01) && in(o.bias_walk_m, 0.0, 0.01) && in(o.capacity_sigma0, 1e-4, 1.0) &&
        in(o.capacity_walk, 0.0, 0.01) && in(o.alarm_capacity_sigmas, 0.0, 10.0)))
    return ObserverError::prior_out_of_range;
  if (!(in(o.gate_chi2, 1.0, 1000.0) && o.reinit_after >= 1 && o.reinit_after <= 1000 && o.stuck_after >= 2 &&
        o.stuck_after <= 100000 && o.capacity_reopen_after >= 0 && o.capacity_reopen_after <= 1000 &&
        o.rest_from_accel_after >= 0 && o.rest_from_accel_after <= 1000))
    return ObserverError::gate_out_of_range;
  if (!(o.dropout_s > 0.0 && o.dropout_s <= 60.0 && in(o.max_age_s, 0.0, 10.0)))
    return ObserverError::timing_out_of_range;
  if (!(o.x_range_m > 0.0 && o.x_range_m <= 2.0 && o.a_range_mps2 > 0.0 && o.a_range_mps2 <= 128.0 &&
        in(o.quiet_fraction, 0.0, 1.0) && o.v_min_mps > 0.0 && o.v_min_mps <= 1.0 && in(o.inform_sigmas, 0.0, 100.0) &&
        in(o.inform_peak_noises, 0.0, 1000.0) && in(o.accel_inform_peak_noises, 0.0, 1000.0)))
    return ObserverError::range_out_of_range;
  if (!((o.doubt_nis == 0.0 || in(o.doubt_nis, 1.0, 1000.0)) && o.doubt_window >= 1 && o.doubt_window <= 100000 &&
        in(o.doubt_capacity_sigma, 0.0, 1.0) && in(o.doubt_r_sigma, 0.0, 1.0) &&
        in(o.quiet_motion_spread_noises, 0.0, 1000.0) && in(o.model_form_sigma, 0.0, 1.0) &&
        in(o.doubt_model_form_sigma, 0.0, 1.0)))
    return ObserverError::doubt_out_of_range;
  return ObserverError::ok;
}

// One sample of the wall-mounted sensors (wall_sensor_t, or a row of a --wall-sensors file).
struct WallSensorSample {
  std::int64_t utime_us = 0;    // sample time on the ground stream's clock [µs]
  double x_mid_m = 0.0;         // displacement transducer at the mid-height hinge [m] (x_valid)
  double a_mid_mps2 = 0.0;      // absolute horizontal acceleration at mid-height [m/s²] (a_valid)
  bool x_valid = false, a_valid = false;
  std::int32_t sensor_status = 0;  // the sensor's own status bits (not 0: counted, flagged)
};

// Health and event bits of the observer (wall_estimate_t SENSOR_*). A bit keeps its meaning forever.
namespace observer_flag {
inline constexpr std::uint32_t x_active = 1u << 0;          // a displacement sample was used within the dropout time
inline constexpr std::uint32_t a_active = 1u << 1;          // an acceleration sample was used within the dropout time
inline constexpr std::uint32_t sensor_lost = 1u << 2;       // no usable displacement sample for dropout_s: model alone
inline constexpr std::uint32_t rejected = 1u << 3;          // an innovation failed the χ² gate
inline constexpr std::uint32_t not_finite = 1u << 4;        // NaN/Inf reading (discarded)
inline constexpr std::uint32_t out_of_range = 1u << 5;      // reading beyond the sensor range (discarded)
inline constexpr std::uint32_t stuck = 1u << 6;             // displacement constant while the wall rocks (discarded)
inline constexpr std::uint32_t motion_while_quiet = 1u << 7;  // sensor shows motion, model at rest, ground quiet
inline constexpr std::uint32_t misaligned = 1u << 8;        // sample applied more than one step after its time
inline constexpr std::uint32_t stale = 1u << 9;             // sample older than max_age (dropped)
inline constexpr std::uint32_t queue_overflow = 1u << 10;   // sensor samples without ground samples (oldest dropped)
inline constexpr std::uint32_t reinitialised = 1u << 11;    // the motion was re-initialised from the measurement
inline constexpr std::uint32_t sensor_flag = 1u << 12;      // the sensor set a status bit
inline constexpr std::uint32_t jump = 1u << 13;             // a displacement jump (rejected) while the ground is quiet
inline constexpr std::uint32_t estimate_clamped = 1u << 14; // an estimate (√r, κc, κk, x_inst) left its range: clamped
inline constexpr std::uint32_t model_doubt = 1u << 15;      // the innovations say the model is wrong (NIS): σ held wide
// Any of these is a sensor fault (never silent: the monitor flags alarms that coincide with one).
inline constexpr std::uint32_t faults = not_finite | out_of_range | stuck | motion_while_quiet | stale |
                                        queue_overflow | sensor_flag | jump;
}  // namespace observer_flag

struct ObserverCounters {
  std::int64_t samples = 0;          // sensor samples received
  std::int64_t x_updates = 0, a_updates = 0;  // accepted measurement updates
  std::int64_t rejected = 0;         // gated out
  std::int64_t not_finite = 0, out_of_range = 0, stuck = 0, motion_while_quiet = 0, jumps = 0;
  std::int64_t misaligned = 0, stale = 0, queue_overflow = 0, reinitialised = 0, sensor_flags = 0;
  std::int64_t impacts = 0;          // impacts seen by the covariance (saltation applied)
  std::int64_t dropouts = 0;         // transitions into sensor_lost
  std::int64_t clamped = 0;          // corrections whose estimate left its physical range (clamped)
  std::int64_t impacts_in_corrections = 0;  // impacts implied by a correction across the hinge (in `impacts` too)
  std::int64_t capacity_reopened = 0;  // the capacity's covariance re-opened (ObserverOptions::capacity_reopen_after)
  std::int64_t rest_from_accel = 0;    // the model put to rest: the accelerometer read a wall at rest (rest_from_accel_after)
  std::int64_t model_doubt = 0;        // steps in model doubt (ObserverOptions::doubt_nis)
  std::int64_t quiet_motion = 0;       // re-initialisations from motion while the model rested on a quiet ground
};

// Every counter with its published name, in the published order: the one list the reports (the monitor's summary,
// `rockwatch simulate --json`) are written from. `visit(const char* name, std::int64_t value)`.
template <typename Visit>
void visit_observer_counters(const ObserverCounters& c, Visit&& visit) {
  visit("samples", c.samples);
  visit("x_updates", c.x_updates);
  visit("a_updates", c.a_updates);
  visit("rejected", c.rejected);
  visit("not_finite", c.not_finite);
  visit("out_of_range", c.out_of_range);
  visit("stuck", c.stuck);
  visit("motion_while_quiet", c.motion_while_quiet);
  visit("jumps", c.jumps);
  visit("misaligned", c.misaligned);
  visit("stale", c.stale);
  visit("queue_overflow", c.queue_overflow);
  visit("reinitialised", c.reinitialised);
  visit("sensor_flags", c.sensor_flags);
  visit("impacts", c.impacts);
  visit("dropouts", c.dropouts);
  visit("clamped", c.clamped);
  visit("impacts_in_corrections", c.impacts_in_corrections);
  visit("capacity_reopened", c.capacity_reopened);
  visit("rest_from_accel", c.rest_from_accel);
  visit("model_doubt", c.model_doubt);
  visit("quiet_motion", c.quiet_motion);
}

// The end of an input sample that starts t0_s after the record's start, on the wall sensors' clock [µs]: what an
// analysis steps the observer to (sim::analyse) and what the Cortex-M4 replay computes for the same sample, so both
// push the same sensor samples before each step.
inline std::int64_t observed_step_end_us(double t0_s, double dt_s) {
  return static_cast<std::int64_t>(std::llround((t0_s + dt_s) * 1e6));
}

// a − b for sample times [µs], saturated: times come from the network and may be anything (no undefined overflow).
inline std::int64_t time_difference_us(std::int64_t a, std::int64_t b) {
  std::int64_t d = 0;
  if (__builtin_sub_overflow(a, b, &d)) return b < 0 ? INT64_MAX : INT64_MIN;
  return d;
}

// What each piece of the observer's work costs when metered [work units] (core/work_meter.hpp): a sub-step's
// prediction (begin_step, end_step), one sensor sample applied (its displacement and acceleration updates, the
// covariance brought up to date first, the corrections fed back into the stepper), a sample's end (the covariance
// brought up to date, the alarm's scales of the estimated wall, the published estimates), one sensor sample dropped.
struct ObserverWorkCosts {
  std::int32_t substep;
  std::int32_t update;
  std::int32_t sample_end;
  std::int32_t dropped;     // a due sensor sample dropped unapplied (stale, or the wall collapsed)
};

// How the observer reads and corrects a stepper. Specialised for the two steppers.
template <typename Stepper>
struct ObserverStepperTraits;

template <>
struct ObserverStepperTraits<RockingStepper<double>> {
  using Scalar = double;
  using Cov = double;  // the covariance, gains and linearisations
  using Input = double;
  using Report = StepReport<double>;
  static constexpr ObserverWorkCosts kWork{0, 0, 0, 0};  // hosts only: never metered
  static double x(const RockingStepper<double>& s) { return s.state().x_m; }
  static double xd(const RockingStepper<double>& s) { return s.state().xd_mps; }
  static double xdd(const RockingStepper<double>& s) { return s.state().xdd_mps2; }
  static double input(Input v) { return v; }
  static double v_before(const Report& r) { return r.first_impact_v_before_mps; }
  static void set_motion(RockingStepper<double>& s, double x, double xd, Input ug, Input vg) {
    s.set_state(x, xd, ug, vg);
  }
  static void set_sqrt_r(RockingStepper<double>& s, double e) { s.set_sqrt_r(e); }
  static void set_capacity(RockingStepper<double>& s, double kc, double kk, Input, Input) {
    s.set_capacity_scales(kc, kk);
  }
};

template <>
struct ObserverStepperTraits<FixedRockingStepper> {
  using Scalar = ObserverQ10_53;
  // The covariance, the gains and the linearisations in single precision on the M4F's FPU (as PX4's EKF2 on
  // Cortex-M4F/M7): a product is one VMUL.F32 instead of a 128-bit product of Fixed64 (~55 instructions), a division
  // one VDIV.F32. Host and target agree bit for bit: IEEE single, round to nearest, no contraction into fused
  // multiply-adds (-ffp-contract=off in both builds). The state (x, ẋ, e, b, κc, κk) stays in fixed point.
  using Cov = float;
  using Input = AccelQ7_56;
  using Report = FixedStepReport;
  // Upper bounds measured on the emulated M4 (docs/BENCHMARKS.md, "The metered observer").
  static constexpr ObserverWorkCosts kWork{1000, 5000, 2500, 300};
  static Scalar x(const FixedRockingStepper& s) { return wide_convert<Scalar>(s.x_m()); }
  static Scalar xd(const FixedRockingStepper& s) { return wide_convert<Scalar>(s.xd_mps()); }
  static Scalar xdd(const FixedRockingStepper& s) { return wide_convert<Scalar>(s.xdd_mps2()); }
  static Scalar input(Input v) { return wide_convert<Scalar>(v); }
  static Scalar v_before(const Report& r) { return wide_convert<Scalar>(r.first_impact_v_before_mps); }
  // The observer corrects the state after the step (or set_capacity) whose input is (ug, vg): f and k are the
  // stepper's already (correct_state: no recomputation, the same state as set_state at that input).
  static void set_motion(FixedRockingStepper& s, Scalar x, Scalar xd, Input, Input) {
    s.correct_state(wide_convert<LengthQ1_62>(x), wide_convert<SpeedQ3_60>(xd));
  }
  static void set_sqrt_r(FixedRockingStepper& s, Scalar e) { s.set_sqrt_r(wide_convert<FractionQ1_62>(e)); }
  static void set_capacity(FixedRockingStepper& s, Scalar kc, Scalar kk, Input ug, Input vg) {
    s.set_capacity_scales(wide_convert<GainQ4_59>(kc), wide_convert<GainQ4_59>(kk), ug, vg);
  }
};

// What the observer did in one step.
struct ObserverStepReport {
  std::uint32_t flags = 0;        // observer_flag bits of this step (health bits included)
  std::int32_t x_updates = 0, a_updates = 0;
  bool corrected = false;         // the stepper's state was corrected by a measurement this step
};

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
    accel_inform_peak_x2_ = Cov(o.accel_inform_peak_noises * o.accel_inform_peak_noises) * r_x_;
    x_range_ = o.x_range_m;
    a_range_ = o.a_range_mps2;
    us_to_s_ = Scalar(1e-6);
    reinit_v_var_ = Cov(0.05 * 0.05);
    const double threshold = std::fmin(threshold_mps2(c, Side::negative, setup.g_mps2),
                                       threshold_mps2(c, Side::positive, setup.g_mps2));
    quiet_ug_ = Scalar(o.quiet_fraction * threshold);
    dropout_us_ = std::int64_t(o.dropout_s * 1e6 + 0.5);
    max_age_us_ = std::int64_t(o.max_age_s * 1e6 + 0.5);
    reinit_after_ = o.reinit_after;
    doubt_nis_ = Cov(o.doubt_nis);
    doubt_alpha_ = Cov(1.0 / o.doubt_window);
    doubt_c_var_ = Cov(o.doubt_capacity_sigma * o.doubt_capacity_sigma);
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
    p_(C, C) = p_(K, K) = capacity_sigma0_ * capacity_sigma0_;
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
    have_last_raw_ = false;
    last_raw_x_ = 0.0;
    impact_last_step_ = false;
    last_impact_us_ = INT64_MIN;
    peak_x_ = Scalar(0);
    last_innovation_x_ = Scalar(0);
    last_innovation_a_ = Scalar(0);
    innovation_x_sq_sum_ = Scalar(0);
    nis_avg_ = Cov(1);
    doubt_ = false;
    quiet_lo_ = quiet_hi_ = Scalar(0);
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

  // After the stepper's step that ends at `t_us` with input (ug, vg) at its end (report: what the stepper did):
  // covariance prediction through the step (and its impact), then every queued sample with utime ≤ t_us, in
  // order, then the end of the sample (the covariance brought up to date). Corrects the stepper's state and √r.
  // All at once: begin_step(), run_updates() without a meter, end_step(), end_sample() (tests and tools that step the
  // observer by hand; StepperAlarmChain runs the pieces, metered, and end_sample() once per input sample).
  ObserverStepReport after_step(Stepper& stepper, const Report& report, Input ug, Input vg, std::int64_t t_us,
                                std::int64_t step_us) {
    begin_step(stepper, report, ug, vg, t_us, step_us);
    UnmeteredWork meter;
    run_updates(stepper, meter);
    const ObserverStepReport out = end_step(stepper);
    end_sample();
    return out;
  }

  // The pieces of after_step (the chain's carry-over, core/work_meter.hpp). begin_step: the prediction through the
  // step, composed into the sample's transition (kWork.substep). run_updates: the queued samples with utime ≤ t_us,
  // in order, one piece each (kWork.update, the covariance brought up to date first); false when the meter cannot
  // pay for the next one (nothing of it done: the next call goes on from there). A shedding meter (the engine's queue
  // is full) drops the due samples instead (counted and flagged queue_overflow). end_step: the step's bookkeeping
  // and its report. end_sample: once per input sample, the covariance brought up to date (kWork.sample_end, with the
  // chain's alarm scales).
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
  }
  template <typename Meter>
  bool run_updates(Stepper& stepper, Meter& meter) {
    ObserverStepReport& out = step_out_;
    while (count_ > 0 && queue_[head_].utime_us <= step_t_us_) {
      if (meter.shed) {  // the engine sheds: the sample is dropped, not applied (its check paid, as a stale one's)
        if (!meter.take(kWork.dropped)) return false;
        head_ = (head_ + 1) % kQueueCapacity;
        --count_;
        ++counters_.queue_overflow;
        out.flags |= observer_flag::queue_overflow;
        continue;
      }
      const std::int64_t age_us = time_difference_us(step_t_us_, queue_[head_].utime_us);
      const bool stale = age_us > max_age_us_;
      // A sample dropped (stale, or nothing left to estimate) costs its check only; one applied, its updates.
      if (!meter.take(stale || stepper.collapsed() ? kWork.dropped : kWork.update)) return false;
      const WallSensorSample s = queue_[head_];
      head_ = (head_ + 1) % kQueueCapacity;
      --count_;
      if (stale) {
        ++counters_.stale;
        out.flags |= observer_flag::stale;
        continue;
      }
      if (age_us > step_us_) {
        ++counters_.misaligned;
        out.flags |= observer_flag::misaligned;
      }
      if (stepper.collapsed()) continue;  // nothing left to estimate
      // The updates need the covariance of now: the sample's transition so far applied.
      flush();
      if (s.x_valid) update_x(stepper, s, age_us, step_ug_, step_vg_, step_quiet_, out);
      // An acceleration taken before the last impact (queued, applied after it) belongs to the other side: its ẍ
      // differs by about 2·c_s from the model's now. Only samples taken after the step that held the impact are used.
      const bool after_impact = s.utime_us > last_impact_us_;
      if (s.a_valid && !step_impact_ && !impact_last_step_ && after_impact && stepper.moving())
        update_a(stepper, s, Traits::input(step_ug_), step_vg_, step_ug_, out);
    }
    return true;
  }
  ObserverStepReport end_step(const Stepper& stepper) {
    ObserverStepReport& out = step_out_;
    const std::int64_t t_us = step_t_us_;
    impact_last_step_ = step_impact_;
    if (!have_first_t_) {
      have_first_t_ = true;
      first_t_us_ = t_us;
    }
    // Sensor loss counts from the last usable displacement sample, or from the first step when there was none.
    // A sensor that keeps sending but is always gated out is not lost (it is flagged rejected), but not active.
    const std::int64_t since_us = time_difference_us(t_us, have_x_used_ ? last_x_used_us_ : first_t_us_);
    if (have_x_accepted_ && time_difference_us(t_us, last_x_accepted_us_) <= dropout_us_) {
      out.flags |= observer_flag::x_active;
    }
    if (since_us > dropout_us_) {
      if (!lost_) ++counters_.dropouts;
      lost_ = true;
    }
    if (lost_) out.flags |= observer_flag::sensor_lost;
    if (a_used_recent(t_us)) out.flags |= observer_flag::a_active;
    if (doubt_) {
      out.flags |= observer_flag::model_doubt;
      ++counters_.model_doubt;
      hold_doubt_floors();
    }
    x_prev_ = Traits::x(stepper);
    return out;
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
  double nis_average() const { return to_d(nis_avg_); }
  double sigma_x_m() const { return root(p_(X, X)); }
  double sigma_xd_mps() const { return root(p_(V, V)); }
  double sigma_r() const { return pub(Cov(2) * ec_ * root_c(p_(E, E))); }
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
  // The published σ(x_inst): the filter's (the variance of κc/κk by first-order propagation) and the model's form
  // (ObserverOptions::model_form_sigma, doubt_model_form_sigma once model doubt was raised) in quadrature.
  double sigma_x_inst_m(Side s = Side::positive) const {
    const Cov f = sigma_x_inst_c(s), x = x_inst_c(s);
    const Cov form = counters_.model_doubt > 0 ? doubt_model_form_var_ : model_form_var_;
    return pub(root_c(f * f + form * x * x));
  }
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
  Cov sigma_x_inst_c(Side s) const {
    const Cov ratio = kcc_ / kkc_;
    const Cov var = p_(C, C) - Cov(2) * ratio * p_(C, K) + ratio * ratio * p_(K, K);
    return x_inst0_[side_index(s)] / kkc_ * root_c(var);
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

  bool a_used_recent(std::int64_t t_us) const {
    return have_a_used_ && time_difference_us(t_us, last_a_used_us_) <= dropout_us_;
  }

  void zero_motion_covariance() {
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
  void predict(const Stepper& stepper, const Report& report) {
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
        jv[X] = (a_after - e * a_before) / cov(v_floored);
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
  }

  // Φ = I, Q = 0: nothing pending.
  void reset_transition() {
    for (int c = 0; c < kStates; ++c) phi_x_[c] = phi_v_[c] = Cov(0);
    phi_x_[X] = phi_v_[V] = Cov(1);
    phi_identity_ = true;
    qa_[0] = qa_[1] = qa_[2] = Cov(0);
    qa_zero_ = true;
    walk_steps_ = 0;
  }

  // The motion known exactly (at rest): rows X and V of Φ and the pending noise zero (P's rows and columns X, V
  // become zero at the flush, as zero_motion_covariance()).
  void zero_motion_transition() {
    for (int c = 0; c < kStates; ++c) phi_x_[c] = phi_v_[c] = Cov(0);
    phi_identity_ = false;
    qa_[0] = qa_[1] = qa_[2] = Cov(0);
    qa_zero_ = true;
  }

  // Φ ← F Φ and Q ← F Q Fᵀ for an F that is the identity but in rows X, V (fx, fv): with Φ = [A B; 0 I] and
  // F = [a b; 0 I] (blocks of rows X, V and of the other four), F Φ = [a A, a B + b; 0 I]. 24 products.
  void compose(const Cov* fx, const Cov* fv) {
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
  Cov current_vv() const {
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
  void flush() {
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
  void transition(int i, Scalar x0, Scalar x1, Cov* fx, Cov* fv) const {
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

  // One scalar measurement with P h = ph already formed (h sparse: the callers add P's columns), s = hᵀ P h + r,
  // innovation y. Returns false when gated out. Only the upper triangle of P is computed (then mirrored).
  // learn = false: the wall's parameters (e, κc, κk) are considered, not estimated (Schmidt–Kalman: their gain is
  // zero and the covariance follows the Joseph form of that gain, so it stays the covariance of the errors).
  // 1/s for the gains k = P h / s: one division for the whole gain (six products instead of six divisions).
  bool scalar_update(Cov (&ph)[kStates], Cov s, Cov y, Vec& correction, bool learn = true) {
    if (!(s > Cov(0))) return false;
    if (y * y > gate_ * s) return false;
    const Cov inv_s = Cov(1) / s;
    Cov k[kStates];
    for (int a = 0; a < kStates; ++a) k[a] = ph[a] * inv_s;
    if (learn) {
      for (int a = 0; a < kStates; ++a) {
        correction(a) = from_cov(k[a] * y);
        for (int c = a; c < kStates; ++c) p_(a, c) = p_(a, c) - k[a] * ph[c];
      }
    } else {
      k[E] = k[C] = k[K] = Cov(0);
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

  // The motion is large enough to say something about the wall's parameters: this half-cycle's peak (or |x| now)
  // at least inform_peak_noises × the transducer's σ. Below, the fused model's motion is mostly the sensor noise
  // (a wall rocking at sub-noise amplitude, or at rest): fitting c, k or r to it biases them with a confident σ.
  bool informative(Scalar x) const { return informative(x, inform_peak_x2_); }
  bool informative(Scalar x, Cov peak_x2) const {
    const Cov a = cov(abs(x) > peak_x_ ? abs(x) : peak_x_);
    return a * a >= peak_x2;
  }

  void symmetrise() {
    for (int a = 0; a < kStates; ++a) {
      for (int c = a + 1; c < kStates; ++c) p_(c, a) = p_(a, c);
    }
    for (int a = 0; a < kStates; ++a) {
      if (p_(a, a) < Cov(0)) p_(a, a) = Cov(0);
    }
  }

  void apply(Stepper& stepper, const Vec& dz, Input ug, Input vg) {
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
    // x_inst = κc/κk·x_inst,nominal within [0.3, 2]× nominal: κc moves (the capacity is what the data pins least).
    if (kc_ < Scalar(0.3) * kk_) {
      kc_ = Scalar(0.3) * kk_;
      clamped = true;
    } else if (kc_ > Scalar(2) * kk_) {
      kc_ = Scalar(2) * kk_;
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

  static bool clamp_to(Scalar& v, Scalar lo, Scalar hi) {
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

  void update_x(Stepper& stepper, const WallSensorSample& s, std::int64_t age_us, Input ug, Input vg, bool quiet,
                ObserverStepReport& out) {
    // Stuck: the same reading again and again while the wall rocks.
    if (have_last_raw_ && s.x_mid_m == last_raw_x_) {
      ++identical_run_;
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
    if (scalar_update(ph, s_x, cov(y), dz, informative(x))) {
      apply(stepper, dz, ug, vg);
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
    ++consecutive_rejections_;
    // The sensor is sending, just disagreeing: not lost (rejections are flagged on their own).
    last_x_used_us_ = s.utime_us;
    have_x_used_ = true;
    lost_ = false;
    if (quiet) {
      // The ground is quiet: a rigid wall does not start rocking by itself, so a reading that disagrees is a sensor
      // fault, not a re-initialisation — unless it keeps disagreeing and moves (a fault reads a constant or jumps
      // once): then the wall moves where the model says it cannot (a lower threshold, crushed hinges, an elastic
      // phase), the most informative reading there is (issue 40). The run's readings' spread decides.
      if (!stepper.moving()) {
        if (consecutive_rejections_ == 1) {
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
  void note_innovation(Cov y, Cov s) {
    if (!(doubt_nis_ > Cov(0)) || !(s > Cov(0))) return;
    Cov nis = y * y / s;
    if (nis > gate_) nis = gate_;
    nis_avg_ = nis_avg_ + (nis - nis_avg_) * doubt_alpha_;
    doubt_ = nis_avg_ > doubt_nis_;
  }
  // After the step's updates, while in doubt: σ(κc), σ(κk) and σ(√r) at least their floors. The pending prediction
  // (flush) leaves these diagonal entries as they are but for their walks; a larger diagonal keeps P positive
  // semi-definite.
  void hold_doubt_floors() {
    if (p_(C, C) < doubt_c_var_) p_(C, C) = doubt_c_var_;
    if (p_(K, K) < doubt_c_var_) p_(K, K) = doubt_c_var_;
    if (p_(E, E) < doubt_e_var_) p_(E, E) = doubt_e_var_;
  }

  // Re-open the capacity: κc and κk forget their correlations and take a variance of at least (the disagreement in
  // units of κc)², never less than the prior's, so that the next accelerations pass the gate and move them; x, ẋ, e
  // and b keep what they know. `kappa_error`: the last innovation over ∂a/∂κc = −s·c_s [-].
  void reopen_capacity(Cov kappa_error) {
    for (int j = 0; j < kStates; ++j) {
      p_(C, j) = p_(j, C) = Cov(0);
      p_(K, j) = p_(j, K) = Cov(0);
    }
    const Cov prior = capacity_sigma0_ * capacity_sigma0_, need = kappa_error * kappa_error;
    p_(C, C) = p_(K, K) = need > prior ? need : prior;
    consecutive_a_rejections_ = 0;
    ++counters_.capacity_reopened;
  }

  // The accelerometer has read a wall at rest rest_after_ times in a row while the model rocked: the model rests.
  // What was learned (ê, b̂, κc, κk) stays.
  void put_to_rest(Stepper& stepper, Input ug, Input vg) {
    Traits::set_motion(stepper, Scalar(0), Scalar(0), ug, vg);
    zero_motion_covariance();
    rest_votes_ = 0;
    ++counters_.rest_from_accel;
  }

  // The measurement has disagreed with the model for reinit_after samples while the ground shakes: the real wall
  // moves where the model does not (or the sensor is back after a dropout). Restart the motion at the reading with
  // a wide velocity prior; what was learned (ê, b̂) stays.
  void reinitialise(Stepper& stepper, Scalar z, Input ug, Input vg, ObserverStepReport& out) {
    const Scalar x = z - b_;
    Traits::set_motion(stepper, x, Scalar(0), ug, vg);
    Traits::set_sqrt_r(stepper, e_);
    zero_motion_covariance();
    p_(X, X) = r_x_;
    p_(V, V) = reinit_v_var_;
    consecutive_rejections_ = 0;
    ++counters_.reinitialised;
    out.flags |= observer_flag::reinitialised;
    out.corrected = true;
  }

  void update_a(Stepper& stepper, const WallSensorSample& s, Scalar ug_s, Input vg, Input ug,
                ObserverStepReport& out) {
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
    const bool learn = informative(x);  // the capacity's re-open rule: the displacement's gate
    const bool learn_a = accel_inform_peak_x2_ == inform_peak_x2_ ? learn : informative(x, accel_inform_peak_x2_);
    if (!scalar_update(ph, hx * ph[X] + hc * ph[C] + hk * ph[K] + r_a_, cov(y), dz, learn_a)) {
      ++counters_.rejected;
      out.flags |= observer_flag::rejected;
      const bool x_agrees = consecutive_rejections_ == 0;  // the last displacement update passed
      // The displacement agrees and the motion is large enough to inform the capacity, yet the accelerometer keeps
      // disagreeing: the capacity is further from the estimate than its covariance says.
      if (reopen_after_ > 0 && x_agrees && learn && ++consecutive_a_rejections_ >= reopen_after_) {
        reopen_capacity(cov(y) / hc);
      }
      // The reading is what a wall at rest gives (a = ü, block 1 vertical): the model rocks where the real wall
      // does not. Every such reading in a row, with the displacement agreeing, is a vote; rest_after_ votes put the
      // model to rest, where its state is known (x = ẋ = 0), and the stepper's start logic takes it from there.
      const Cov y_rest = cov(Scalar(s.a_mid_mps2) - ug_s);
      if (rest_after_ > 0 && x_agrees && y_rest * y_rest <= gate_ * r_a_) {
        if (++rest_votes_ >= rest_after_) put_to_rest(stepper, ug, vg);
      } else {
        rest_votes_ = 0;
      }
      return;
    }
    consecutive_a_rejections_ = 0;
    rest_votes_ = 0;
    apply(stepper, dz, ug, vg);
    ++counters_.a_updates;
    ++out.a_updates;
    out.corrected = true;
    last_a_used_us_ = s.utime_us;
    have_a_used_ = true;
  }

  // Constants (init).
  Cov k0_[2]{};        // the nominal k_s = p4/p1 at ü = 0, G = g per side [1/s²]
  Cov x_inst0_[2]{};   // the nominal x_inst per side [m]
  Cov h_{}, half_h_{}, quarter_h2_{};  // the step h, h/2, h²/4 [s, s, s²]
  Cov capacity_sigma0_{};
  Cov alarm_capacity_sigmas_ = Cov(0.5);
  Mat q_{};            // process noise per step
  Cov f0_[2]{};        // ẍ at the hinge with ü = 0 per side [m/s²]
  Cov r_x_{}, r_a_{}, gate_{}, reinit_v_var_{};
  Scalar g_over_h1_{}, v_min_{}, us_to_s_{}, quiet_ug_{};
  Scalar inv_h1_{};     // 1/h1 [1/m]
  Cov inform_var_{}, inform_peak_var_{};  // inform_sigmas², inform_peak_noises² [-]
  Cov inform_peak_x2_{};  // inform_peak_noises² × x_noise² [m²]
  Cov accel_inform_peak_x2_{};  // accel_inform_peak_noises² × x_noise² [m²]
  Scalar e0_{};
  Cov e_sigma0_{}, b_sigma0_{};
  double x_range_ = 0.5, a_range_ = 80.0;
  std::int64_t dropout_us_ = 250000, max_age_us_ = 50000;
  std::int32_t reinit_after_ = 8, stuck_after_ = 40, reopen_after_ = 16, rest_after_ = 8;
  Cov doubt_nis_{}, doubt_alpha_{}, doubt_c_var_{}, doubt_e_var_{};  // model doubt (ObserverOptions) [-]
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
  Scalar last_innovation_x_{}, last_innovation_a_{}, innovation_x_sq_sum_{};
};

}  // namespace rockwatch::core
