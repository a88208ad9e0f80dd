// The fixed-point path of sim::analyse (AnalysisOptions::arithmetic == fixed_point): the same record handling,
// post-record energy verdict and summary as the double engine, run on core::FixedRockingStepper.
#pragma once

#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim::detail {

// Called by analyse() after the options and input have been validated. Throws AnalysisError when the wall or
// record does not fit the fixed-point formats (the message names the quantity and its range).
// Keeps one alarm update in the summary (shared by the double and fixed paths). Allocates only when a transition
// is kept (max_alarm_transitions_kept > 0).
struct AlarmSample {
  double x_m = 0.0, xd_mps = 0.0;             // state after the step
  std::optional<double> t_to_instability_s;   // prediction, when there is one [s]
  double energy_ratio = 0.0;                  // E / E_barrier [-]
};
void record_alarm_update(AlarmSummary& summary, std::size_t keep, double t_s, const core::AlarmUpdate& u,
                         const AlarmSample& sample);

AnalysisResult analyse_fixed(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o);

}  // namespace rockwatch::sim::detail
