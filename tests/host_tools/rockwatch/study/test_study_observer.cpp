// The wall observer's evaluation through `rockwatch study --alarms --observer` on a tiny plan: summary.json's observer
// object (open loop and fused scored against the true wall's verdict, the estimation errors, per case, settings), the
// fused alarm at least as good as the open loop's, the text report, the plan digest, the option rejections; and the
// scoring itself (observer_outcome) on hand-made results, against the study's own alarm scores.
#include <cstddef>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/observer_evaluation.hpp"
#include "study/run/study_observer.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_study_observer {

using rockwatch::test::describe;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace study = rockwatch::sim::study;
namespace cli = rockwatch::cli;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

// Set 3, component X and Y, horizontal only, 0.16, 0.20, 0.24 g: 6 records x levels, 96 evaluation runs (16 cases).
std::vector<std::string> tiny_plan(const std::string& out) {
  return {"--suite", kSuite, "--sets", "3", "--r", "exp", "--vertical", "without", "--pga", "0.16:0.24:0.04",
          "--alarms", "--observer", "--jobs", "2", "--out", out};
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void check_alarm_score(const nlohmann::json& a) {
  for (const char* key : {"recall", "false_alarm_rate", "lead_time_s_median", "lead_time_s_p05", "counts"}) {
    CHECK_TEXT(a.contains(key), key);
  }
}

}  // namespace

TEST_GROUP(StudyObserver){};

TEST(StudyObserver, ScoresOpenLoopAndFusedAgainstTheTrueWall) {
  TempDir dir;
  const std::string out = dir.file("study");
  std::vector<std::string> args{"study"};
  for (const std::string& a : tiny_plan(out)) args.push_back(a);
  const ProcessResult r = run_rockwatch(args);
  check_ok(r);
  const nlohmann::json summary = read_json(out + "/summary.json");
  CHECK(summary.contains("alarm"));  // the study's own alarm scores are still there
  const nlohmann::json& o = summary["observer"];
  LONGS_EQUAL(96, o["runs"].get<std::size_t>());
  LONGS_EQUAL(0, o["runs_with_error"].get<std::size_t>());
  check_alarm_score(o["open_loop"]);
  check_alarm_score(o["fused"]);
  const nlohmann::json& open = o["open_loop"];
  const nlohmann::json& fused = o["fused"];
  // Both scored against the same true verdicts.
  LONGS_EQUAL(open["counts"]["collapsed"].get<std::size_t>(), fused["counts"]["collapsed"].get<std::size_t>());
  CHECK(fused["counts"]["collapsed"].get<std::size_t>() > 0);
  CHECK(fused["recall"].get<double>() >= open["recall"].get<double>());
  CHECK(fused["recall"].get<double>() == 1.0);
  const nlohmann::json& e = o["estimation"];
  const double x_median = e["x_rms_over_x_inst"]["fused"]["median"].get<double>();
  CHECK(x_median > 0.0 && x_median < 0.02);
  CHECK(e["x_rms_over_x_inst"]["open_loop"]["median"].get<double>() > 5.0 * x_median);
  CHECK(e["r_error_after_impacts"]["runs"].get<std::size_t>() > 0);
  CHECK(e["r_error_after_impacts"].contains("within_0_02"));
  CHECK(e["r_error_final"]["median"].is_number());
  const nlohmann::json& cases = o["per_case"];
  LONGS_EQUAL(16, cases.size());
  STRCMP_EQUAL("r_ana", cases[0]["name"].get<std::string>().c_str());
  STRCMP_EQUAL("b_0.9", cases[3]["name"].get<std::string>().c_str());
  STRCMP_EQUAL("fp_3kN", cases[7]["name"].get<std::string>().c_str());
  STRCMP_EQUAL("fp_3kN+accel", cases[15]["name"].get<std::string>().c_str());
  for (const nlohmann::json& c : cases) {
    CHECK(c["estimation"].contains("x_inst_relative_error_after_impacts"));
  }
  std::size_t per_case_runs = 0;
  for (const nlohmann::json& c : cases) {
    check_alarm_score(c["fused"]);
    per_case_runs += c["runs"].get<std::size_t>();
  }
  LONGS_EQUAL(96, per_case_runs);
  const nlohmann::json& settings = o["settings"];
  DOUBLES_EQUAL(0.5e-3, settings["sensors"]["x_noise_m"].get<double>(), 0.0);
  DOUBLES_EQUAL(2e-3, settings["sensors"]["x_bias_m"].get<double>(), 0.0);
  DOUBLES_EQUAL(1.5, settings["cases"][5]["wall"]["h1_m"].get<double>(), 1e-12);
  DOUBLES_EQUAL(0.09, settings["cases"][3]["wall"]["b_m"].get<double>(), 1e-12);
  CHECK(settings["cases"][3]["accel_noise_mps2"].is_null());
  DOUBLES_EQUAL(0.05, settings["cases"][11]["accel_noise_mps2"].get<double>(), 0.0);
  // The plan description (what --resume compares) includes the evaluation.
  CHECK(read_json(out + "/study.json")["plan"].contains("observer"));
  CHECK(r.out.find("Wall observer evaluation: 96 runs (16 mismatch cases)") != std::string::npos);
  CHECK(r.out.find("fused") != std::string::npos);
}

TEST(StudyObserver, RefusesTheObserverWithoutTheAlarmAndItsSettingsWithoutIt) {
  TempDir dir;
  expect_command_rejected("study", {"--observer", "--out", dir.file("a")}, {"--observer", "give --alarms too"});
  expect_command_rejected("study", {"--alarms", "--observer-gate-chi2", "9", "--out", dir.file("a")},
                          {"--observer-gate-chi2", "give --observer too"});
  expect_command_rejected("study", {"--alarms", "--observer", "--observer-x-noise-m", "1", "--out", dir.file("a")},
                          {"--observer-x-noise-m must be in [1e-06, 0.1] m"});
}

TEST(StudyObserver, ScoringUsesTheTrueVerdictAndTheStudysAlarmDefinitions) {
  // Two records at one level, one case: hand-made results.
  study::StudyPlan plan;
  plan.records.resize(2);
  plan.pga_g = {0.2};
  plan.vertical = {false};
  study::ObserverEvaluationPlan evaluation;
  evaluation.cases.resize(1);
  std::vector<study::ObserverRunResult> results(2);
  // Run 0: the true wall collapses at 5 s; open loop never IMMINENT, fused IMMINENT at 4 s.
  results[0].done = true;
  results[0].true_collapsed = true;
  results[0].true_t_collapse_s = 5.0;
  results[0].true_r = 0.99;
  results[0].true_x_inst_m = 0.1;
  results[0].fused_t_first_imminent_s = 4.0;
  results[0].fused_x_rms_error_m = 0.001;
  results[0].open_x_rms_error_m = 0.05;
  results[0].r_estimate = 0.98;
  results[0].r_estimate_after_impacts = 0.95;
  results[0].fused_impacts = 7;
  // Run 1: the true wall survives; the open loop says IMMINENT (a false alarm), the fused wall does not.
  results[1].done = true;
  results[1].true_x_inst_m = 0.1;
  results[1].true_r = 0.9;
  results[1].open_t_first_imminent_s = 3.0;
  results[1].fused_x_rms_error_m = 0.003;
  results[1].fused_impacts = 3;  // fewer than 5: no r score
  results[1].r_estimate_after_impacts = 0.5;
  const study::ObserverOutcome o = study::observer_outcome(plan, evaluation, results);
  DOUBLES_EQUAL(0.0, *o.all.open_loop.recall, 0.0);
  DOUBLES_EQUAL(1.0, *o.all.open_loop.false_alarm_rate, 0.0);
  DOUBLES_EQUAL(1.0, *o.all.fused.recall, 0.0);
  DOUBLES_EQUAL(0.0, *o.all.fused.false_alarm_rate, 0.0);
  DOUBLES_EQUAL(1.0, *o.all.fused.lead_time_s_median, 1e-12);
  LONGS_EQUAL(2, o.all.fused_x_rms_over_x_inst.n);
  DOUBLES_EQUAL(0.02, *o.all.fused_x_rms_over_x_inst.median, 1e-12);  // (0.01 + 0.03) / 2
  LONGS_EQUAL(1, o.all.fused_x_within_2_percent);  // 0.01 and 0.03 of x_inst
  LONGS_EQUAL(1, o.all.r_error_after_impacts.n);
  DOUBLES_EQUAL(0.04, *o.all.r_error_after_impacts.median, 1e-12);
  DOUBLES_EQUAL(0.01, *o.all.r_error_final.median, 1e-12);
  LONGS_EQUAL(0, o.all.r_within_0_02);
  LONGS_EQUAL(1, o.per_case.size());
  const nlohmann::ordered_json j = cli::observer_summary_json(evaluation, o);
  CHECK(j["open_loop"]["lead_time_s_median"].is_null());
  DOUBLES_EQUAL(1.0, j["fused"]["recall"].get<double>(), 0.0);
}

}  // namespace unity_test_study_observer
