// Internals of sim::analyse: the integration grid, the common start of an analysis, the alarm-summary recorder, and
// the two analysis engines — one per arithmetic — that the one analysis loop (analysis.cpp: forced motion over the
// record, then free motion until the post-record verdict) runs. Each engine is core::StepperAlarmChain over its
// stepper plus what the analysis reads from it in double; they differ only where the arithmetic does:
//   - the input format (double, or the record's doubles converted straight to Q7.56),
//   - the post-record verdict "safe" (|x| < x_inst and E < E_barrier, SPEC §4.3): the double engine evaluates the
//     model's exact mechanical energy (full model included); the fixed engine decides it in fixed point from its
//     indicators (ρ = E/E_barrier of the linear model), so it needs the indicators every step;
//   - set-up failures: the fixed engine refuses walls, steps and records outside its formats (AnalysisError).
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "rockwatch/core/fixed_instability_indicators.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim::detail {

// What both arithmetics prepare the same way: the step, the stepper setup in double and the result's header fields
// (dt, duration, t_end, PGA, r, x_inst, threshold). Defined in analysis.cpp.
struct AnalysisStart {
  std::size_t n_sub = 1;            // integration steps per record interval
  double h_s = 0.0;                 // integration step [s]
  core::StepperSetup<double> setup{};
};
AnalysisStart start_analysis(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o,
                             AnalysisResult& result);

// Keeps one alarm update in the summary. Allocates only when a transition is kept (max_alarm_transitions_kept > 0).
struct AlarmSample {
  double x_m = 0.0, xd_mps = 0.0;             // state after the step
  std::optional<double> t_to_instability_s;   // prediction, when there is one [s]
  double energy_ratio = 0.0;                  // E / E_barrier [-]
};
void record_alarm_update(AlarmSummary& summary, std::size_t keep, double t_s, const core::AlarmUpdate& u,
                         const AlarmSample& sample);

// A value of either arithmetic in double (the summary, history and alarm transitions are in double).
inline double to_double(double v) { return v; }
template <typename FixedValue>
double to_double(const FixedValue& v) {
  return v.to_double();
}

// The alarm settings the chain runs with: the options' when the alarm is evaluated (then validated), else the
// defaults (the alarm's output is not used, and unvalidated settings must not reach the set-up).
inline core::AlarmSettings chain_alarm_settings(const AnalysisOptions& o) {
  return o.evaluate_alarm ? o.alarm : core::AlarmSettings{};
}

// The monitor's latency (AnalysisOptions::work_budget_units): the inputs the fixed engine was given (the reset's, then
// one per sample of dt_s), run again call by call through the monitor's budgeted chain; fills summary.published.
void measure_published(const core::StepperSetup<double>& setup, const AnalysisOptions& o, double dt_s,
                       std::size_t n_sub, const std::vector<std::array<core::AccelQ7_56, 2>>& inputs,
                       AlarmSummary& summary);

class DoubleAnalysisEngine {
 public:
  using Stepper = core::RockingStepper<double>;
  using Chain = core::StepperAlarmChain<Stepper>;
  using Input = double;
  using Length = double;
  using Speed = double;
  static constexpr Arithmetic kArithmetic = Arithmetic::double_precision;
  static constexpr bool kVerdictNeedsIndicators = false;  // the verdict evaluates the exact energy

  static void check_motion(const GroundMotion&) {}
  DoubleAnalysisEngine(const core::WallParameters& wall, const core::StepperSetup<double>& setup,
                       const AnalysisOptions& o, double dt_s, std::size_t n_sub);
  static Input input(double v) { return v; }

  Chain& chain() { return chain_; }
  const Chain::Output& out() const { return out_; }
  Chain::Output& out() { return out_; }
  const Stepper& stepper() const { return chain_.stepper(); }
  double x_m() const { return stepper().state().x_m; }
  double xd_mps() const { return stepper().state().xd_mps; }
  double xdd_mps2() const { return stepper().state().xdd_mps2; }
  static bool saturated(const core::StepReport<double>&) { return false; }

  // After the record: |x| < x_inst and E < E_barrier on the current side (exact energy of the model), or at rest.
  bool safe() const {
    const Stepper& s = stepper();
    if (!s.moving()) return true;
    const auto& st = s.state();
    const int i = core::side_index(s.side());
    const double energy = core::mechanical_energy(free_k_[i], st.x_m, st.xd_mps);
    return std::fabs(st.x_m) < x_inst_m_[i] && energy < barrier_jpm_;
  }

 private:
  Chain chain_{};
  Chain::Output out_{};
  core::Coefficients<double> free_k_[2]{};
  double x_inst_m_[2]{};
  double barrier_jpm_ = 0.0;
};

class FixedAnalysisEngine {
 public:
  using Stepper = core::FixedRockingStepper;
  using Chain = core::StepperAlarmChain<Stepper>;
  using Input = core::AccelQ7_56;
  using Length = core::LengthQ1_62;
  using Speed = core::SpeedQ3_60;
  static constexpr Arithmetic kArithmetic = Arithmetic::fixed_point;
  static constexpr bool kVerdictNeedsIndicators = true;  // the verdict is decided from ρ and |x| ≥ x_inst

  // Inputs beyond ±80 m/s² would saturate ẍ and the engine's coefficients (docs/FIXED_POINT.md): refuse, naming
  // the sample. Before anything else.
  static void check_motion(const GroundMotion& motion);
  // Throws AnalysisError when the wall, step or x_inst do not fit the formats.
  FixedAnalysisEngine(const core::WallParameters& wall, const core::StepperSetup<double>& setup,
                      const AnalysisOptions& o, double dt_s, std::size_t n_sub);
  // The record's doubles converted to the engine's input format once per step.
  static Input input(double v) { return Input(v); }

  Chain& chain() { return chain_; }
  const Chain::Output& out() const { return out_; }
  Chain::Output& out() { return out_; }
  const Stepper& stepper() const { return chain_.stepper(); }
  double x_m() const { return stepper().x_m().to_double(); }
  double xd_mps() const { return stepper().xd_mps().to_double(); }
  double xdd_mps2() const { return stepper().xdd_mps2().to_double(); }
  static bool saturated(const core::FixedStepReport& r) { return r.saturated; }

  // After the record: decided in fixed point by the last step's indicators (ρ = E/E_barrier), or at rest.
  bool safe() const {
    if (!stepper().moving()) return true;
    return !out_.indicators.conditions.over_instability_displacement &&
           out_.indicators.energy_ratio < core::RatioQ7_24(1);
  }

 private:
  Chain chain_{};
  Chain::Output out_{};
};

}  // namespace rockwatch::sim::detail
