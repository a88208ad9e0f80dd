// The fixed-point engine of sim::analyse (AnalysisOptions::arithmetic == fixed_point) and the alarm-summary
// recorder shared by both engines. The analysis loop itself is analysis.cpp's, for both.
#include <cmath>
#include <sstream>

#include "analysis_engines.hpp"

namespace rockwatch::sim::detail {

void FixedAnalysisEngine::check_motion(const GroundMotion& motion) {
  constexpr double limit = 80.0;
  const std::vector<double>* series[2] = {&motion.ug_mps2, &motion.vg_mps2};
  const char* names[2] = {"horizontal", "vertical"};
  for (int c = 0; c < 2; ++c) {
    for (std::size_t i = 0; i < series[c]->size(); ++i) {
      if (std::fabs((*series[c])[i]) >= limit) {
        std::ostringstream m;
        m << names[c] << " sample " << i << " (t = " << double(i) * motion.dt_s << " s) is " << (*series[c])[i]
          << " m/s2: the fixed-point engine accepts |acceleration| < " << limit << " m/s2";
        throw AnalysisError(m.str());
      }
    }
  }
}

FixedAnalysisEngine::FixedAnalysisEngine(const core::WallParameters&, const core::StepperSetup<double>& setup,
                                         const AnalysisOptions& o, double dt_s, std::size_t n_sub) {
  switch (chain_.init(setup, chain_alarm_settings(o), dt_s, static_cast<int>(n_sub))) {
    case core::AlarmChainError::ok: break;
    case core::AlarmChainError::substeps_out_of_range:
      throw AnalysisError("the record step needs more than 64 sub-steps of max_step: choose a larger max step");
    case core::AlarmChainError::stepper_setup:
      throw AnalysisError(core::fixed_setup_error_message(chain_.setup_error()));
    case core::AlarmChainError::indicator_constants:
      throw AnalysisError("x_inst must be in (0.008, 1.9) m for the fixed-point instability indicators");
  }
}

void measure_published(const core::StepperSetup<double>& setup, const AnalysisOptions& o, double dt_s,
                       std::size_t n_sub, const std::vector<std::array<core::AccelQ7_56, 2>>& inputs,
                       AlarmSummary& summary) {
  using Chain = core::StepperAlarmChain<core::FixedRockingStepper>;
  AlarmSummary::Published& p = summary.published;
  p = AlarmSummary::Published{};
  if (inputs.empty()) return;
  Chain chain;
  if (chain.init(setup, chain_alarm_settings(o), dt_s, static_cast<int>(n_sub)) != core::AlarmChainError::ok) return;
  p.measured = true;
  chain.reset(inputs[0][0], inputs[0][1]);
  std::uint32_t call = 0;
  const auto on_sample = [&](const Chain::Output& out, std::uint32_t tag) {
    p.count_sample(call - tag, out.step.work_shed);
    const double t_s = double(call) * dt_s;
    if (out.alarm.level >= core::AlarmLevel::imminent && !p.t_first_imminent_s) {
      p.t_first_imminent_s = t_s;
      p.imminent_late_calls = call - tag;
    }
    if (out.alarm.level >= core::AlarmLevel::collapsed && !p.t_first_collapsed_s) p.t_first_collapsed_s = t_s;
  };
  for (std::size_t k = 1; k < inputs.size(); ++k) {
    call = static_cast<std::uint32_t>(k);
    p.count_call(chain.call(inputs[k][0], inputs[k][1], false, o.work_budget_units, o.work_overflow, call,
                            Chain::kMaxFinishedPerCall, on_sample));
  }
  // The monitor's input goes on after the analysis stops (a collapsed wall costs nothing): the samples still in work
  // are finished at the next calls, each with a budget.
  while (chain.pending() > 0) {
    ++call;
    core::WorkMeter meter = core::WorkMeter::of(o.work_budget_units);
    chain.run(meter, Chain::kMaxFinishedPerCall, [](int, const core::FixedStepReport&, Chain::Input, Chain::Input) {},
              on_sample);
  }
}

void record_alarm_update(AlarmSummary& summary, std::size_t keep, double t_s, const core::AlarmUpdate& u,
                         const AlarmSample& sample) {
  if (u.level > summary.max_level) summary.max_level = u.level;
  if (u.level >= core::AlarmLevel::warning && !summary.t_first_warning_s) summary.t_first_warning_s = t_s;
  if (u.level >= core::AlarmLevel::imminent && !summary.t_first_imminent_s) summary.t_first_imminent_s = t_s;
  if (u.level >= core::AlarmLevel::collapsed && !summary.t_first_collapsed_s) summary.t_first_collapsed_s = t_s;
  if (!u.changed) return;
  ++summary.n_transitions;
  if (summary.transitions.size() >= keep) return;
  AlarmTransition t;
  t.t_s = t_s;
  t.level = u.level;
  t.previous = u.previous;
  t.reasons = u.reasons;
  t.x_m = sample.x_m;
  t.xd_mps = sample.xd_mps;
  t.t_to_instability_s = sample.t_to_instability_s;
  t.energy_ratio = sample.energy_ratio;
  summary.transitions.push_back(t);
}

}  // namespace rockwatch::sim::detail
