// The one segment logic of the two-block rocking stepper (SPEC §3–4), for every arithmetic: a step is a sequence of
// segments on one side, each integrated to the step end and cut at the first event inside it —
//   on the hinge moving inwards, or x crossing 0 → an impact: ẋ⁺ = √r·ẋ⁻ into the other side, or rest when
//     |ẋ⁺| < v_rest and the ground does not drive the wall out towards the new side (SPEC §3);
//   |x| rising through x_inst → the exceedance is located (the segment goes on);
//   |x| reaching κ·x_inst → collapse, located; the stepper stops;
// and at rest, the start of motion where the ground's drive s·p6 crosses zero (input linear in the step, so the
// crossing is exact). The chatter rule (SPEC §3, one rule for every arithmetic): within one step (one integration
// sub-step) at most kMaxImpactsPerSubstep impacts are located; a further crossing of the hinge in that step is not
// located — the wall is put at rest on the hinge at the step's end (`rest_forced`: bounces that close together are a
// wall settling), and from there the start rule decides at the next step (it rocks again at once if the ground
// drives it out). The rule depends on the step only, never on the input's sample rate.
//
// The arithmetic is the derived stepper's (CRTP, the Kernel below): RockingStepper<Scalar> (double: Newmark through
// the model's coefficients, events by Illinois regula falsi to convergence) and FixedRockingStepper (64-bit fixed
// point: the equation divided by p1, events by a fixed number of Newton steps on the exact Newmark residual). What
// a kernel provides, all const:
//   Segment begin_segment(Fraction θ)              the current state at θ, and what the kernel needs to integrate
//                                                  from it to the step end on the current side
//   State end_of(const Segment&)                   the state at the step end
//   Located locate(const Segment&, const State& end, Length level, Report&)
//                                                  where s·x reaches `level` in the segment (located.theta: the
//                                                  fraction of the step), counting its work in the report
//   State state_at(const Segment&, const Located&) the state there
//   Accel drive(Side s, Fraction θ), drive_at_end(Side s)
//                                                  the ground's drive towards s at x = 0 (s·p6, or s·p6/p1)
//   Fraction start_crossing(Fraction θ, Accel now, Accel end)
//                                                  where the drive, affine in θ, crosses 0 between θ and 1
//   Accel accel_at_hinge(Side s, Fraction θ)       ẍ at x = 0 on side s
//   Speed rebound(Speed v)                         √r·v
// and its setup (x_inst_m, x_collapse_m, v_rest_mps, v_count_mps per the stepper's formats); and, public, the step in
// pieces: begin_step(ug, vg) (the input at the step end; resets report_ and calls begin_segments()) and
// continue_step(meter) (run_segments() until done, then the step's end), which step(ug, vg) runs at once.
//
// Core rules: header-only, no heap, no exceptions, no I/O; the loops are bounded by kMaxSegmentsPerStep.
#pragma once

#include <cstdint>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/newmark.hpp"
#include "rockwatch/core/work_meter.hpp"

namespace rockwatch::core {

// What happened inside one step, in the stepper's formats (Fraction: of the step, in [0, 1]; Speed: m/s).
template <typename Fraction, typename Speed = Fraction>
struct StepReport {
  // Members widest first (no padding between them): a report is zeroed and copied out at every step.
  Fraction start_fraction{};          // rocking started from rest at this fraction of the step (when `started`)
  Fraction first_impact_fraction{};   // the first impact of the step: when,
  Speed first_impact_v_before_mps{};  //   ẋ⁻ [m/s]
  Speed first_impact_v_after_mps{};   //   and ẋ⁺ = √r·ẋ⁻ [m/s], also when the impact puts the wall at rest
  Fraction exceed_fraction{};         // when |x| rose through x_inst (when `exceeded`)
  Fraction collapse_fraction{};       // when |x| reached κ·x_inst (when `collapsed`)
  std::uint16_t impacts_counted = 0;  // impacts with |ẋ⁻| ≥ v_count
  std::uint16_t impacts_total = 0;    // all impacts
  // Work done, for the constant-iteration proofs and worst-case accounting (tests/sim/test_fixed_engine.cpp):
  std::uint16_t segments = 0;           // segments integrated to the step end (≤ kMaxSegmentsPerStep)
  std::uint16_t events_located = 0;     // impacts, collapse and x_inst passages located inside the step
  std::uint16_t locate_iterations = 0;  // iterations of the event locator
  bool input_invalid = false;     // G = g + v̈ ≤ 0 at the step end: outside the model, state held
  bool started = false;           // rocking started from rest in this step
  bool came_to_rest = false;
  bool rest_forced = false;       // the chatter rule (a crossing beyond the step's K located impacts), or a shed
                                  // crossing: put at rest at the step end (settling)
  bool exceeded = false;          // |x| rose through x_inst in this step (first time in the step)
  bool collapsed = false;         // |x| reached κ·x_inst; the stepper stops
  bool saturated = false;         // fixed point: a state quantity reached the end of its format (results unreliable)
  bool work_shed = false;         // the engine's queue was full: an event was not located (core/work_meter.hpp)
};

// The chatter rule's K (SPEC §3): impacts located inside one integration step, in every engine. Chosen by measurement,
// K = 2 the knee between the double engine's answer moved and the worst M4 sample (K = 1, 2, 4, 8 against the engine
// before the rule). Measured: docs/BENCHMARKS.md, "The chatter rule".
// The macro is there only to repeat that measurement (a build with -DROCKWATCH_CHATTER_IMPACTS=N); the tools and the
// firmware use the default.
#ifndef ROCKWATCH_CHATTER_IMPACTS
#define ROCKWATCH_CHATTER_IMPACTS 2
#endif
inline constexpr int kMaxImpactsPerSubstep = ROCKWATCH_CHATTER_IMPACTS;
static_assert(kMaxImpactsPerSubstep >= 1 && kMaxImpactsPerSubstep <= 1000, "the chatter rule needs 1 <= K <= 1000");

template <typename Derived, typename Types>
class RockingSegments {
 public:
  using Length = typename Types::Length;
  using Speed = typename Types::Speed;
  using Accel = typename Types::Accel;
  using Fraction = typename Types::Fraction;
  using State = MotionState<Length, Speed, Accel>;
  using Report = StepReport<Fraction, Speed>;
  // Impacts located inside one step (the chatter rule, SPEC §3), and so segments (impacts + 1) integrated in it.
  static constexpr int kMaxImpactsPerStep = kMaxImpactsPerSubstep;
  static constexpr int kMaxSegmentsPerStep = kMaxImpactsPerStep + 1;
  // What each piece of the work costs when metered (core/work_meter.hpp).
  static constexpr WorkCosts kWork = Types::kWork;

  Side side() const { return side_; }
  bool moving() const { return moving_; }
  bool collapsed() const { return collapsed_; }

  // One whole step to this input at the step end: the derived stepper's begin_step(), then its continue_step() with
  // no meter.
  Report step(Accel ug_mps2, Accel vg_mps2) {
    UnmeteredWork meter;
    derived().begin_step(ug_mps2, vg_mps2);
    derived().continue_step(meter);
    return report_;
  }
  // The report of the step in progress (the derived stepper's begin_step/continue_step); the step's own once
  // continue_step() returned true, bit-identical to step()'s.
  const Report& step_report() const { return report_; }

 protected:
  // The wall at rest, vertical.
  void rest_vertical() {
    state_ = State{Length{}, Speed{}, Accel{}};
    side_ = Side::positive;
    moving_ = false;
    collapsed_ = false;
  }

  // After rest_vertical(): the wall at x, ẋ (side follows x, or ẋ when x = 0); ẍ is the caller's.
  void place(Length x_m, Speed xd_mps) {
    state_.x_m = x_m;
    state_.xd_mps = xd_mps;
    if (x_m != Length{}) {
      side_ = x_m > Length{} ? Side::positive : Side::negative;
    } else {
      side_ = xd_mps < Speed{} ? Side::negative : Side::positive;
    }
    moving_ = x_m != Length{} || xd_mps != Speed{};
  }

  // The segments of one step, from θ = 0 to the step end (or collapse): begin_segments(), then run_segments() until
  // it returns true. It returns false when `meter` cannot pay for the next piece of work (core/work_meter.hpp); the
  // next call goes on from there, and the report and the state are then the same as if the step had run at once.
  void begin_segments() {
    seg_theta_ = Fraction{};
    seg_index_ = 0;
    seg_counted_ = false;
  }
  template <typename Meter>
  bool run_segments(Meter& meter) {
    Report& report = report_;
    // Each pass either ends the step or ends in an impact; after kMaxImpactsPerStep impacts the next crossing of the
    // hinge ends the step (the chatter rule, advance_segment), so the loop runs at most kMaxSegmentsPerStep times.
    while (seg_index_ < kMaxSegmentsPerStep) {
      if (!moving_ && !try_start(seg_theta_, report)) break;
      const SegmentEnd end = advance_segment(seg_theta_, report, meter);
      if (end == SegmentEnd::suspended) return false;
      if (end == SegmentEnd::finished) break;
      ++seg_index_;
      seg_counted_ = false;
    }
    return true;
  }
  // s·x and s·ẋ: the motion as seen from side s (positive away from the hinge on that side).
  static Length signed_x(Side s, Length x) { return s == Side::positive ? x : -x; }
  static Speed signed_v(Side s, Speed v) { return s == Side::positive ? v : -v; }

  State state_{};
  Side side_ = Side::positive;
  bool moving_ = false;
  bool collapsed_ = false;
  Report report_{};  // the step in progress (the derived stepper's begin_step resets it)

 private:
  enum class SegmentEnd : std::uint8_t { finished, impact, suspended };

  // Where the step in progress stands (run_segments): position in the step, segment number (= impacts so far in the
  // step), whether that segment has been counted in the report.
  Fraction seg_theta_{};
  int seg_index_ = 0;
  bool seg_counted_ = false;

  const Derived& kernel() const { return static_cast<const Derived&>(*this); }
  Derived& derived() { return static_cast<Derived&>(*this); }

  // At rest from θ: if the ground's drive towards a side is positive at the step end, start rocking towards it
  // where the drive crosses zero (at θ if it already is positive). Returns true if moving.
  bool try_start(Fraction& theta, Report& report) {
    for (int candidate = 0; candidate < 2; ++candidate) {
      const Side s = candidate == 0 ? Side::positive : Side::negative;
      const Accel drive_end = kernel().drive_at_end(s);
      if (!(drive_end > Accel{})) continue;
      const Accel drive_now = kernel().drive(s, theta);
      if (drive_now < Accel{}) theta = kernel().start_crossing(theta, drive_now, drive_end);
      side_ = s;
      moving_ = true;
      state_ = State{Length{}, Speed{}, kernel().accel_at_hinge(s, theta)};
      if (!report.started) {
        report.started = true;
        report.start_fraction = theta;
      }
      return true;
    }
    return false;
  }

  // From θ to the step end on the current side, stopping at the first impact or at collapse: finished (end reached or
  // collapsed), impact (the next segment starts at θ), or suspended before a piece of work the meter cannot pay for
  // (nothing changed but the report's work counters: the segment is done again from θ at the next call).
  template <typename Meter>
  SegmentEnd advance_segment(Fraction& theta, Report& report, Meter& meter) {
    if (!seg_counted_) {
      ++report.segments;
      seg_counted_ = true;
    }
    const Side s = side_;
    const Length x0 = signed_x(s, state_.x_m);
    const bool chatter = seg_index_ >= kMaxImpactsPerStep;  // the step's located impacts are spent (SPEC §3)
    if (x0 == Length{} && signed_v(s, state_.xd_mps) < Speed{}) {
      if (chatter) return close_chatter(theta, report, false);
      impact(theta, state_.xd_mps, report);  // sitting on the hinge and moving across it
      return SegmentEnd::impact;
    }
    if (!(theta < Fraction(1))) return SegmentEnd::finished;
    if (!meter.take(kWork.trial)) return SegmentEnd::suspended;
    const auto segment = kernel().begin_segment(theta);
    const State end = kernel().end_of(segment);
    const Length x1 = signed_x(s, end.x_m);
    if (x1 < Length{}) {
      // The chatter rule, or the queue is full and events are not located (core/work_meter.hpp): the crossing is not
      // located; at rest at the step end.
      if (chatter || meter.shed) return close_chatter(theta, report, !chatter);
      // Crossed x = 0 inside the step: locate the crossing and apply the impact there (SPEC §3, §4.1).
      if (!meter.take(kWork.locate)) return SegmentEnd::suspended;
      const auto at = kernel().locate(segment, end, Length{}, report);
      theta = at.theta;
      impact(theta, kernel().state_at(segment, at).xd_mps, report);
      return SegmentEnd::impact;
    }
    const int i = side_index(s);
    const Length inst = kernel().setup().x_inst_m[i];
    const Length limit = kernel().setup().x_collapse_m[i];
    if (x0 < inst && x1 >= inst && !report.exceeded) {
      if (meter.shed) {
        report.exceeded = true;
        report.exceed_fraction = Fraction(1);
        report.work_shed = true;
      } else {
        if (!meter.take(kWork.locate)) return SegmentEnd::suspended;
        report.exceeded = true;
        report.exceed_fraction = kernel().locate(segment, end, inst, report).theta;
      }
    }
    if (x1 >= limit) {
      if (meter.shed) {
        state_ = end;
        report.collapse_fraction = Fraction(1);
        report.work_shed = true;
      } else {
        if (!meter.take(kWork.locate)) return SegmentEnd::suspended;
        const auto at = kernel().locate(segment, end, limit, report);
        state_ = kernel().state_at(segment, at);
        report.collapse_fraction = at.theta;
      }
      state_.x_m = s == Side::positive ? limit : -limit;
      report.collapsed = true;
      collapsed_ = true;
      moving_ = false;
      return SegmentEnd::finished;
    }
    state_ = end;
    return SegmentEnd::finished;
  }

  // Impact at x = 0 at θ with velocity v_before: ẋ⁺ = √r ẋ⁻ into the other side, ẍ⁺ from its equation of motion,
  // or rest when the wall barely moves and the ground does not drive it out (SPEC §3).
  void impact(Fraction theta, Speed v_before, Report& report) {
    const Speed v_after = kernel().rebound(v_before);
    if (report.impacts_total == 0) {
      report.first_impact_fraction = theta;
      report.first_impact_v_before_mps = v_before;
      report.first_impact_v_after_mps = v_after;
    }
    if (report.impacts_total < UINT16_MAX) ++report.impacts_total;
    const Speed speed_before = v_before < Speed{} ? -v_before : v_before;
    if (speed_before >= kernel().setup().v_count_mps && report.impacts_counted < UINT16_MAX) {
      ++report.impacts_counted;
    }
    side_ = opposite(side_);
    const Speed speed_after = v_after < Speed{} ? -v_after : v_after;
    if (speed_after < kernel().setup().v_rest_mps) {
      if (!(kernel().drive(side_, theta) > Accel{})) {
        put_at_rest(report);
        return;
      }
    }
    state_ = State{Length{}, v_after, kernel().accel_at_hinge(side_, theta)};
  }

  // The chatter rule (SPEC §3): a crossing of the hinge beyond the step's kMaxImpactsPerStep located impacts (or one
  // the meter sheds) is not located; the wall rests on the hinge at the step's end and the start rule takes over at the
  // next step.
  SegmentEnd close_chatter(Fraction& theta, Report& report, bool shed) {
    theta = Fraction(1);
    put_at_rest(report);
    report.rest_forced = true;
    if (shed) report.work_shed = true;
    return SegmentEnd::finished;
  }

  void put_at_rest(Report& report) {
    state_ = State{Length{}, Speed{}, Accel{}};
    moving_ = false;
    report.came_to_rest = true;
  }
};

}  // namespace rockwatch::core
