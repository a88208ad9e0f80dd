// The instability alarm inside sim::analyse (AnalysisOptions::evaluate_alarm) and the batch study: evaluated after
// every integration step, free motion after the record included; the summary consistent with its transitions;
// the analysis itself unchanged by it; settings validated naming the one at fault; the arithmetic dispatch.
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "reference_pulses.hpp"
#include "rockwatch/core/alarm.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;
using rockwatch::test::pulse_mps2;

namespace {

sim::GroundMotion pulse(const std::string& name, double record_end_s = 5.0) {
  return sim::sample_motion([&](double t) { return pulse_mps2(name, t); }, 0.005, record_end_s);
}

sim::AnalysisOptions alarm_options(double t_end_s = 5.0) {
  sim::AnalysisOptions o;
  o.t_end_s = t_end_s;
  o.evaluate_alarm = true;
  return o;
}

void check_rejected(const sim::AnalysisOptions& o, const char* mention) {
  try {
    sim::analyse(core::paper_wall(), pulse("G1"), o);
    FAIL("accepted");
  } catch (const sim::AnalysisError& e) {
    STRCMP_CONTAINS(mention, e.what());
  }
}

// The summary is what its transitions say.
void check_summary_follows_transitions(const sim::AlarmSummary& a) {
  CHECK_TRUE(a.evaluated);
  LONGS_EQUAL(a.n_transitions, a.transitions.size());
  core::AlarmLevel level = core::AlarmLevel::quiet, highest = core::AlarmLevel::quiet;
  double t_previous = -1.0;
  std::optional<double> warning, imminent, collapsed;
  for (const sim::AlarmTransition& t : a.transitions) {
    CHECK_TRUE(t.previous == level);
    CHECK_TRUE(t.level != t.previous);
    CHECK_TRUE(t.t_s > t_previous);
    t_previous = t.t_s;
    level = t.level;
    if (level > highest) highest = level;
    if (level >= core::AlarmLevel::warning && !warning) warning = t.t_s;
    if (level >= core::AlarmLevel::imminent && !imminent) imminent = t.t_s;
    if (level >= core::AlarmLevel::collapsed && !collapsed) collapsed = t.t_s;
  }
  CHECK_TRUE(highest == a.max_level);
  CHECK_TRUE(warning == a.t_first_warning_s);
  CHECK_TRUE(imminent == a.t_first_imminent_s);
  CHECK_TRUE(collapsed == a.t_first_collapsed_s);
}

}  // namespace

TEST_GROUP(AnalysisAlarm){};

TEST(AnalysisAlarm, OffByDefaultAndTheAnalysisIsTheSameWithIt) {
  sim::AnalysisOptions plain;
  plain.t_end_s = 5.0;
  const sim::AnalysisResult a = sim::analyse(core::paper_wall(), pulse("G1"), plain);
  CHECK_FALSE(a.alarm.evaluated);
  LONGS_EQUAL(0, a.alarm.n_transitions);
  CHECK_TRUE(a.arithmetic == sim::Arithmetic::double_precision);
  const sim::AnalysisResult b = sim::analyse(core::paper_wall(), pulse("G1"), alarm_options());
  CHECK_TRUE(b.alarm.evaluated);
  CHECK_EQUAL(a.collapsed, b.collapsed);
  CHECK_TRUE(a.t_collapse_s == b.t_collapse_s);
  CHECK_TRUE(a.t_exceed_s == b.t_exceed_s);
  DOUBLES_EQUAL(a.max_abs_x_m, b.max_abs_x_m, 0.0);
  LONGS_EQUAL(a.n_impacts_total, b.n_impacts_total);
}

TEST(AnalysisAlarm, CollapseDuringTheRecord) {
  // G1 collapses at about 0.99 s: IMMINENT comes before, COLLAPSED at the collapse point itself.
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), pulse("G1"), alarm_options());
  CHECK_TRUE(r.collapsed);
  const sim::AlarmSummary& a = r.alarm;
  check_summary_follows_transitions(a);
  CHECK_TRUE(a.max_level == core::AlarmLevel::collapsed);
  DOUBLES_EQUAL(*r.t_collapse_s, *a.t_first_collapsed_s, 0.0);
  CHECK_TRUE(*a.t_first_imminent_s < *r.t_collapse_s);
  CHECK_TRUE(*a.t_first_warning_s <= *a.t_first_imminent_s);
  const sim::AlarmTransition& last = a.transitions.back();
  CHECK_TRUE(last.level == core::AlarmLevel::collapsed);
  CHECK_TRUE((last.reasons & core::alarm_reason::over_collapse_displacement) != 0);
  DOUBLES_EQUAL(2.0 * r.x_inst_m, std::fabs(last.x_m), 1e-12);
  DOUBLES_EQUAL(0.0, *last.t_to_instability_s, 0.0);
  // IMMINENT came by energy (moving outward above the barrier), with a prediction, well before |x| reached x_inst.
  for (const sim::AlarmTransition& t : a.transitions) {
    if (t.level != core::AlarmLevel::imminent) continue;
    CHECK_TRUE((t.reasons & core::alarm_reason::energy_over_barrier_outward) != 0);
    CHECK_TRUE(t.energy_ratio >= 1.0);
    CHECK_TRUE(t.t_to_instability_s.has_value());
    CHECK_TRUE(std::fabs(t.x_m) < r.x_inst_m);
    break;
  }
}

TEST(AnalysisAlarm, FreeMotionAfterTheRecordIsWatchedToo) {
  // G1 cut at 0.5 s: the collapse comes in the free motion after the record; the alarm follows it there.
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), pulse("G1"), alarm_options(0.5));
  CHECK_TRUE(r.collapse_after_end);
  check_summary_follows_transitions(r.alarm);
  CHECK_TRUE(r.alarm.max_level == core::AlarmLevel::collapsed);
  DOUBLES_EQUAL(*r.t_collapse_s, *r.alarm.t_first_collapsed_s, 0.0);
  CHECK_TRUE(*r.alarm.t_first_collapsed_s > 0.5);
}

TEST(AnalysisAlarm, SurvivorRocksWithoutImminent) {
  // G3 (0.15 g) rocks the wall and lets it settle.
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), pulse("G3"), alarm_options());
  CHECK_FALSE(r.verdict_collapse());
  check_summary_follows_transitions(r.alarm);
  CHECK_TRUE(r.alarm.max_level >= core::AlarmLevel::rocking);
  CHECK_TRUE(r.alarm.max_level < core::AlarmLevel::imminent);
  CHECK_FALSE(r.alarm.t_first_imminent_s.has_value());
}

TEST(AnalysisAlarm, TransitionsKeptAreBoundedButAllAreCounted) {
  sim::AnalysisOptions o = alarm_options();
  o.max_alarm_transitions_kept = 1;
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), pulse("G1"), o);
  LONGS_EQUAL(1, r.alarm.transitions.size());
  CHECK_TRUE(r.alarm.n_transitions > 1);
  CHECK_TRUE(r.alarm.max_level == core::AlarmLevel::collapsed);
  o.max_alarm_transitions_kept = 0;
  CHECK_TRUE(sim::analyse(core::paper_wall(), pulse("G1"), o).alarm.transitions.empty());
}

TEST(AnalysisAlarm, HoldIsCountedInSamples) {
  // G3 sampled at 0.01 s runs in 10 sub-steps of 1 ms (the default max step), the alarm once per record sample, as
  // the monitor runs it. It lifts the wall just past λ_w·x_inst: WARNING, then below it again. With no hold the
  // level falls at the first sample end below; with a hold of 0.1 s it falls exactly 0.1 s (10 samples) later.
  const sim::GroundMotion coarse = sim::sample_motion([](double t) { return pulse_mps2("G3", t); }, 0.01, 5.0);
  auto fall_from_warning = [&](double hold_s) {
    sim::AnalysisOptions o = alarm_options();
    o.alarm.hold_s = hold_s;
    const sim::AnalysisResult r = sim::analyse(core::paper_wall(), coarse, o);
    DOUBLES_EQUAL(0.001, r.dt_s, 1e-15);
    check_summary_follows_transitions(r.alarm);
    CHECK_TRUE(r.alarm.max_level == core::AlarmLevel::warning);
    for (const sim::AlarmTransition& t : r.alarm.transitions) {
      // Transitions are at record sample ends (multiples of 0.01 s).
      DOUBLES_EQUAL(std::round(t.t_s / 0.01) * 0.01, t.t_s, 1e-9);
      if (t.previous == core::AlarmLevel::warning) return t.t_s;
    }
    FAIL("never fell from WARNING");
    return 0.0;
  };
  const double t_below = fall_from_warning(0.0);
  DOUBLES_EQUAL(t_below + 0.1, fall_from_warning(0.1), 1e-9);
}

TEST(AnalysisAlarm, SettingsAreValidatedNamingTheOneAtFault) {
  sim::AnalysisOptions o = alarm_options();
  o.alarm.lambda_warning = 0.0;
  check_rejected(o, "lambda_warning");
  o.alarm.lambda_warning = std::nan("");
  check_rejected(o, "lambda_warning");
  o = alarm_options();
  o.alarm.hold_s = -1.0;
  check_rejected(o, "hold_s");
  o = alarm_options();
  o.alarm.energy_margin = 0.5;
  check_rejected(o, "energy_margin");
  // Not evaluated: not checked.
  o.evaluate_alarm = false;
  CHECK_TRUE(sim::analyse(core::paper_wall(), pulse("G1"), o).collapsed);
}

TEST(AnalysisAlarm, FixedPointTakesTheLinearModelOnly) {
  sim::AnalysisOptions o = alarm_options();
  o.arithmetic = sim::Arithmetic::fixed_point;
  o.model = core::ModelKind::full;
  check_rejected(o, "fixed-point arithmetic supports the linear model only");
  o.model = core::ModelKind::linear;
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), pulse("G1"), o);
  CHECK_TRUE(r.arithmetic == sim::Arithmetic::fixed_point);
  CHECK_TRUE(r.collapsed);
  CHECK_TRUE(r.alarm.evaluated);
  CHECK_TRUE(r.alarm.max_level == core::AlarmLevel::collapsed);
}

namespace {

sim::study::StudyPlan g_pulse_plan() {
  sim::study::StudyPlan plan;
  for (const char* name : {"G1", "G3"}) {
    sim::study::StudyRecord r;
    r.name = name;
    r.dt_s = 0.005;
    r.ug_mps2 = pulse(name, 3.0).ug_mps2;
    r.peak_ug_mps2 = sim::peak_abs(r.ug_mps2);
    plan.records.push_back(r);
  }
  plan.pga_g = {0.15, 0.30};
  plan.restitutions = {{core::Restitution{core::RestitutionKind::exp, 0.0}, "exp"}};
  plan.vertical = {false};
  plan.analysis.evaluate_alarm = true;
  return plan;
}

}  // namespace

TEST_GROUP(StudyAlarmRuns){};

TEST(StudyAlarmRuns, EachRunKeepsItsFirstImminentAndFixedRunsTheirDoubleReference) {
  sim::study::StudyPlan plan = g_pulse_plan();
  std::vector<sim::study::RunResult> results;
  sim::study::run_study(plan, results, 1);
  sim::study::StudyPlan fixed = plan;
  fixed.analysis.arithmetic = sim::Arithmetic::fixed_point;
  fixed.dt_check = true;
  std::vector<sim::study::RunResult> fixed_results;
  sim::study::run_study(fixed, fixed_results, 1);
  bool some_imminent = false;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const sim::study::RunResult& d = results[i];
    const sim::study::RunResult& f = fixed_results[i];
    CHECK_TRUE(d.error.empty() && f.error.empty());
    CHECK_FALSE(d.reference.has_value());
    CHECK_TRUE(f.reference.has_value());
    // The reference is the double run of the plain study.
    CHECK_EQUAL(d.collapsed, f.reference->collapsed);
    CHECK_TRUE(d.t_collapse_s == f.reference->t_collapse_s);
    DOUBLES_EQUAL(d.max_abs_x_m, f.reference->max_abs_x_m, 0.0);
    CHECK_TRUE(d.t_first_imminent_s == f.reference->t_first_imminent_s);
    CHECK_EQUAL(d.collapsed, sim::study::double_collapsed(f));
    CHECK_TRUE(f.collapsed_reference.has_value());
    some_imminent = some_imminent || d.t_first_imminent_s.has_value();
    if (d.collapsed) CHECK_TRUE(*d.t_first_imminent_s < *d.t_collapse_s);
  }
  CHECK_TRUE(some_imminent);
  DOUBLES_EQUAL(0.001, sim::study::integration_step_s(plan, plan.records[0]), 1e-18);  // the default: 5 sub-steps
  plan.analysis.max_step_s = 0.005;
  DOUBLES_EQUAL(0.005, sim::study::integration_step_s(plan, plan.records[0]), 0.0);
  plan.analysis.max_step_s = 0.002;
  DOUBLES_EQUAL(0.005 / 3.0, sim::study::integration_step_s(plan, plan.records[0]), 1e-18);
}

TEST(StudyAlarmRuns, PlanValidationCoversTheAlarmAndTheArithmetic) {
  sim::study::StudyPlan plan = g_pulse_plan();
  plan.analysis.alarm.energy_margin = 0.5;
  std::vector<sim::study::RunResult> results;
  try {
    sim::study::run_study(plan, results, 1);
    FAIL("accepted");
  } catch (const sim::AnalysisError& e) {
    STRCMP_CONTAINS("energy_margin", e.what());
  }
  plan = g_pulse_plan();
  plan.analysis.arithmetic = sim::Arithmetic::fixed_point;
  plan.analysis.model = core::ModelKind::full;
  try {
    sim::study::validate_plan(plan);
    FAIL("accepted");
  } catch (const sim::AnalysisError& e) {
    STRCMP_CONTAINS("linear model only", e.what());
  }
}
