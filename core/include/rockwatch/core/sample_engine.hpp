// The engine seam of the monitor loop: what MonitorLoop needs from a per-sample engine (start, step, restart, the
// published quantities), so that the loop runs whatever engine it is given. The firmware's engine is
// firmware::WallEngine (fixed point, wall_engine.hpp); hosts with an FPU may hand the loop sim::DoubleWallEngine
// (sim/include/rockwatch/sim/double_wall_engine.hpp), which firmware never sees.
//
// Why an abstract class and not a template parameter of MonitorLoop: the loop stays one translation unit compiled
// once, in firmware, with firmware's flags (no exceptions, no RTTI) and audited as such; the host picks the engine at
// run time (--arith) without two instantiations of the loop and its callers. The price is one indirect call per
// sample (measured: tests/bench/callgrind_per_sample.sh). Virtual calls need no RTTI. The destructor is protected and
// not virtual: engines are never deleted through this interface, and a virtual destructor would make every
// implementation's vtable reference operator delete (the symbol audit forbids it).
#pragma once

#include <cstdint>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/sensor_axes.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"

namespace rockwatch::core {

// The default work budget of a call: with the call's own overhead, at most 25 000 Cortex-M4 instructions per sample
// (docs/BENCHMARKS.md, "Bounded work per call").
inline constexpr std::int32_t kDefaultWorkBudgetUnits = 23000;
// What an open-loop call does beyond its meter, at most (measured: docs/BENCHMARKS.md, "Bounded work per call").
inline constexpr std::int32_t kDefaultCallOverheadUnits = 2000;
// The least budget: a sample with one located event must fit one call, else the queue would only ever grow.
inline constexpr std::int32_t kMinWorkBudgetUnits = FixedRockingStepper::kWork.substep + FixedRockingStepper::kWork.trial +
                                                    FixedRockingStepper::kWork.locate + FixedRockingStepper::kWork.evaluate;

// With the wall observer on, the estimator's share of a sample (issue 28): a quarter of the sample period on the
// wall's Cortex-M4 at 168 MHz and about 1.3 cycles per instruction, taken as 128 million instructions a second
// (1 kHz: 32 000 instructions a sample, 200 Hz: 160 000, 100 Hz: 320 000).
inline constexpr double kM4InstructionsPerSecond = 128e6;
inline constexpr double kEstimatorShareOfSample = 0.25;
inline std::int64_t estimator_share_units(double dt_s) {
  return static_cast<std::int64_t>(kEstimatorShareOfSample * dt_s * kM4InstructionsPerSecond);
}
// What a call of the engine does beyond the units its meter charged, at most: the seam's conversions, the queue's
// bookkeeping, the publication of the samples it finishes (their estimates computed in float, widened to double)
// and the cost model's error (measured on the emulated M4: docs/BENCHMARKS.md, "The metered observer").
inline constexpr std::int32_t kObserverCallOverheadUnits = 4000;
// The work budget of a call with the observer on: the estimator's share less that overhead and less what the
// caller's call does around the engine's (caller_overhead_units: WallEngineConfig::caller_overhead_units, 0 on hosts),
// at least the least budget. The open loop keeps WallEngineConfig::work_budget_units (kDefaultWorkBudgetUnits:
// 25 000 at any rate).
// caller_units_per_sample (WallEngineConfig::caller_units_per_sample) is paid from the budget with the sample's end
// (its largest piece then, which the least budget must pay).
inline std::int32_t observer_work_budget_units(double dt_s, std::int32_t caller_overhead_units = 0,
                                               std::int32_t caller_units_per_sample = 0) {
  using Observer = WallObserver<FixedRockingStepper>;
  // A sub-step's observer part is paid at its worst (StepperAlarmChain::run_substep), so that is what must fit.
  std::int64_t least = kMinWorkBudgetUnits + Observer::kSubstepWorstUnits + Observer::kWork.sample_end;
  const std::int64_t sample_end = std::int64_t{FixedRockingStepper::kWork.evaluate} + Observer::kWork.sample_end +
                                  caller_units_per_sample;
  if (least < sample_end) least = sample_end;
  std::int64_t units = estimator_share_units(dt_s) - kObserverCallOverheadUnits - caller_overhead_units;
  if (units < least) units = least;
  if (units > 1000000000) units = 1000000000;
  return static_cast<std::int32_t>(units);
}

// What a wall engine is configured with (both engines).
struct WallEngineConfig {
  WallParameters wall{};
  double r_energy = 0.0;           // restitution energy ratio r in [0, 1] [-]
  double kappa = 2.0;              // collapse at κ·x_inst [-]
  ModelKind model = ModelKind::linear;  // the fixed-point engine: linear only; the double engine: either
  double dt_s = 0.005;             // sample interval [s]
  double max_step_s = kDefaultMaxStep_s;  // longest integration step: ceil(dt / max_step) sub-steps per sample [s]
  AlarmSettings alarm{};
  SensorAxes<double> axes = default_sensor_axes();
  // The wall observer (core/wall_observer.hpp) between the stepper and the alarm: off, the engine is the open-loop
  // model exactly as before (bit-identical outputs); on, push_sensor() feeds it and step_at() aligns the streams.
  bool observer_enabled = false;
  ObserverOptions observer{};
  // The work one step/step_at call of the fixed-point engine may do [work units = Cortex-M4 instructions]: the rest
  // waits for the next call (carry-over, core/work_meter.hpp). 0: every sample finishes in its own call. The
  // fixed-point engine is metered; with the observer on, its work is metered too and the call's budget is
  // observer_work_budget_units(dt_s) (the estimator's share of the sample) whenever this is not 0. The double
  // engine is never metered.
  std::int32_t work_budget_units = kDefaultWorkBudgetUnits;
  // What the budgeted engine does when its queue of waiting samples is full (core/work_meter.hpp): shed keeps every
  // call within the budget, finish keeps every answer.
  WorkOverflow work_overflow = WorkOverflow::shed;
  // What the caller's call does around the engine's, at most [work units], for a caller whose whole call must fit
  // the budget (the monitor image, firmware/embedded/m4_monitor/monitor_main.cpp, declares both; 0 on hosts, whose
  // calls are not budgeted: their outputs are unchanged):
  // - caller_overhead_units: once a call (a monitor: the network receive, the message's decoding, the sequence
  //   rules). With the observer it is taken off the estimator's share (observer_work_budget_units). The open loop's
  //   budget is work_budget_units as given, this not subtracted.
  // - caller_units_per_sample: once for every sample the call finishes (a monitor: encoding and sending its outputs).
  //   A metered call pays it from its budget with the sample's end, so that a call that catches up on waiting samples
  //   also pays for publishing each (a constant per call could not: it would have to assume the most samples).
  std::int32_t caller_overhead_units = 0;
  std::int32_t caller_units_per_sample = 0;
};

// The worst call of the fixed-point engine on paper (docs/FIXED_POINT.md, "The worst call on paper"): from the caps —
// n sub-steps per sample, kMaxSegmentsPerStep segments per sub-step, at most one sensor sample applied a sub-step
// (WallObserver::substep) and kQueueCapacity passed over in a sample — and the cost model (FixedRockingStepper::kWork,
// WallObserver::kWork), an upper bound on the instructions of one step()/step_at() call:
//   bound = overhead + max(budget, overrun)
// A call pays its pieces from a meter of `budget` units and starts no piece the meter cannot pay; at a full queue it
// first finishes the oldest sample without a meter (the overrun) and the queue gets the budget less the overrun's
// units (StepperAlarmChain::call). The overrun's work is one sample's, by the policy (Q = kQueueCapacity):
//   shed:   n·(substep + trial [+ observer substep + dropped]) + evaluate [+ Q·superseded + sample_end]   (no event
//           located, no sensor sample applied — one dropped a sub-step at the cost of its check: one trial a sub-step)
//   finish: n·(substep + S·(trial + locate) + locate [+ observer substep + update]) + evaluate
//           [+ Q·superseded + sample_end]                          (every event, the newest due sensor sample each)
// overhead: what a call does beyond its meter (the seam's conversions, the queue's bookkeeping, the cost model's
// error), measured. Without a budget (0) the engine is not metered: the bound is the finish overrun's, a whole
// sample. All in work units (Cortex-M4 instructions).
struct WorstCallBound {
  bool metered = false;            // a budget is in force (else every sample finishes in its own call)
  int substeps = 1;                // n
  int segments_per_substep = 0;    // S = FixedRockingStepper::kMaxSegmentsPerStep
  int updates_per_sample = 0;      // sensor samples applied at most in a sample: one a sub-step, n (0: observer off)
  std::int64_t budget_units = 0;   // the meter of a call
  std::int64_t overrun_units = 0;  // one sample without a meter, by the overflow policy
  std::int64_t overhead_units = 0;
  std::int64_t bound_units = 0;    // overhead + caller's overhead + max(budget, overrun)
  std::int64_t caller_overhead_units = 0;  // WallEngineConfig::caller_overhead_units (its per-sample units are paid
                                           // from the budget, and are in the overrun)
  std::int64_t share_units = 0;    // with the observer: the estimator's share of the sample (target), else 0
};
inline WorstCallBound worst_call_bound(const WallEngineConfig& c) {
  constexpr WorkCosts w = FixedRockingStepper::kWork;
  constexpr ObserverWorkCosts o = WallObserver<FixedRockingStepper>::kWork;
  WorstCallBound b;
  b.substeps = substeps_per_sample(c.dt_s, c.max_step_s);
  b.segments_per_substep = FixedRockingStepper::kMaxSegmentsPerStep;
  const std::int64_t n = b.substeps, segments = b.segments_per_substep;
  const bool observed = c.observer_enabled;
  b.updates_per_sample = observed ? int(n) : 0;
  b.budget_units = c.work_budget_units == 0 ? 0
                   : observed            ? observer_work_budget_units(c.dt_s, c.caller_overhead_units,
                                                                          c.caller_units_per_sample)
                                         : c.work_budget_units;
  b.metered = b.budget_units > 0;
  const bool shed = b.metered && c.work_overflow == WorkOverflow::shed;
  const std::int64_t per_substep = shed ? w.substep + w.trial : w.substep + segments * (w.trial + w.locate) + w.locate;
  const std::int64_t observer_per_substep = observed ? o.substep + (shed ? o.dropped : o.update) : 0;
  const std::int64_t passed_over = observed ? std::int64_t(WallObserver<FixedRockingStepper>::kQueueCapacity) : 0;
  b.overrun_units = n * (per_substep + observer_per_substep) + w.evaluate +
                    (observed ? o.sample_end + passed_over * o.superseded : 0) +
                    (b.metered ? c.caller_units_per_sample : 0);
  b.overhead_units = observed ? kObserverCallOverheadUnits : kDefaultCallOverheadUnits;
  b.caller_overhead_units = c.caller_overhead_units;
  b.bound_units = b.overhead_units + b.caller_overhead_units +
                  (b.budget_units > b.overrun_units ? b.budget_units : b.overrun_units);
  b.share_units = observed ? estimator_share_units(c.dt_s) : 0;
  return b;
}

// Why init() refused a configuration. Values are stable: append, never renumber.
enum class WallEngineError : std::uint8_t {
  ok = 0,
  wall_invalid = 1,
  restitution_out_of_range = 2,
  kappa_out_of_range = 3,
  alarm_settings_invalid = 4,
  sensor_axes_invalid = 5,
  fixed_point_setup = 6,         // see WallEngine::fixed_setup_error()
  indicator_constants = 7,       // x_inst or ω outside the indicator formats
  model_not_supported = 8,       // the fixed-point engine runs the linear model only
  observer_invalid = 9,          // the observer refused its options or the step (see observer_error())
  max_step_invalid = 10,         // max_step_s must be > 0 and give at most kMaxSubsteps sub-steps per sample
  work_budget_invalid = 11,      // work_budget_units 0 or in [kMinWorkBudgetUnits, 10⁹] (and ≥ evaluate + caller_units_per_sample); caller units in [0, 10⁹]
  work_overflow_invalid = 12,    // work_overflow must be a WorkOverflow value
};


// The checks every engine makes (wall, r, κ, alarm settings, sensor axes): ok or the first failure.
inline WallEngineError validate_wall_engine_config(const WallEngineConfig& c) {
  if (!validate_wall(c.wall).ok()) return WallEngineError::wall_invalid;
  if (!(c.r_energy >= 0.0 && c.r_energy <= 1.0)) return WallEngineError::restitution_out_of_range;
  if (!(c.kappa >= 1.0 && c.kappa < 100.0)) return WallEngineError::kappa_out_of_range;
  if (!alarm_settings_valid(c.alarm)) return WallEngineError::alarm_settings_invalid;
  if (!sensor_axes_valid(c.axes)) return WallEngineError::sensor_axes_invalid;
  if (substeps_per_sample(c.dt_s, c.max_step_s) == 0) {
    return WallEngineError::max_step_invalid;
  }
  if (c.work_budget_units != 0 && !(c.work_budget_units >= kMinWorkBudgetUnits && c.work_budget_units <= 1000000000)) {
    return WallEngineError::work_budget_invalid;
  }
  if (c.caller_overhead_units < 0 || c.caller_overhead_units > 1000000000 || c.caller_units_per_sample < 0 ||
      c.caller_units_per_sample > 1000000000) {
    return WallEngineError::work_budget_invalid;
  }
  if (c.work_budget_units != 0 &&
      c.work_budget_units < std::int64_t{FixedRockingStepper::kWork.evaluate} + c.caller_units_per_sample) {
    return WallEngineError::work_budget_invalid;  // the sample's end with its publication must fit one call
  }
  if (!work_overflow_valid(c.work_overflow)) return WallEngineError::work_overflow_invalid;
  if (c.observer_enabled && validate_observer_options(c.observer) != ObserverError::ok) {
    return WallEngineError::observer_invalid;
  }
  return WallEngineError::ok;
}

// The arithmetic an engine runs (published in monitor_status_t). Values are stable: append, never renumber.
enum class MonitorArithmetic : std::uint8_t {
  fixed_point = 0,       // WallEngine: bit-identical to `rockwatch simulate --arith fixed`; the firmware's engine
  double_precision = 1,  // sim::DoubleWallEngine: bit-identical to `rockwatch simulate --arith double`; hosts only
};

// What an engine gives after a sample, in the published units (double: the LCM messages carry doubles).
// With the observer on, x_m and xd_mps are the fused state (what the alarm saw) and `observer` says how it was made.
struct ObserverSample {
  bool enabled = false;           // the engine runs the observer (all fields below are 0 otherwise)
  std::uint32_t flags = 0;        // observer_flag bits of this sample (health and events)
  bool corrected = false;         // a measurement corrected the motion in this step
  double sigma_x_m = 0.0;         // standard deviation of x [m]
  double sigma_xd_mps = 0.0;      // standard deviation of ẋ [m/s]
  double r_estimate = 0.0;        // estimated restitution energy ratio [-]
  double sigma_r = 0.0;           // its standard deviation [-]
  double bias_m = 0.0;            // estimated zero offset of the displacement transducer [m]
  double innovation_x_m = 0.0;    // last displacement innovation [m]
  double innovation_a_mps2 = 0.0; // last acceleration innovation [m/s²]
  // The estimated capacity and stiffness (SPEC §9, side +1): x_inst, the alarm's x_inst (estimate − k_σ·σ), ω, c, k.
  double x_inst_estimate_m = 0.0, sigma_x_inst_m = 0.0, x_inst_alarm_m = 0.0;
  double omega_estimate_rps = 0.0, sigma_omega_rps = 0.0;
  double c_estimate_mps2 = 0.0, sigma_c_mps2 = 0.0;
  double k_estimate_ps2 = 0.0, sigma_k_ps2 = 0.0;
  // Each sensor's fusion status (innovation, its variance, test ratio, rejected, last fused): the displacement
  // transducer's [m] and the accelerometer's [m/s²].
  ObserverSensorStatus x_status{}, a_status{};
};

struct EngineSample {
  double x_m = 0.0, xd_mps = 0.0, energy_ratio = 0.0;
  double t_to_instability_s = -1.0;  // −1: no prediction
  bool side_positive = true, moving = false, input_invalid = false, saturated = false;
  AlarmUpdate alarm{};
  ObserverSample observer{};
  // Carry-over (core/work_meter.hpp): calls after its own that this sample was finished (0: in its own call),
  // whether the engine's full queue made it skip locating an event (its times are then those of a step end), and
  // whether it was finished beyond its call's budget (an overrun: the queue was full).
  std::uint16_t late_calls = 0;
  bool work_shed = false;
  bool work_overrun = false;
};

// The published observer block of an engine that runs `observer` (either arithmetic): its estimates in double and
// what it did in the last step. Both engines fill EngineSample::observer with it.
template <typename Observer>
ObserverSample observer_sample(const Observer& observer, const ObserverStepReport& last_step) {
  ObserverSample o;
  o.enabled = true;
  o.flags = last_step.flags;
  o.corrected = last_step.corrected;
  o.sigma_x_m = observer.sigma_x_m();
  o.sigma_xd_mps = observer.sigma_xd_mps();
  o.r_estimate = observer.r_estimate();
  o.sigma_r = observer.sigma_r();
  o.bias_m = observer.bias_m();
  // Each sensor's status carries its last innovation: taken from there, not converted twice (on the M4 a Q10.53 to
  // double is a soft-double conversion, ~150 instructions; issue 28's 1 kHz median is within 12 000).
  o.x_status = observer.x_status();
  o.a_status = observer.a_status();
  o.innovation_x_m = o.x_status.innovation;
  o.innovation_a_mps2 = o.a_status.innovation;
  // The fixed-point observer computes these in single precision (core/wall_observer.hpp: no soft double).
  o.x_inst_estimate_m = observer.x_inst_estimate_m();
  o.sigma_x_inst_m = observer.sigma_x_inst_m();
  o.x_inst_alarm_m = observer.x_inst_alarm_m(Side::positive);
  o.omega_estimate_rps = observer.omega_estimate_rps();
  o.c_estimate_mps2 = observer.c_estimate_mps2();
  o.sigma_c_mps2 = observer.sigma_c_mps2();
  o.k_estimate_ps2 = observer.k_estimate_ps2();
  o.sigma_k_ps2 = observer.sigma_k_ps2();
  o.sigma_omega_rps = observer.sigma_omega_rps();
  return o;
}

class SampleEngine {
 public:
  virtual MonitorArithmetic arithmetic() const = 0;
  // Validates and prepares (all floating-point set-up happens here). The engine is at rest afterwards; the observer
  // (config.observer_enabled) starts fresh: ê = √r of the configuration, b̂ = 0, counters zero.
  virtual WallEngineError init(const WallEngineConfig& config) = 0;
  // Inputs are wall-frame accelerations ü, v̈ [m/s²] as received. Bounded work, no allocation:
  // the wall at rest and the alarm QUIET, with this sample as the current input (no step); the observer keeps what
  // it learned (ê, b̂), its queue and counters (the same wall: a new run is a new init());
  virtual EngineSample start(double ug_mps2, double vg_mps2) = 0;
  // the state restarts from rest (state unknown) with this sample as the current input, the alarm keeps its level;
  virtual EngineSample restart(double ug_mps2, double vg_mps2) = 0;
  // one step to this sample.
  virtual EngineSample step(double ug_mps2, double vg_mps2) = 0;
  // One step to this sample, which ends at t_us on the sensor clock, step_us after the previous one [µs]: the
  // observer (when enabled) applies the queued sensor samples up to t_us after the stepper's step. Observer off: the
  // same as step(), bit for bit.
  virtual EngineSample step_at(double ug_mps2, double vg_mps2, std::int64_t t_us, std::int64_t step_us) = 0;
  // A wall-sensor sample for the observer: checked and queued until a step reaches its time. Returns the
  // observer_flag bits it raised (0 and ignored when the observer is off).
  virtual std::uint32_t push_sensor(const WallSensorSample& sample) = 0;
  // The observer's counters since init() (all zero when it is off).
  virtual const ObserverCounters& observer_counters() const = 0;
  // The samples the last start/restart/step/step_at call finished, oldest first: what the caller publishes. An
  // engine that finishes every sample in its own call finishes exactly that one (and the call returned it);
  // firmware::WallEngine with a work budget (carry-over, core/work_meter.hpp) may finish none (the sample waits for
  // the next call) or several (those that waited, then this one).
  virtual int finished_count() const = 0;
  virtual const EngineSample& finished_sample(int i) const = 0;
  // Samples given and not yet finished, and finishing them without a budget (some per call: finished_count()).
  virtual int pending_samples() const = 0;
  virtual void finish_pending() = 0;

 protected:
  SampleEngine() = default;
  SampleEngine(const SampleEngine&) = default;
  SampleEngine& operator=(const SampleEngine&) = default;
  ~SampleEngine() = default;
};

}  // namespace rockwatch::core
