// Internals shared by the two paths of sim::analyse: the integration grid, the common start of an analysis, the
// alarm-summary recorder, and the fixed-point path itself (AnalysisOptions::arithmetic == fixed_point: the same
// record handling, post-record energy verdict and summary as the double engine, run on core::FixedRockingStepper).
#pragma once

#include <optional>
#include <vector>

#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim::detail {

// Called by analyse() after the options and input have been validated. Throws AnalysisError when the wall or
// record does not fit the fixed-point formats (the message names the quantity and its range).
// Input on the integration grid: sample k of n_sub sub-steps per record interval, zero after the record.
struct GridInput {
  const GroundMotion& motion;
  std::size_t n_sub;

  double at(const std::vector<double>& v, std::size_t k) const {
    if (v.empty()) return 0.0;
    const std::size_t i = k / n_sub, j = k % n_sub;
    if (i + 1 >= v.size()) return i + 1 == v.size() && j == 0 ? v.back() : 0.0;
    return v[i] + (v[i + 1] - v[i]) * double(j) / double(n_sub);
  }
  double ug(std::size_t k) const { return at(motion.ug_mps2, k); }
  double vg(std::size_t k) const { return at(motion.vg_mps2, k); }
};

// What both arithmetics prepare the same way: the step, the stepper setup in double and the result's header fields
// (dt, duration, t_end, PGA, r, x_inst, threshold). Defined in analysis.cpp.
struct AnalysisStart {
  std::size_t n_sub = 1;            // integration steps per record interval
  double h_s = 0.0;                 // integration step [s]
  core::StepperSetup<double> setup{};
};
AnalysisStart start_analysis(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o,
                             AnalysisResult& result);

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
