// What the wall observer (core/wall_observer.hpp) takes in and gives out, apart from its settings
// (observer_options.hpp): a sensor sample, the health and event bits, the counters and their published names, a
// step's report, the cost of each piece of work, sample-time arithmetic and the fixed-point observer's state format.
#pragma once

#include <cmath>
#include <cstdint>

#include "rockwatch/core/fixed_point64.hpp"

namespace rockwatch::core {

// The fixed-point observer's state format (corrections, e, b, κc, κk, innovations): ±1024, resolution 1.1e-16. Its
// covariance is single precision (ObserverStepperTraits<FixedRockingStepper>::Cov); a correction k·y comes back into
// this format saturating at ±1024.
using ObserverQ10_53 = Fixed64<10, 53>;

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
  std::int64_t superseded = 0;         // due sensor samples not applied because a newer one was due at the same
                                       // sub-step (one sensor sample a sub-step: WallObserver::substep)
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
  visit("superseded", c.superseded);
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
// prediction and bookkeeping (WallObserver::substep without its sensor sample), one sensor sample applied (its
// displacement and acceleration updates, the covariance brought up to date first, the corrections fed back into the
// stepper), a sample's end (the covariance brought up to date, the alarm's scales of the estimated wall, the published
// estimates), one sensor sample dropped, one passed over for a newer one.
struct ObserverWorkCosts {
  std::int32_t substep;
  std::int32_t update;
  std::int32_t sample_end;
  std::int32_t dropped;     // a due sensor sample dropped unapplied (stale, or the wall collapsed)
  std::int32_t superseded;  // a due sensor sample passed over because a newer one is due too (its index moved)
};

// One sensor's fusion status, as PX4's EKF2 publishes per sensor: the last reading tried against the model (its
// innovation, the innovation's variance hᵀPh + R, and the test ratio the χ² gate compared with 1) and when one of its
// readings last corrected the state. Kept by the observer per sensor (WallObserver::x_status(), a_status()),
// published in wall_estimate_t (x_*, a_*) and on the dashboard. Units are the sensor's: the displacement
// transducer's [m], the accelerometer's [m/s²].
struct ObserverSensorStatus {
  double innovation = 0.0;           // measured − predicted, last reading tried [m | m/s²]
  double innovation_variance = 0.0;  // hᵀPh + R of that reading [m² | m²/s⁴] (0: none tried yet)
  double test_ratio = 0.0;           // innovation² / (gate_chi2 · variance): above 1 the gate rejected it [-]
  bool rejected = false;             // the last reading tried failed the gate
  bool fused = false;                // a reading of this sensor has corrected the state since start()
  std::int64_t last_fused_us = 0;    // utime of the last accepted reading [µs] (0 until fused)
};

// What the observer did in one step.
struct ObserverStepReport {
  std::uint32_t flags = 0;        // observer_flag bits of this step (health bits included)
  std::int32_t x_updates = 0, a_updates = 0;
  bool corrected = false;         // the stepper's state was corrected by a measurement this step
};

}  // namespace rockwatch::core
