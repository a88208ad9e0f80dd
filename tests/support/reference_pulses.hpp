// The reference solver's input pulses (tests/data/reference/two_block_reference.json, descriptions in the JSON)
// and a one-call analysis of the paper wall under them, for the double and the fixed-point engine tests.
#pragma once

#include <cmath>
#include <string>

#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::test {

inline constexpr double kG = 9.81;

// Zero after the pulse.
inline double pulse_mps2(const std::string& name, double t) {
  if (name == "G1") return t <= 0.5 ? 0.30 * kG * std::sin(2.0 * M_PI * t / 0.5) : 0.0;
  if (name == "G2") return t <= 0.25 ? 0.30 * kG * std::sin(2.0 * M_PI * t / 0.25) : 0.0;
  if (name == "G3") return t <= 0.5 ? 0.15 * kG * std::sin(2.0 * M_PI * t / 0.5) : 0.0;
  if (name == "G6") return t <= 1.5 ? -(0.15 * kG / 1.5) * t : -0.15 * kG;
  const double peak = name == "G7" ? 0.20 * kG : 0.15 * kG;  // G7, G7b: triangle 0 → −peak at 0.5 s → 0 at 1 s
  if (t <= 0.5) return -peak * t / 0.5;
  return t <= 1.0 ? -peak * (1.0 - t) / 0.5 : 0.0;
}

inline bool is_piecewise_linear(const std::string& name) { return name == "G6" || name == "G7" || name == "G7b"; }

inline sim::AnalysisResult analyse_pulse(
    const std::string& name, const std::string& r, double dt, core::ModelKind model, double kappa = 2.0,
    double t_end = 5.0, double record_end = 5.0,
    sim::Arithmetic arithmetic = sim::Arithmetic::double_precision) {
  sim::AnalysisOptions o;
  o.arithmetic = arithmetic;
  o.restitution.kind = r == "r_ana" ? core::RestitutionKind::ana : core::RestitutionKind::exp;
  o.model = model;
  o.kappa = kappa;
  o.max_step_s = dt;
  o.t_end_s = t_end;
  return sim::analyse(core::paper_wall(),
                      sim::sample_motion([&](double t) { return pulse_mps2(name, t); }, dt, record_end), o);
}

}  // namespace rockwatch::test
