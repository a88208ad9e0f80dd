// The work one call of an engine may still do, and what each piece of work costs: how the fixed-point engine bounds
// its worst call without changing its answers (docs/FIXED_POINT.md, "Bounded work per call: carry-over").
//
// A sample's work is a sequence of pieces — a sub-step's set-up, a Newmark trial to the step end, an event located by
// Newton (with the trial to the event), the indicators and the alarm at the sample's end — each of a bounded cost.
// The engine takes each piece from a WorkMeter before doing it; when the meter cannot pay for the next piece the work
// stops there and goes on at the next call from exactly that point (StepperAlarmChain's queue of samples): between two
// sub-steps, or inside the stepper's step between two of its pieces — never inside the observer's part of a sub-step,
// which is paid whole (at its worst, the unused part given back). The
// pieces and their order do not depend on where a call stops, so the results are bit-identical to doing all the work
// at once; what a stop costs is latency: the sample is finished (and its state and alarm published) at a later call.
//
// Core rules: header-only, no heap, no exceptions, no I/O.
#pragma once

#include <cstdint>

namespace rockwatch::core {

// The cost of each piece of work in work units. For the fixed-point engine one unit is one Cortex-M4 instruction,
// an upper bound measured on the emulated M4 (FixedRockingStepperTypes::kWork); the double engine, which runs on
// hosts only, costs nothing and is never metered.
struct WorkCosts {
  std::int32_t substep;   // a sub-step's set-up: the input interpolated, f and k at its end, the start test at rest
  std::int32_t trial;     // one Newmark trial over the rest of the step
  std::int32_t locate;    // one event located (Newton) and the state there
  std::int32_t evaluate;  // the indicators and the alarm at a sample's end
};

// What a budgeted engine does when its queue of samples (StepperAlarmChain::kMaxPendingSamples) is full — sustained
// chatter of a wall settling needs more work than the budget pays (docs/BENCHMARKS.md, "Bounded work per call").
// Values are stable: append, never renumber.
enum class WorkOverflow : std::uint8_t {
  // Events are no longer located (WorkMeter::shed): every call stays within its budget, but the shed samples' answers
  // are no longer those of the engine without a budget (flagged `work_shed`, counted).
  shed = 0,
  // The oldest sample is finished beyond the budget (an overrun, flagged and counted): the answers are always those
  // of the engine without a budget; such a call's work is bounded by the engine's worst sample (its event caps).
  finish = 1,
};
inline constexpr bool work_overflow_valid(WorkOverflow w) {
  return w == WorkOverflow::shed || w == WorkOverflow::finish;
}

// What a call may still spend. unlimited(): every piece is paid (hosts, tests, the double engine). shed: the queue of
// samples is full and the engine sheds (WorkOverflow::shed), so events are no longer located — a crossing of the hinge
// puts the wall at rest at the step end, an exceedance or a collapse is dated at the step end — which bounds a
// sample's work by its trials; flagged in the report (`work_shed`). The default study meets it while walls settle
// at r_ana (docs/BENCHMARKS.md).
struct WorkMeter {
  bool limited = false;
  bool shed = false;
  std::int32_t left_units = 0;

  static constexpr WorkMeter unlimited() { return WorkMeter{}; }
  static constexpr WorkMeter of(std::int32_t units) { return WorkMeter{true, false, units}; }
  // Pays every piece but counts it (an overrun's work: of() with more units than any sample needs).
  static constexpr std::int32_t kCountingUnits = 2000000000;
  static constexpr WorkMeter counting() { return of(kCountingUnits); }
  std::int32_t spent_of(std::int32_t units) const { return units - left_units; }

  // Pays for a piece of work, or returns false (nothing paid) when the call cannot afford it.
  bool take(std::int32_t units) {
    if (!limited) return true;
    if (units > left_units) return false;
    left_units -= units;
    return true;
  }
  // Gives back units taken for work that was not done (a reserve: StepperAlarmChain pays a sub-step's observer part at
  // its worst before the stepper's pieces, and gives back what it did not use).
  void refund(std::int32_t units) {
    if (limited) left_units += units;
  }
};

// What one call of a budgeted engine did (StepperAlarmChain::call).
struct WorkCallReport {
  bool overrun = false;            // it worked beyond the budget to make room in a full queue
  std::int32_t units_spent = 0;    // of the budget
  std::int32_t overrun_units = 0;  // beyond it: the overrun's work (cost model's units)
};

// What a budgeted engine's calls did, counted one way by the firmware's engine (firmware::WallEngine::work_counters)
// and by the studies that measure its publication (sim::AlarmSummary::Published).
struct WorkTally {
  std::uint32_t late_samples = 0;    // samples finished in a later call than their own
  std::uint32_t max_late_calls = 0;  // the most calls a sample waited
  std::uint32_t shed_samples = 0;    // samples whose events were not located (the queue was full)
  std::uint32_t overruns = 0;        // calls that worked beyond the budget to make room in a full queue
  std::int32_t max_call_units = 0;   // the most work one call did, an overrun's included [work units]

  // A finished sample: the calls after its own that finished it, and whether it was shed.
  void count_sample(std::uint32_t calls_waited, bool shed) {
    if (calls_waited > 0) ++late_samples;
    if (calls_waited > max_late_calls) max_late_calls = calls_waited;
    if (shed) ++shed_samples;
  }
  void count_call(const WorkCallReport& r) {
    if (r.overrun) ++overruns;
    const std::int32_t units = r.units_spent + r.overrun_units;
    if (units > max_call_units) max_call_units = units;
  }
};

// The meter of work done all at once (hosts, tests, the double engine, the steps of the observer): every piece is
// paid and nothing is shed, known at compile time, so the unmetered path — every analysis of a study — carries no
// meter checks (RockingSegments and StepperAlarmChain take either meter as a template parameter).
struct UnmeteredWork {
  static constexpr bool shed = false;
  static constexpr bool take(std::int32_t) { return true; }
  static constexpr void refund(std::int32_t) {}
};

}  // namespace rockwatch::core
