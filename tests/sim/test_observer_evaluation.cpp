// The wall observer's evaluation engine (sim::study::run_observer_evaluation): the mismatch cases, the run order,
// results independent of the thread count, each run equal to the three analyses done by hand, cancel.
#include <atomic>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/observer_evaluation.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;
namespace study = rockwatch::sim::study;

namespace {

// Set 3 X and Y of the shipped suite, horizontal only, 0.16 and 0.22 g.
study::StudyPlan suite_plan() {
  const records::SuiteRecordFile f = records::read_suite_record(records::suite_set_path(ROCKWATCH_SUITE_DIR, 3));
  study::StudyPlan plan;
  for (std::size_t c = 0; c < 2; ++c) {
    study::StudyRecord r;
    r.name = "set03";
    r.component = c == 0 ? "X" : "Y";
    r.dt_s = f.dt_s;
    r.ug_mps2 = f.components_mps2[c];
    r.peak_ug_mps2 = sim::peak_abs(r.ug_mps2);
    plan.records.push_back(r);
  }
  plan.pga_g = {0.16, 0.22};
  plan.restitutions = {study::RestitutionCase{core::Restitution{}, "exp"}};
  plan.vertical = {false};
  plan.analysis.evaluate_alarm = true;
  return plan;
}

bool same(const study::ObserverRunResult& a, const study::ObserverRunResult& b) {
  return a.done == b.done && a.true_collapsed == b.true_collapsed && a.true_t_collapse_s == b.true_t_collapse_s &&
         a.open_t_first_imminent_s == b.open_t_first_imminent_s &&
         a.fused_t_first_imminent_s == b.fused_t_first_imminent_s && a.fused_x_rms_error_m == b.fused_x_rms_error_m &&
         a.r_estimate == b.r_estimate && a.r_estimate_after_impacts == b.r_estimate_after_impacts &&
         a.bias_estimate_m == b.bias_estimate_m && a.n_rejected == b.n_rejected;
}

}  // namespace

// Four of the standard cases (r_ana, b_0.9, b_1.1, h1_h2_1.5_2.0), so the run-order tests stay small.
std::vector<study::MismatchCase> four_cases(const core::WallParameters& w) {
  std::vector<study::MismatchCase> out;
  for (const study::MismatchCase& c : study::standard_mismatch_cases(w)) {
    if (c.name == "r_ana" || c.name == "b_0.9" || c.name == "b_1.1" || c.name == "h1_h2_1.5_2.0") out.push_back(c);
  }
  return out;
}

TEST_GROUP(ObserverEvaluation){};

TEST(ObserverEvaluation, TheStandardMismatchCases) {
  const core::WallParameters w = core::paper_wall();
  const std::vector<study::MismatchCase> cases = study::standard_mismatch_cases(w);
  // Eight walls (issue 27), with the transducer alone and then with the accelerometer.
  LONGS_EQUAL(16, cases.size());
  const char* const names[] = {"r_ana", "r_0.8", "b_0.85", "b_0.9", "b_1.1", "h1_h2_1.5_2.0", "fp_2kN", "fp_3kN"};
  for (std::size_t i = 0; i < 8; ++i) {
    STRCMP_EQUAL(names[i], cases[i].name.c_str());
    STRCMP_EQUAL((std::string(names[i]) + "+accel").c_str(), cases[i + 8].name.c_str());
    CHECK_FALSE(cases[i].accel_noise_mps2.has_value());
    DOUBLES_EQUAL(0.05, *cases[i + 8].accel_noise_mps2, 0.0);
    DOUBLES_EQUAL(cases[i].wall.b_m, cases[i + 8].wall.b_m, 0.0);
  }
  CHECK_TRUE(cases[0].restitution.kind == core::RestitutionKind::ana);
  CHECK_TRUE(cases[1].restitution.kind == core::RestitutionKind::value);
  DOUBLES_EQUAL(0.8, cases[1].restitution.value, 0.0);
  DOUBLES_EQUAL(w.b_m, cases[0].wall.b_m, 0.0);
  DOUBLES_EQUAL(0.85 * w.b_m, cases[2].wall.b_m, 1e-15);
  DOUBLES_EQUAL(0.9 * w.b_m, cases[3].wall.b_m, 1e-15);
  DOUBLES_EQUAL(1.1 * w.b_m, cases[4].wall.b_m, 1e-15);
  DOUBLES_EQUAL(1.5, cases[5].wall.h1_m, 1e-12);
  DOUBLES_EQUAL(2.0, cases[5].wall.h2_m, 1e-12);
  DOUBLES_EQUAL(2000.0, cases[6].wall.fp_npm, 0.0);
  DOUBLES_EQUAL(3000.0, cases[7].wall.fp_npm, 0.0);
  for (std::size_t i = 2; i < 8; ++i) CHECK_TRUE(cases[i].restitution.kind == core::RestitutionKind::exp);
  const study::ObserverEvaluationPlan e;
  DOUBLES_EQUAL(0.5e-3, e.sensors.x_noise_m, 0.0);
  DOUBLES_EQUAL(2e-3, e.sensors.x_bias_m, 0.0);
  CHECK_FALSE(e.sensors.a_noise_mps2.has_value());
}

TEST(ObserverEvaluation, RunOrderAndResultsIndependentOfTheThreadCount) {
  const study::StudyPlan plan = suite_plan();
  study::ObserverEvaluationPlan e;
  e.cases = four_cases(plan.wall);
  LONGS_EQUAL(16, study::observer_run_count(plan, e));
  const study::ObserverRunKey k = study::observer_run_key(plan, e, 7);  // case 1, record 1, level 1
  LONGS_EQUAL(1, k.case_index);
  LONGS_EQUAL(1, k.record_index);
  LONGS_EQUAL(1, k.pga_index);
  std::vector<study::ObserverRunResult> one, two;
  study::run_observer_evaluation(plan, e, one, 1);
  study::run_observer_evaluation(plan, e, two, 2);
  LONGS_EQUAL(16, one.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    CHECK_TEXT(one[i].error.empty(), one[i].error.c_str());
    CHECK_TEXT(same(one[i], two[i]), ("run " + std::to_string(i)).c_str());
  }

  // Run 7 by hand: the true wall (0.9 b) with the run's sensors, the nominal wall open loop and fused.
  const study::StudyRecord& rec = plan.records[1];
  sim::GroundMotion m;
  m.dt_s = rec.dt_s;
  for (const double u : rec.ug_mps2) m.ug_mps2.push_back(u * 0.22 * plan.wall.g_mps2 / rec.peak_ug_mps2);
  sim::AnalysisOptions t;
  t.keep_history = true;
  const sim::AnalysisResult truth = sim::analyse(e.cases[1].wall, m, t);
  CHECK_EQUAL(truth.verdict_collapse(), one[7].true_collapsed);
  CHECK_TRUE(truth.t_collapse_s == one[7].true_t_collapse_s);
  DOUBLES_EQUAL(0.09 / 0.1 * 0.1003276, one[7].true_x_inst_m, 1e-4);
  sim::AnalysisOptions o;
  o.evaluate_alarm = true;
  const sim::AnalysisResult open = sim::analyse(plan.wall, m, o);
  CHECK_TRUE(open.alarm.t_first_imminent_s == one[7].open_t_first_imminent_s);
  // The fused run learns the bias of the study's sensors.
  DOUBLES_EQUAL(2e-3, one[7].bias_estimate_m, 2e-4);
  CHECK(one[7].n_updates > 0);
}

TEST(ObserverEvaluation, StopsWhenCancelled) {
  const study::StudyPlan plan = suite_plan();
  study::ObserverEvaluationPlan e;
  e.cases = four_cases(plan.wall);
  std::vector<study::ObserverRunResult> results;
  const std::atomic<bool> cancel{true};
  study::run_observer_evaluation(plan, e, results, 2, {}, &cancel);
  LONGS_EQUAL(16, results.size());
  for (const study::ObserverRunResult& r : results) CHECK_FALSE(r.done);
}
