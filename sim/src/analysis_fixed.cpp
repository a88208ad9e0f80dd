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
