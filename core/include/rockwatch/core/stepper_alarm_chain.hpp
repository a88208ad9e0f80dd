// The one composition of the per-step chain: rocking stepper → instability indicators → alarm state machine,
// for either stepper (core::RockingStepper<double>, core::FixedRockingStepper). Used by the firmware's engine
// (firmware::WallEngine), the host's double engine (sim::DoubleWallEngine) and both paths of sim::analyse, so the
// order of the stages and what the alarm sees are written once.
//
// The stepper-specific parts (report, constants and indicator types, how the stepper and the constants are set up)
// come from AlarmChainTraits, specialised below for the two steppers. The output is written into a caller-owned
// AlarmChainOutput (the firmware engine extends it with its inputs): no copy per sample.
//
// Core rules: header-only, no heap, no exceptions, no I/O; init() is initialisation-time code (double), the rest
// has the stepper's bounds on work.
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/fixed_instability_indicators.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/instability_indicators.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall_observer.hpp"

// The queue of samples waiting for work (carry-over): 64 by default. A build may set another length to measure the
// trade-off between samples shed and samples late (docs/BENCHMARKS.md, "The overflow policy").
#ifndef ROCKWATCH_PENDING_SAMPLES
#define ROCKWATCH_PENDING_SAMPLES 64
#endif

namespace rockwatch::core {

template <typename Stepper>
struct AlarmChainTraits;

template <>
struct AlarmChainTraits<RockingStepper<double>> {
  using Input = double;
  using Constants = InstabilityConstants<double>;
  using Indicators = InstabilityIndicators<double>;
  static FixedSetupError init_stepper(RockingStepper<double>& s, const StepperSetup<double>& setup) {
    s.init(setup);
    return FixedSetupError::ok;
  }
  static bool make_constants(const StepperSetup<double>& setup, const AlarmSettings& a, Constants& out) {
    out = make_instability_constants(setup, a);
    return true;
  }
  using Fraction = double;
  // Sub-step j of n (1 ≤ j ≤ n) of the input linear from `from` to `to`: the expression sim::analyse has always
  // used on its integration grid, and `to` itself at j = n.
  static Input interpolate(Input from, Input to, int j, int n, const Fraction*) {
    return j == n ? to : from + (to - from) * double(j) / double(n);
  }
  static Fraction fraction(int j, int n) { return double(j) / double(n); }
  // A fraction f of sub-step j (1-based) of n as a fraction of the whole sample.
  static Fraction sample_fraction(Fraction f, int j, int n, const Fraction*) { return (double(j - 1) + f) / double(n); }
  // The constants of the estimated wall (the observer's): x_inst, λ_w·x_inst and energy_min_x·x_inst times q, ω²
  // times kk (so the barrier c²/2k and ρ follow), from the nominal ones.
  static void scale_constants(Constants& c, const Constants& n, double q, double kk) {
    const double w = std::sqrt(kk);
    for (int i = 0; i < 2; ++i) {
      c.x_inst_m[i] = q * n.x_inst_m[i];
      c.x_warning_m[i] = q * n.x_warning_m[i];
      c.x_energy_min_m[i] = q * n.x_energy_min_m[i];
      c.omega2_rps2[i] = kk * n.omega2_rps2[i];
      c.omega_rps[i] = w * n.omega_rps[i];
      c.inv_omega2_x_inst2_s2pm2[i] = n.inv_omega2_x_inst2_s2pm2[i] / (kk * q * q);
    }
  }
};

template <>
struct AlarmChainTraits<FixedRockingStepper> {
  using Input = AccelQ7_56;
  using Constants = FixedInstabilityConstants;
  using Indicators = FixedInstabilityIndicators;
  static FixedSetupError init_stepper(FixedRockingStepper& s, const StepperSetup<double>& setup) {
    return s.init(setup);
  }
  static bool make_constants(const StepperSetup<double>& setup, const AlarmSettings& a, Constants& out) {
    return make_fixed_instability_constants(setup, a, out);
  }
  using Fraction = FractionQ1_62;
  // (1 − θ_j)·from + θ_j·to with θ_j = j/n (theta: the chain's table θ_0..θ_n), `to` itself at j = n.
  // Scaling and overflow: a convex combination of two Q7.56 inputs stays within their range (no difference is
  // formed, so inputs of opposite sign near ±128 m/s² cannot overflow); one rounding per product.
  static Input interpolate(Input from, Input to, int j, int n, const Fraction* theta) {
    if (j == n) return to;
    return wide_mul<AccelQ7_56>(FractionQ1_62(1) - theta[j], from) + wide_mul<AccelQ7_56>(theta[j], to);
  }
  // j/n in Q1.62, rounded (initialisation time).
  static Fraction fraction(int j, int n) { return FractionQ1_62::from_raw(fixed64_detail::div_round(j, n, 62)); }
  // A fraction f of sub-step j (1-based) of n as a fraction of the whole sample: θ_{j−1} + f·θ_1.
  // Scaling and overflow: the sum is at most 1 (+ rounding); one rounding (the product); exact for n = 1.
  static Fraction sample_fraction(Fraction f, int j, int n, const Fraction* theta) {
    if (n == 1) return f;
    return theta[j - 1] + wide_mul<FractionQ1_62>(f, theta[1]);
  }
  // As the double chain's, in the indicators' 32-bit formats. Once per observed sample: the root and the three
  // reciprocals in single precision on the M4F's FPU (24-bit mantissas: within a unit in the last place of the
  // Q7.24 ratios, for a few dozen instructions instead of soft double's ~3 000), then six 32-bit products per side.
  static void scale_constants(Constants& c, const Constants& n, double q, double kk) {
    const float qf = static_cast<float>(q), w = std::sqrt(static_cast<float>(kk));
    const RatioQ7_24 fq(q), inv_q(static_cast<double>(1.0f / qf)), inv_w(static_cast<double>(1.0f / w)),
        inv_qw(static_cast<double>(1.0f / (qf * w)));
    for (int i = 0; i < 2; ++i) {
      c.x_inst_m[i] = fixed_mul<LengthQ1_30>(fq, n.x_inst_m[i]);
      c.x_warning_m[i] = fixed_mul<LengthQ1_30>(fq, n.x_warning_m[i]);
      c.x_energy_min_m[i] = fixed_mul<LengthQ1_30>(fq, n.x_energy_min_m[i]);
      c.inv_x_inst_pm[i] = fixed_mul<RateQ7_24>(inv_q, n.inv_x_inst_pm[i]);
      c.inv_omega_x_inst_spm[i] = fixed_mul<RateQ7_24>(inv_qw, n.inv_omega_x_inst_spm[i]);
      c.inv_omega_s[i] = fixed_mul<RateQ7_24>(inv_w, n.inv_omega_s[i]);
    }
  }
};

template <typename Stepper>
struct AlarmChainOutput {
  typename Stepper::Report step{};                                // what the stepper did inside the step
  typename AlarmChainTraits<Stepper>::Indicators indicators{};    // conditions, predicted time, energy ratio
  AlarmUpdate alarm{};                                            // level after the step, reasons, transition flag
};

// Integration sub-steps per input sample: the step is at most max_step_s, so ceil(dt / max_step) sub-steps of
// dt / n each (1 when the samples are already that close). The one rule every engine and tool uses and checks
// (sim::analyse, the monitor's engines and configuration, simulate, study): 0 when the arguments are not positive and
// finite or the sample would need more than kMaxSubsteps sub-steps.
inline constexpr int kMaxSubsteps = 64;
// The default longest integration step [s]: 1 ms, five sub-steps per sample at 200 Hz. Chosen so that over the
// default study the survivors' max|x| is within 0.5 % (median) of the converged answer (docs/BENCHMARKS.md, "Sub-steps");
// the paper's 5 ms (one step per 200 Hz sample) stays available as an option.
inline constexpr double kDefaultMaxStep_s = 0.001;
inline int substeps_per_sample(double sample_dt_s, double max_step_s) {
  if (!(sample_dt_s > 0.0 && max_step_s > 0.0 && sample_dt_s < 1e6 && max_step_s < 1e6)) return 0;
  const double ratio = sample_dt_s / max_step_s - 1e-9;  // a ratio a rounding above a whole number is that number
  if (ratio > double(kMaxSubsteps)) return 0;
  const int whole = static_cast<int>(ratio);
  return whole < 1 ? 1 : (double(whole) < ratio ? whole + 1 : whole);
}

// Why init() refused. Values are stable: append, never renumber.
enum class AlarmChainError : std::uint8_t {
  ok = 0,
  stepper_setup = 1,        // the fixed-point stepper refused the setup (setup_error() says why)
  indicator_constants = 2,  // x_inst or ω outside the fixed-point indicator formats
  substeps_out_of_range = 3,  // sub-steps per sample must be in [1, kMaxSubsteps]
};

// Per input sample: n sub-steps of the stepper (input linear from the previous sample to this one, so sub-steps add
// no latency), then the indicators and the alarm once, on the state at the sample's end. The report of the sample
// (out.step) merges the sub-steps' reports: flags or-ed, counts summed, the first start, impact, exceedance and
// the collapse with their fractions of the whole sample. With n = 1 the chain is exactly one stepper step per sample.
template <typename Stepper>
class StepperAlarmChain {
 public:
  using Traits = AlarmChainTraits<Stepper>;
  using Input = typename Traits::Input;
  using Report = typename Stepper::Report;
  using Fraction = typename Traits::Fraction;
  using Output = AlarmChainOutput<Stepper>;

  // Initialisation time. setup.dt_s is the sub-step: the sample interval / substeps. The alarm holds a level for
  // hold_samples(alarm, sample_dt_s) samples.
  AlarmChainError init(const StepperSetup<double>& setup, const AlarmSettings& alarm, double sample_dt_s,
                       int substeps = 1) {
    if (substeps < 1 || substeps > kMaxSubsteps) return AlarmChainError::substeps_out_of_range;
    substeps_ = substeps;
    for (int j = 0; j <= substeps; ++j) theta_[j] = Traits::fraction(j, substeps);
    setup_error_ = Traits::init_stepper(stepper_, setup);
    if (setup_error_ != FixedSetupError::ok) return AlarmChainError::stepper_setup;
    if (!Traits::make_constants(setup, alarm, constants_)) return AlarmChainError::indicator_constants;
    nominal_constants_ = constants_;
    alarm_.init(hold_samples(alarm, sample_dt_s));
    return AlarmChainError::ok;
  }

  // Wall at rest with this input as the current one, alarm QUIET.
  void reset(Input ug_mps2, Input vg_mps2) {
    stepper_.reset(ug_mps2, vg_mps2);
    ug_last_ = ug_mps2;
    vg_last_ = vg_mps2;
    alarm_.reset();
  }

  // A release test (snap-back): the wall held at displacement x and released with velocity ẋ under this input as
  // the current one; alarm QUIET. Length/Speed are the stepper's formats (double, or LengthQ1_62 and SpeedQ3_60).
  template <typename Length, typename Speed>
  void reset_released(Length x_m, Speed xd_mps, Input ug_mps2, Input vg_mps2) {
    reset(ug_mps2, vg_mps2);
    stepper_.set_state(x_m, xd_mps, ug_mps2, vg_mps2);
  }

  // The stepper through one sample to this input (callers that do not need the indicators this sample).
  // on_substep(j, report, ug, vg) runs after each sub-step j = 1..n with that sub-step's report and input.
  // All at once: the queue of run() must be empty.
  template <typename OnSubstep>
  void step_motion(Input ug_mps2, Input vg_mps2, Output& out, OnSubstep&& on_substep) {
    UnmeteredWork meter;
    out.step = Report{};
    run_motion(ug_mps2, vg_mps2, 0, 0, out.step, meter, on_substep, static_cast<NoObserver*>(nullptr));
    substeps_done_ = 0;
    ug_last_ = ug_mps2;
    vg_last_ = vg_mps2;
  }
  void step_motion(Input ug_mps2, Input vg_mps2, Output& out) {
    step_motion(ug_mps2, vg_mps2, out, [](int, const Report&, Input, Input) {});
  }

  // The indicators of the stepper's state and out.step, then the alarm.
  void evaluate(Output& out) {
    out.indicators = evaluate_instability(constants_, stepper_, out.step);
    out.alarm = alarm_.update(out.indicators.conditions);
  }

  // One sample: stepper (n sub-steps) → indicators → alarm.
  void step(Input ug_mps2, Input vg_mps2, Output& out) {
    step_motion(ug_mps2, vg_mps2, out);
    evaluate(out);
  }

  // One sample with a state observer between the stepper and the indicators (core/wall_observer.hpp): after every
  // sub-step the observer corrects the stepper's state with the newest sensor sample due by the sub-step's end
  // (WallObserver::substep: one a sub-step), so the indicators and the alarm see the fused state. t_us: the
  // sample's end on the sensor clock; step_us: the sample interval [µs]; sub-step j ends at t_us − step_us·(n − j)/n
  // (integer µs). Returns the observer's report of the sample: flags or-ed, updates summed, corrected if any sub-step
  // was.
  template <typename Observer, typename OnSubstep>
  typename Observer::StepOutcome step_observed(Input ug_mps2, Input vg_mps2, Observer& observer, std::int64_t t_us,
                                               std::int64_t step_us, Output& out, OnSubstep&& on_substep) {
    UnmeteredWork meter;
    obs_total_ = ObserverStepReport{};
    out.step = Report{};
    run_motion(ug_mps2, vg_mps2, t_us, step_us, out.step, meter, on_substep, &observer);
    substeps_done_ = 0;
    ug_last_ = ug_mps2;
    vg_last_ = vg_mps2;
    end_observed(observer);
    evaluate(out);
    return obs_total_;
  }
  template <typename Observer>
  typename Observer::StepOutcome step_observed(Input ug_mps2, Input vg_mps2, Observer& observer, std::int64_t t_us,
                                               std::int64_t step_us, Output& out) {
    return step_observed(ug_mps2, vg_mps2, observer, t_us, step_us, out, [](int, const Report&, Input, Input) {});
  }

  // The state restarts from rest (state unknown after a long gap or a publisher restart) with this input as the
  // current one; the alarm keeps its level (a latched COLLAPSED stays, others fall only through the hold time).
  void restart_motion(Input ug_mps2, Input vg_mps2, Output& out) {
    stepper_.reset(ug_mps2, vg_mps2);
    ug_last_ = ug_mps2;
    vg_last_ = vg_mps2;
    out.step = Report{};
    evaluate(out);
  }

  // Carry-over (core/work_meter.hpp): samples queued with submit() and worked by run() in pieces paid from a meter,
  // in order; a sample whose work the meter cannot pay goes on at the next run() from where it stopped — between two
  // sub-steps, or inside the stepper's step (its own pieces, core/rocking_segments.hpp), never inside the observer's
  // part of a sub-step (run_substep). The results are those of step() on the same samples, bit for bit, unless the
  // meter sheds.
  static constexpr int kMaxPendingSamples = ROCKWATCH_PENDING_SAMPLES;
  // The most samples one call of a budgeted engine finishes (call()'s callers: firmware::WallEngine, sim).
  static constexpr int kMaxFinishedPerCall = 8;

  // Queues a sample (restart: the motion restarts from rest with this input, as restart_motion()). False, nothing
  // queued, when kMaxPendingSamples wait.
  // tag: the caller's, handed back with the finished sample.
  // t_us, step_us: the sample's end on the sensor clock and its interval (the observer's, submit_observed()).
  bool submit(Input ug_mps2, Input vg_mps2, bool restart = false, std::uint32_t tag = 0, std::int64_t t_us = 0,
              std::int64_t step_us = 0) {
    if (pending_count_ == kMaxPendingSamples) return false;
    queue_[(pending_head_ + pending_count_) % kMaxPendingSamples] =
        PendingSample{ug_mps2, vg_mps2, restart, tag, t_us, step_us};
    ++pending_count_;
    return true;
  }
  // Samples queued and not yet finished (the one in progress included).
  int pending() const { return pending_count_; }
  // The sub-steps of the sample in progress already finished, the observer's part included (0 between samples);
  // stepper().step_in_progress() says whether a call stopped inside the next one's stepper step.
  int substeps_done() const { return substeps_done_; }
  // What the caller does for each finished sample (publishing it: WallEngineConfig::caller_units_per_sample) [work
  // units]: taken from the meter with the sample's end, so that a metered call pays for it too. 0: nothing taken.
  void set_caller_units_per_sample(std::int32_t units) { caller_units_per_sample_ = units; }
  // Forgets the queued samples (before a reset: the wall at rest, the queue empty; the stepper's reset abandons a step
  // stopped inside).
  void clear_pending() {
    pending_count_ = 0;
    substeps_done_ = 0;
  }

  // Works on the queue until it is empty, max_samples are finished or the meter cannot pay for the next piece:
  // on_substep as step_motion()'s, on_sample(const Output&, tag) after each finished sample (its merged report,
  // indicators and alarm; the stepper then stands at its end).
  template <typename Meter, typename OnSubstep, typename OnSample>
  void run(Meter& meter, int max_samples, OnSubstep&& on_substep, OnSample&& on_sample) {
    run_with(meter, max_samples, on_substep, on_sample, static_cast<NoObserver*>(nullptr));
  }
  // The same with the wall observer between the stepper and the indicators (queued with submit(…, t_us, step_us), as
  // step_observed() does it all at once): its work (WallObserver::substep after each sub-step, bounded; end_sample
  // with the sample's end) paid from the same meter, in the same order, so a sample finished at a later call is
  // bit-identical to step_observed(). The observer's report of the finished sample: observer_report().
  template <typename Meter, typename Observer, typename OnSample>
  void run_observed(Meter& meter, Observer& observer, int max_samples, OnSample&& on_sample) {
    const auto no_substep = [](int, const Report&, Input, Input) {};
    run_with(meter, max_samples, no_substep, on_sample, &observer);
  }
  // The observer's report of the last sample finished by run_observed() (zero after a restart).
  const ObserverStepReport& observer_report() const { return obs_total_; }

  // One call of a budgeted engine (the policy of firmware::WallEngine's step(), and of the studies that measure its
  // latency): this sample queued, then the queue worked with a meter of budget_units, finishing at most max_samples
  // (on_sample as run()'s). At a full queue (WorkOverflow): shed — the call's meter sheds, and a sample arriving at a
  // queue still full (a sample's trials alone exceed the budget) first finishes the oldest without a budget, shedding
  // (an overrun); finish — a sample arriving at a full queue first finishes the oldest without a budget and without
  // shedding (an overrun), so nothing is ever shed. An overrun's sample is the call's first on_sample.
  //
  // The overrun's work is the call's first: the budget left for the queue is the budget less the overrun's units (at
  // least 0), so that a call does at most max(budget, the overrun's work) units (docs/FIXED_POINT.md, "The worst call
  // on paper").
  using CallReport = WorkCallReport;
  template <typename OnSample>
  CallReport call(Input ug_mps2, Input vg_mps2, bool restart, std::int32_t budget_units, WorkOverflow overflow,
                  std::uint32_t tag, int max_samples, OnSample&& on_sample) {
    return call_with(ug_mps2, vg_mps2, restart, 0, 0, budget_units, overflow, tag, max_samples, on_sample,
                     static_cast<NoObserver*>(nullptr));
  }
  // The same with the wall observer (t_us, step_us as step_observed()'s; on_sample may read observer_report()).
  template <typename Observer, typename OnSample>
  CallReport call_observed(Input ug_mps2, Input vg_mps2, std::int64_t t_us, std::int64_t step_us, bool restart,
                           std::int32_t budget_units, WorkOverflow overflow, std::uint32_t tag, int max_samples,
                           Observer& observer, OnSample&& on_sample) {
    return call_with(ug_mps2, vg_mps2, restart, t_us, step_us, budget_units, overflow, tag, max_samples, on_sample,
                     &observer);
  }

  const Stepper& stepper() const { return stepper_; }
  FixedSetupError setup_error() const { return setup_error_; }
  int substeps() const { return substeps_; }

 private:
  struct PendingSample {
    Input ug_mps2, vg_mps2;
    bool restart;
    std::uint32_t tag;
    std::int64_t t_us, step_us;  // with the observer: the sample's end on the sensor clock, its interval [µs]
  };

  // The open loop's stand-in for an observer (run(), call()): no observer code is instantiated.
  struct NoObserver {
    static constexpr ObserverWorkCosts kWork{0, 0, 0, 0, 0};
    static constexpr std::int32_t kSubstepWorstUnits = 0;
  };
  template <typename Observer>
  static constexpr bool kObserved = !std::is_same_v<Observer, NoObserver>;

  template <typename Meter, typename OnSubstep, typename OnSample, typename Observer>
  void run_with(Meter& meter, int max_samples, OnSubstep& on_substep, OnSample& on_sample, Observer* observer) {
    for (int finished = 0; pending_count_ > 0 && finished < max_samples; ++finished) {
      const PendingSample& p = queue_[pending_head_];
      if (p.restart) {
        if (!meter.take(Stepper::kWork.evaluate + caller_units_per_sample_)) return;
        restart_motion(p.ug_mps2, p.vg_mps2, head_out_);
        if constexpr (kObserved<Observer>) {
          observer->restart_motion();
          obs_total_ = ObserverStepReport{};
        }
      } else {
        // Nothing of the sample done yet (or an earlier call stopped before its first sub-step): its reports start
        // empty. Idempotent, so no flag says whether the sample has begun.
        if (substeps_done_ == 0 && !stepper_.step_in_progress()) {
          head_out_.step = Report{};
          obs_total_ = ObserverStepReport{};
        }
        if (!run_motion(p.ug_mps2, p.vg_mps2, p.t_us, p.step_us, head_out_.step, meter, on_substep, observer)) return;
        // The sample's end (the observer's, when on, and the indicators and the alarm): one piece.
        if (!meter.take(Stepper::kWork.evaluate + Observer::kWork.sample_end + caller_units_per_sample_)) return;
        ug_last_ = p.ug_mps2;
        vg_last_ = p.vg_mps2;
        if constexpr (kObserved<Observer>) end_observed(*observer);
        evaluate(head_out_);
      }
      const std::uint32_t tag = p.tag;
      substeps_done_ = 0;
      pending_head_ = (pending_head_ + 1) % kMaxPendingSamples;
      --pending_count_;
      on_sample(static_cast<const Output&>(head_out_), tag);
    }
  }

  template <typename OnSample, typename Observer>
  CallReport call_with(Input ug_mps2, Input vg_mps2, bool restart, std::int64_t t_us, std::int64_t step_us,
                       std::int32_t budget_units, WorkOverflow overflow, std::uint32_t tag, int max_samples,
                       OnSample& on_sample, Observer* observer) {
    const auto no_substep = [](int, const Report&, Input, Input) {};
    CallReport report;
    if (pending_count_ == kMaxPendingSamples) {
      WorkMeter room = WorkMeter::counting();
      room.shed = overflow == WorkOverflow::shed;
      run_with(room, 1, no_substep, on_sample, observer);
      report.overrun = true;
      report.overrun_units = room.spent_of(WorkMeter::kCountingUnits);
    }
    submit(ug_mps2, vg_mps2, restart, tag, t_us, step_us);
    const std::int32_t left = budget_units > report.overrun_units ? budget_units - report.overrun_units : 0;
    WorkMeter meter = WorkMeter::of(left);
    meter.shed = overflow == WorkOverflow::shed && pending_count_ == kMaxPendingSamples;
    run_with(meter, max_samples, no_substep, on_sample, observer);
    report.units_spent = meter.spent_of(left);
    return report;
  }

  // The sample's end with the observer: the covariance brought up to date; the alarm judges the estimated wall (its
  // capacity less the observer's margin, ObserverOptions::alarm_capacity_sigmas), not the nominal one. Open loop
  // (step, step_motion, run) keeps the nominal constants.
  template <typename Observer>
  void end_observed(Observer& observer) {
    observer.end_sample();
    double q = 1.0, kk = 1.0;
    if (observer.alarm_scales(q, kk)) Traits::scale_constants(constants_, nominal_constants_, q, kk);
  }

  // The motion of a sample (t_us, step_us: its end and interval on the sensor clock, with the observer): its
  // sub-steps from substeps_done_ on; false when the meter stopped it (the next call goes on from there). One step per
  // sample runs even on a collapsed wall (its report says whether the input was valid).
  template <typename Meter, typename OnSubstep, typename Observer>
  bool run_motion(Input ug_mps2, Input vg_mps2, std::int64_t t_us, std::int64_t step_us, Report& total, Meter& meter,
                  OnSubstep& on_substep, Observer* observer) {
    while (stepper_.step_in_progress() ||
           (substeps_done_ < substeps_ && !(substeps_ > 1 && stepper_.collapsed()))) {
      if (!run_substep(ug_mps2, vg_mps2, t_us, step_us, total, meter, on_substep, observer)) return false;
    }
    return true;
  }

  // Sub-step j = substeps_done_ + 1: the stepper's step to the sub-step's input, then the observer's part.
  // The stepper's step is its own pieces (set-up, trials, located events): a sub-step of chatter locates up to
  // 3 events, ≈ 45 000 units, more than a 1 kHz call's whole budget (23 000 open loop, 28 000 with the observer), so
  // a call may stop between them and the stepper goes on from there (step_in_progress). The observer's part is
  // bounded (WallObserver::substep: one sensor sample at most) and is paid at its worst before the stepper's pieces,
  // so a step that finishes is followed by the observer's part in the same call; the reserve is given back when the
  // stepper stops, and what the observer did not use once it ran. So a call stops only before a sub-step or inside
  // the stepper's step, and the chain needs no record of where inside a sub-step it stood.
  template <typename Meter, typename OnSubstep, typename Observer>
  bool run_substep(Input ug_mps2, Input vg_mps2, std::int64_t t_us, std::int64_t step_us, Report& total,
                   Meter& meter, OnSubstep& on_substep, Observer* observer) {
    const int j = substeps_done_ + 1;
    const bool resume = stepper_.step_in_progress();
    const std::int32_t reserve = Observer::kSubstepWorstUnits;
    if (!meter.take((resume ? 0 : Stepper::kWork.substep) + reserve)) return false;
    if (!resume) {
      sub_ug_ = Traits::interpolate(ug_last_, ug_mps2, j, substeps_, theta_);
      sub_vg_ = Traits::interpolate(vg_last_, vg_mps2, j, substeps_, theta_);
      stepper_.begin_step(sub_ug_, sub_vg_);
    }
    if (!stepper_.continue_step(meter)) {
      meter.refund(reserve);
      return false;
    }
    const Report& sub = stepper_.step_report();
    if constexpr (kObserved<Observer>) {
      // Sub-step j ends at t_us − step_us·(n − j)/n (integer µs).
      const std::int64_t n = substeps_;
      const std::int64_t end_us = t_us - (step_us * (n - j)) / n;
      std::int32_t used = 0;
      const ObserverStepReport o =
          observer->substep(stepper_, sub, sub_ug_, sub_vg_, end_us, step_us / n, meter.shed, &used);
      meter.refund(reserve - used);
      obs_total_.flags |= o.flags;
      obs_total_.x_updates += o.x_updates;
      obs_total_.a_updates += o.a_updates;
      obs_total_.corrected = obs_total_.corrected || o.corrected;
    }
    on_substep(j, sub, sub_ug_, sub_vg_);
    merge(total, sub, j);
    ++substeps_done_;
    return true;
  }

  // Sub-step j's report into the sample's.
  void merge(Report& total, const Report& sub, int j) const {
    total.input_invalid = total.input_invalid || sub.input_invalid;
    if (sub.started && !total.started) {
      total.started = true;
      total.start_fraction = Traits::sample_fraction(sub.start_fraction, j, substeps_, theta_);
    }
    if (sub.impacts_total > 0 && total.impacts_total == 0) {
      total.first_impact_fraction = Traits::sample_fraction(sub.first_impact_fraction, j, substeps_, theta_);
      total.first_impact_v_before_mps = sub.first_impact_v_before_mps;
      total.first_impact_v_after_mps = sub.first_impact_v_after_mps;
    }
    total.impacts_counted = static_cast<std::uint16_t>(total.impacts_counted + sub.impacts_counted);
    total.impacts_total = static_cast<std::uint16_t>(total.impacts_total + sub.impacts_total);
    total.came_to_rest = total.came_to_rest || sub.came_to_rest;
    if (sub.exceeded && !total.exceeded) {
      total.exceeded = true;
      total.exceed_fraction = Traits::sample_fraction(sub.exceed_fraction, j, substeps_, theta_);
    }
    if (sub.collapsed) {
      total.collapsed = true;
      total.collapse_fraction = Traits::sample_fraction(sub.collapse_fraction, j, substeps_, theta_);
    }
    total.rest_forced = total.rest_forced || sub.rest_forced;
    total.saturated = total.saturated || sub.saturated;
    total.work_shed = total.work_shed || sub.work_shed;
    total.segments = static_cast<std::uint16_t>(total.segments + sub.segments);
    total.events_located = static_cast<std::uint16_t>(total.events_located + sub.events_located);
    total.locate_iterations = static_cast<std::uint16_t>(total.locate_iterations + sub.locate_iterations);
  }

  Stepper stepper_{};
  typename Traits::Constants constants_{};
  typename Traits::Constants nominal_constants_{};  // as made by init() (the observer's estimate scales from them)
  InstabilityAlarm alarm_{};
  FixedSetupError setup_error_ = FixedSetupError::ok;
  int substeps_ = 1;
  Fraction theta_[kMaxSubsteps + 1]{};  // θ_j = j / substeps_
  Input ug_last_{}, vg_last_{};          // the previous sample's input: where the sub-steps' ramp starts
  // The sample in progress (run_motion): its sub-steps finished, the input of the last one begun (the stepper knows
  // whether its step stopped inside: step_in_progress), and the observer's report of the sample so far.
  int substeps_done_ = 0;
  Input sub_ug_{}, sub_vg_{};
  ObserverStepReport obs_total_{};
  // The queue of run(): a ring of kMaxPendingSamples, the head in progress.
  PendingSample queue_[kMaxPendingSamples]{};
  int pending_head_ = 0;
  int pending_count_ = 0;
  Output head_out_{};
  std::int32_t caller_units_per_sample_ = 0;
};

}  // namespace rockwatch::core
