// The instability alarm through `rockwatch study --alarms`: the alarm scored against the verdicts (recall, false
// alarms, lead times recomputed from runs.csv), the files independent of --jobs and resumable; the summary's alarm and
// fixed-vs-double arithmetic and runs.csv's fixed-point columns checked on hand-made results.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/sample_engine.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/engine_comparison.hpp"
#include "rockwatch/sim/study/quantile.hpp"
#include "study/outputs/study_runs_csv.hpp"
#include "study/report/study_summary.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_study_alarm {

using rockwatch::options::split_fields;
using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;
namespace study = rockwatch::sim::study;
namespace cli = rockwatch::cli;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;
const char* const kElCentro180 = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2";

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

}  // namespace

namespace {

// Set 1 (records X and Y), r_exp, horizontal only, PGA 0.14 to 0.30 g: survivors and collapses.
std::vector<std::string> alarm_study(const std::string& out) {
  return {"study", "--suite", kSuite, "--sets", "1", "--r", "exp", "--vertical", "without", "--pga", "0.14:0.30:0.02",
          "--alarms", "--out", out};
}

struct Row {
  bool collapsed = false;
  std::optional<double> t_collapse_s, t_first_imminent_s;
};

std::vector<Row> read_alarm_rows(const std::string& path) {
  std::vector<std::string> lines = split_fields(slurp(path), '\n');
  lines.pop_back();  // after the final newline
  STRCMP_EQUAL("record,component,vertical,r,pga_g,collapsed,t_collapse_s,t_exceed_s,max_abs_x_m,n_impacts,run,"
               "t_first_imminent_s,error",
               lines.front().c_str());
  std::vector<Row> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = split_fields(lines[i], ',');
    LONGS_EQUAL(13, f.size());
    CHECK_TRUE(f[12].empty());
    Row r;
    r.collapsed = f[5] == "true";
    if (!f[6].empty()) r.t_collapse_s = std::stod(f[6]);
    if (!f[11].empty()) r.t_first_imminent_s = std::stod(f[11]);
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

TEST_GROUP(StudyAlarm){};

TEST(StudyAlarm, SummaryScoresTheAlarmAsRunsCsvSays) {
  const TempDir tmp;
  const std::string one = tmp.file("one"), two = tmp.file("two");
  const ProcessResult r = run_rockwatch(with(alarm_study(one), {"--jobs", "1"}));
  check_ok(r);
  for (const char* text : {"alarm", "recall", "false alarms", "lead time median"}) STRCMP_CONTAINS(text, r.out.c_str());

  const std::vector<Row> rows = read_alarm_rows(one + "/runs.csv");
  LONGS_EQUAL(18, rows.size());
  std::size_t collapsed = 0, flagged = 0, survivors = 0, false_alarms = 0;
  std::vector<double> leads;
  for (const Row& row : rows) {
    if (row.collapsed) {
      ++collapsed;
      CHECK_TRUE(row.t_collapse_s.has_value());
      CHECK_TRUE(row.t_first_imminent_s.has_value());  // COLLAPSED is above IMMINENT: at the latest, at the collapse
      CHECK_TRUE(*row.t_first_imminent_s <= *row.t_collapse_s);
      if (*row.t_first_imminent_s < *row.t_collapse_s) {
        ++flagged;
        leads.push_back(*row.t_collapse_s - *row.t_first_imminent_s);
      }
    } else {
      ++survivors;
      false_alarms += row.t_first_imminent_s ? 1 : 0;
    }
  }
  CHECK_TRUE(collapsed > 0 && survivors > 0);

  const nlohmann::json summary = nlohmann::json::parse(slurp(one + "/summary.json"));
  const nlohmann::json& a = summary["alarm"];
  for (const char* key : {"recall", "false_alarm_rate", "lead_time_s_median", "lead_time_s_p05"}) {
    CHECK_TEXT(a.contains(key) && a[key].is_number(), key);
  }
  const double recall = a["recall"].get<double>(), far = a["false_alarm_rate"].get<double>();
  CHECK_TRUE(recall >= 0.0 && recall <= 1.0);
  CHECK_TRUE(far >= 0.0 && far <= 1.0);
  DOUBLES_EQUAL(double(flagged) / double(collapsed), recall, 1e-15);
  DOUBLES_EQUAL(double(false_alarms) / double(survivors), far, 1e-15);
  LONGS_EQUAL(collapsed, a["counts"]["collapsed"].get<std::size_t>());
  LONGS_EQUAL(flagged, a["counts"]["collapsed_flagged"].get<std::size_t>());
  LONGS_EQUAL(survivors, a["counts"]["survivors"].get<std::size_t>());
  LONGS_EQUAL(false_alarms, a["counts"]["survivors_flagged"].get<std::size_t>());
  const double median = a["lead_time_s_median"].get<double>(), p05 = a["lead_time_s_p05"].get<double>();
  CHECK_TRUE(p05 > 0.0 && p05 <= median);
  CHECK_TRUE(median < 30.0);  // the records are 20 s long
  std::sort(leads.begin(), leads.end());
  DOUBLES_EQUAL(*study::quantile_type7(leads, 0.5), median, 1e-12);
  DOUBLES_EQUAL(*study::quantile_type7(leads, 0.05), p05, 1e-12);
  DOUBLES_EQUAL(1.5, a["settings"]["energy_margin"].get<double>(), 0.0);
  STRCMP_EQUAL("double", summary["plan"]["arithmetic"].get<std::string>().c_str());
  DOUBLES_EQUAL(0.4, summary["plan"]["alarm"]["lambda_warning"].get<double>(), 0.0);
  CHECK_FALSE(summary.contains("fixed_vs_double"));

  // Two threads: the same files, byte for byte.
  check_ok(run_rockwatch(with(alarm_study(two), {"--jobs", "2"})));
  for (const char* name : {"runs.csv", "summary.json", "table3.md"}) {
    CHECK_TEXT(slurp(one + "/" + name) == slurp(two + "/" + name), name);
  }

  // Resume after losing the last rows reads the alarm column back and ends with the same files.
  const std::string runs = slurp(one + "/runs.csv"), summary_text = slurp(one + "/summary.json");
  std::vector<std::string> lines = split_fields(runs, '\n');
  std::string kept;
  for (std::size_t i = 0; i < 10; ++i) kept += lines[i] + "\n";
  rockwatch::test::write_text(one + "/runs.csv", kept);
  check_ok(run_rockwatch(with(alarm_study(one), {"--jobs", "2", "--resume"})));
  CHECK_TRUE(slurp(one + "/runs.csv") == runs);
  CHECK_TRUE(slurp(one + "/summary.json") == summary_text);

  // The alarm settings are part of the plan: resuming with others is another study.
  const std::vector<std::string> again = with(alarm_study(one), {"--resume", "--energy-margin", "1.25"});
  rockwatch::test::expect_command_rejected("study", std::vector<std::string>(again.begin() + 1, again.end()),
                                           {"alarm", "energy_margin"});
}

TEST(StudyAlarm, LargerEnergyMarginsNeverRaiseMoreAlarms) {
  const TempDir tmp;
  double previous_far = 2.0, previous_recall = 2.0;
  for (const char* margin : {"1", "1.5", "100"}) {
    const std::string dir = tmp.file(std::string("m") + margin);
    check_ok(run_rockwatch(with(alarm_study(dir), {"--energy-margin", margin, "--jobs", "2"})));
    const nlohmann::json a = nlohmann::json::parse(slurp(dir + "/summary.json"))["alarm"];
    const double far = a["false_alarm_rate"].get<double>(), recall = a["recall"].get<double>();
    CHECK_TRUE(far <= previous_far);
    CHECK_TRUE(recall <= previous_recall);
    previous_far = far;
    previous_recall = recall;
  }
}

TEST(StudyAlarm, WithoutAlarmsTheFilesHaveNoAlarmFields) {
  const TempDir tmp;
  const std::string dir = tmp.file("plain");
  std::vector<std::string> args = alarm_study(dir);
  args.erase(std::find(args.begin(), args.end(), "--alarms"));
  check_ok(run_rockwatch(args));
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir + "/summary.json"));
  CHECK_FALSE(summary.contains("alarm"));
  CHECK_TRUE(summary["plan"]["alarm"].is_null());
  CHECK_TRUE(slurp(dir + "/runs.csv").find("t_first_imminent_s") == std::string::npos);
}

TEST(StudyAlarm, FixedPointStudyIsComparedWithTheDoubleEngine) {
  const TempDir tmp;
  const std::string one = tmp.file("one"), two = tmp.file("two");
  const std::vector<std::string> args = with(alarm_study(one), {"--arith", "fixed", "--dt-check"});
  const ProcessResult r = run_rockwatch(with(args, {"--jobs", "1"}));
  check_ok(r);
  STRCMP_CONTAINS("fixed vs double", r.out.c_str());
  STRCMP_CONTAINS("fixed engine; verdicts of the double engine", r.out.c_str());

  std::vector<std::string> lines = split_fields(slurp(one + "/runs.csv"), '\n');
  lines.pop_back();
  STRCMP_EQUAL("record,component,vertical,r,pga_g,collapsed,t_collapse_s,t_exceed_s,max_abs_x_m,n_impacts,run,"
               "t_first_imminent_s,saturated,collapsed_double,t_collapse_double_s,max_abs_x_double_m,"
               "t_first_imminent_double_s,verdict_differs,t_first_imminent_published_s,imminent_late_samples,"
               "max_late_samples,shed_samples,overrun_calls,max_call_units,collapsed_reference,max_abs_x_reference_m,error",
               lines.front().c_str());
  LONGS_EQUAL(19, lines.size());
  std::vector<std::size_t> flips, flips_at_half_step;
  std::size_t collapsed_double = 0, survivors_both = 0, survivors_within = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = split_fields(lines[i], ',');
    if (f[5] == "false" && f[13] == "false") {
      ++survivors_both;
      if (std::fabs(std::stod(f[8]) - std::stod(f[15])) <= 5e-4) ++survivors_within;
    }
    LONGS_EQUAL(27, f.size());
    // As the monitor publishes it: never before the step end it was computed for, and only when computed.
    CHECK_EQUAL(f[11].empty(), f[18].empty());
    if (!f[18].empty()) CHECK_TRUE(std::stod(f[18]) >= std::stod(f[11]));
    CHECK_TRUE(std::stoul(f[20]) >= std::stoul(f[19]));  // the most samples waited >= the IMMINENT's wait
    // The default policy sheds: a call overruns only when a sample's trials alone exceed the budget (never here).
    STRCMP_EQUAL("0", f[22].c_str());
    CHECK_TRUE(std::stol(f[23]) <= rockwatch::core::kDefaultWorkBudgetUnits);  // the most work in a call
    CHECK_TRUE(!f[25].empty() && std::stod(f[25]) >= 0.0);  // max |x| at the reference step
    CHECK_TRUE(f[26].empty());
    CHECK_EQUAL(f[5] != f[13], f[17] == "true");
    if (f[17] == "true") {
      flips.push_back(i - 1);
      if (f[24] != f[13]) flips_at_half_step.push_back(i - 1);
    }
    collapsed_double += f[13] == "true" ? 1 : 0;
    CHECK_EQUAL(f[13] == "true", !f[14].empty());
    CHECK_TRUE(std::stod(f[15]) >= 0.0);
  }
  const nlohmann::json summary = nlohmann::json::parse(slurp(one + "/summary.json"));
  STRCMP_EQUAL("fixed", summary["plan"]["arithmetic"].get<std::string>().c_str());
  const nlohmann::json& c = summary["fixed_vs_double"];
  LONGS_EQUAL(18, c["runs_compared"].get<std::size_t>());
  LONGS_EQUAL(18 - flips.size(), c["verdicts_same"].get<std::size_t>());
  CHECK_TRUE(c["verdict_flips"] == nlohmann::json(flips));
  CHECK_TRUE(c["flips_also_at_reference"] == nlohmann::json(flips_at_half_step));
  CHECK_TRUE(c["max_abs_x_diff_m_max"].get<double>() >= 0.0);
  CHECK_TRUE(c["first_imminent_diff_samples_max"].is_number_unsigned());
  LONGS_EQUAL(survivors_both, c["survivors_compared"].get<std::size_t>());
  LONGS_EQUAL(survivors_within, c["survivors_within_0_5_mm"].get<std::size_t>());
  CHECK_TRUE(c["imminent_within_one_step"].get<std::size_t>() <= c["imminent_compared"].get<std::size_t>());
  LONGS_EQUAL(collapsed_double, summary["alarm"]["counts"]["collapsed"].get<std::size_t>());
  STRCMP_EQUAL("fixed", summary["alarm"]["alarm_engine"].get<std::string>().c_str());
  const nlohmann::json& published = summary["alarm"]["as_published"];
  LONGS_EQUAL(collapsed_double, published["counts"]["collapsed"].get<std::size_t>());
  CHECK_TRUE(published["counts"]["collapsed_flagged"].get<std::size_t>() <= collapsed_double);
  CHECK_TRUE(published["max_late_samples"].is_number_unsigned());
  LONGS_EQUAL(rockwatch::core::kDefaultWorkBudgetUnits, published["work_budget_units"].get<long>());
  STRCMP_EQUAL("shed", published["work_overflow"].get<std::string>().c_str());
  LONGS_EQUAL(0, published["overrun_calls"].get<long>());
  CHECK_TRUE(summary["plan"]["alarm"].find("work_overflow") == summary["plan"]["alarm"].end());  // digest unchanged
  STRCMP_CONTAINS("as the firmware's monitor publishes it", r.out.c_str());

  check_ok(run_rockwatch(with(with(alarm_study(two), {"--arith", "fixed", "--dt-check"}), {"--jobs", "2"})));
  for (const char* name : {"runs.csv", "summary.json", "table3.md"}) {
    CHECK_TEXT(slurp(one + "/" + name) == slurp(two + "/" + name), name);
  }
  // Resume reads the fixed-point columns back.
  const std::string runs = slurp(one + "/runs.csv"), summary_text = slurp(one + "/summary.json");
  std::string kept;
  for (std::size_t i = 0; i < 7; ++i) kept += lines[i] + "\n";
  rockwatch::test::write_text(one + "/runs.csv", kept);
  check_ok(run_rockwatch(with(args, {"--jobs", "2", "--resume"})));
  CHECK_TRUE(slurp(one + "/runs.csv") == runs);
  CHECK_TRUE(slurp(one + "/summary.json") == summary_text);
}

// The firmware's policy at a full queue (--work-overflow): a wall settling at r_ana chatters long enough to fill the
// queue. shed (default): every call within the budget, samples shed; finish: nothing shed, calls overrun; the computed
// answers are the same either way, and the policy is part of the plan (a resume with the other is refused).
TEST(StudyAlarm, TheWorkOverflowPolicyTradesShedSamplesForOverrunCalls) {
  const TempDir tmp;
  const std::string shed = tmp.file("shed"), finish = tmp.file("finish");
  const std::vector<std::string> base = {"study", "--suite", kSuite, "--sets", "1", "--r", "ana", "--vertical",
                                         "without", "--pga", "0.12:0.12:0.01", "--alarms", "--arith", "fixed", "--jobs", "1"};
  check_ok(run_rockwatch(with(base, {"--out", shed})));
  const ProcessResult r = run_rockwatch(with(base, {"--out", finish, "--work-overflow", "finish"}));
  check_ok(r);
  STRCMP_CONTAINS("finish at a full queue", r.out.c_str());
  std::vector<std::string> a = split_fields(slurp(shed + "/runs.csv"), '\n'), b = split_fields(slurp(finish + "/runs.csv"), '\n');
  LONGS_EQUAL(4, a.size());  // header, X, Y, the final newline's empty field
  CHECK_TRUE(a[0] == b[0]);
  std::size_t shed_total = 0, overruns_total = 0;
  for (std::size_t i = 1; i < 3; ++i) {
    const std::vector<std::string> fa = split_fields(a[i], ','), fb = split_fields(b[i], ',');
    for (std::size_t k = 0; k <= 17; ++k) CHECK_TEXT(fa[k] == fb[k], ("computed column " + std::to_string(k)).c_str());
    shed_total += std::stoul(fa[21]);
    STRCMP_EQUAL("0", fa[22].c_str());
    CHECK_TRUE(std::stol(fa[23]) <= rockwatch::core::kDefaultWorkBudgetUnits);
    STRCMP_EQUAL("0", fb[21].c_str());
    overruns_total += std::stoul(fb[22]);
    if (std::stoul(fb[22]) > 0) CHECK_TRUE(std::stol(fb[23]) > rockwatch::core::kDefaultWorkBudgetUnits);
  }
  CHECK_TRUE(shed_total > 0);
  CHECK_TRUE(overruns_total > 0);
  const nlohmann::json summary = nlohmann::json::parse(slurp(finish + "/summary.json"));
  STRCMP_EQUAL("finish", summary["plan"]["alarm"]["work_overflow"].get<std::string>().c_str());
  STRCMP_EQUAL("finish", summary["alarm"]["as_published"]["work_overflow"].get<std::string>().c_str());
  LONGS_EQUAL(overruns_total, summary["alarm"]["as_published"]["overrun_calls"].get<std::size_t>());
  LONGS_EQUAL(0, summary["alarm"]["as_published"]["shed_samples"].get<long>());
  rockwatch::test::expect_command_rejected(
      "study", {"--suite", kSuite, "--sets", "1", "--r", "ana", "--vertical", "without", "--pga", "0.12:0.12:0.01", "--alarms",
                "--arith", "fixed", "--jobs", "1", "--out", shed, "--resume", "--work-overflow", "finish"},
      {"work_overflow"});
  rockwatch::test::expect_command_rejected("study", {"--suite", kSuite, "--alarms", "--work-overflow", "finish",
                                                     "--out", tmp.file("x")},
                                           {"--work-overflow", "--arith fixed --alarms"});
  rockwatch::test::expect_command_rejected("study", {"--suite", kSuite, "--alarms", "--arith", "fixed",
                                                     "--work-overflow", "later", "--out", tmp.file("y")},
                                           {"--work-overflow must be shed or finish", "'later'"});
}

TEST(StudyAlarm, HelpListsTheOptionsAndTheKeys) {
  const ProcessResult r = run_rockwatch({"study", "--help"});
  check_ok(r);
  for (const char* text : {"--arith", "--alarms", "--lambda-w", "--alarm-hold", "--energy-margin", "recall",
                           "false_alarm_rate", "lead_time_s_p05", "fixed_vs_double", "t_first_imminent_s",
                           "collapsed_double", "verdict_differs", "type 7", "--work-overflow", "overrun_calls",
                           "max_call_units"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
}

// The summary's arithmetic on hand-made results: no engine involved, so every number is known.
TEST_GROUP(StudyAlarmArithmetic) {
  study::StudyPlan plan;
  void setup() override {
    study::StudyRecord r;
    r.name = "rec";
    r.component = "X";
    r.dt_s = 0.01;  // ten integration steps of 1 ms per sample (the default max step)
    r.ug_mps2 = {0.0, 1.0, 0.0};
    r.peak_ug_mps2 = 1.0;
    plan.records.push_back(r);
    plan.pga_g = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
    plan.restitutions = {{rockwatch::core::Restitution{rockwatch::core::RestitutionKind::exp, 0.0}, "exp"}};
    plan.vertical = {false};
    plan.analysis.evaluate_alarm = true;
  }
};

// The quantile and the alarm scores themselves: tests/sim/test_study_statistics.cpp.

TEST(StudyAlarmArithmetic, FixedAgainstDouble) {
  plan.analysis.arithmetic = sim::Arithmetic::fixed_point;
  plan.dt_check = true;
  std::vector<study::RunResult> results(6);
  for (study::RunResult& r : results) r.done = true;
  // 0: both survive, max |x| 0.010 vs 0.012; IMMINENT 3 record samples apart (0.03 s at 0.01 s; the alarm runs once
  // per sample).
  results[0].max_abs_x_m = 0.010;
  results[0].t_first_imminent_s = 1.000;
  results[0].reference = study::DoubleReference{false, std::nullopt, 0.012, 1.030};
  results[0].collapsed_reference = false;
  // 1: both collapse.
  results[1].collapsed = true;
  results[1].t_collapse_s = 3.0;
  results[1].reference = study::DoubleReference{true, 3.01, 0.2, std::nullopt};
  results[1].collapsed_reference = true;
  // 2: fixed collapses, double survives, and survives at half the step too: a flip of the fixed engine's own.
  results[2].collapsed = true;
  results[2].reference = study::DoubleReference{false, std::nullopt, 0.09, std::nullopt};
  results[2].collapsed_reference = false;
  // 3: fixed survives, double collapses but survives at half the step: the double verdict itself is fragile.
  results[3].max_abs_x_m = 0.05;
  results[3].saturated = true;
  results[3].reference = study::DoubleReference{true, 7.0, 0.2, std::nullopt};
  results[3].collapsed_reference = false;
  // 4: both survive, max |x| 0.020 vs 0.0205.
  results[4].max_abs_x_m = 0.020;
  results[4].reference = study::DoubleReference{false, std::nullopt, 0.0205, 2.0};
  results[4].collapsed_reference = false;
  // 5: refused.
  results[5].error = "out of range";
  const study::FixedComparison f = study::fixed_comparison(plan, results);
  LONGS_EQUAL(5, f.runs_compared);
  LONGS_EQUAL(3, f.verdicts_same);
  LONGS_EQUAL(2, f.verdict_flips.size());
  LONGS_EQUAL(2, f.verdict_flips[0]);
  LONGS_EQUAL(3, f.verdict_flips[1]);
  LONGS_EQUAL(1, f.flips_also_at_reference.size());
  LONGS_EQUAL(3, f.flips_also_at_reference[0]);
  DOUBLES_EQUAL(0.002, *f.max_abs_x_diff_m_max, 1e-15);
  LONGS_EQUAL(3, *f.first_imminent_diff_samples_max);
  LONGS_EQUAL(1, f.runs_saturated);

  // The dt check compares the half-step run (double) with the double verdict: runs 3 only.
  const cli::StudyOutcome o = cli::summarise_study(plan, results, cli::StaticCapacities{0.139, 0.180, false});
  LONGS_EQUAL(1, o.flipped_runs.size());
  LONGS_EQUAL(3, o.flipped_runs[0]);
  CHECK_TRUE(o.fixed_vs_double.has_value());
  CHECK_TRUE(o.alarm.has_value());
}

TEST(StudyAlarmArithmetic, RunsCsvOfAFixedPointStudyReadsBackWhatWasWritten) {
  plan.analysis.arithmetic = sim::Arithmetic::fixed_point;
  plan.dt_check = true;
  std::vector<study::RunResult> results(6);
  results[0].done = true;
  results[0].collapsed = true;
  results[0].t_collapse_s = 4.25;
  results[0].t_exceed_s = 4.0;
  results[0].max_abs_x_m = 0.2006552;
  results[0].n_impacts = 7;
  results[0].t_first_imminent_s = 3.125;
  results[0].saturated = true;
  results[0].reference = study::DoubleReference{false, std::nullopt, 0.0931, 3.13};
  results[0].t_first_imminent_published_s = 3.135;
  results[0].imminent_late_samples = 2;
  results[0].max_late_samples = 17;
  results[0].shed_samples = 1;
  results[0].overrun_calls = 3;
  results[0].max_call_units = 398750;
  results[0].collapsed_reference = false;
  results[0].max_abs_x_reference_m = 0.0932;
  results[2].done = true;
  results[2].max_abs_x_m = 0.01;
  results[2].reference = study::DoubleReference{false, std::nullopt, 0.0101, std::nullopt};
  results[2].collapsed_reference = false;
  results[3].done = true;
  results[3].error = "refused, with a comma";

  std::ostringstream text;
  cli::write_runs_csv(text, plan, results);
  const std::vector<std::string> lines = split_fields(text.str(), '\n');
  STRCMP_EQUAL("record,component,vertical,r,pga_g,collapsed,t_collapse_s,t_exceed_s,max_abs_x_m,n_impacts,run,"
               "t_first_imminent_s,saturated,collapsed_double,t_collapse_double_s,max_abs_x_double_m,"
               "t_first_imminent_double_s,verdict_differs,t_first_imminent_published_s,imminent_late_samples,"
               "max_late_samples,shed_samples,overrun_calls,max_call_units,collapsed_reference,max_abs_x_reference_m,error",
               lines[0].c_str());
  STRCMP_EQUAL("rec,X,false,exp,0.1,true,4.25,4,0.2006552,7,0,3.125,true,false,,0.0931,3.13,true,3.135,2,17,1,3,398750,"
               "false,0.0932,",
               lines[1].c_str());
  STRCMP_EQUAL("rec,X,false,exp,0.4,,,,,,3,,,,,,,,,,,,,,,,\"refused, with a comma\"", lines[3].c_str());

  const TempDir tmp;
  rockwatch::test::write_text(tmp.file("runs.csv"), text.str());
  std::vector<study::RunResult> back;
  LONGS_EQUAL(3, cli::read_runs_csv(tmp.file("runs.csv"), plan, back));
  for (const std::size_t i : {0U, 2U, 3U}) {
    const study::RunResult& a = results[i];
    const study::RunResult& b = back[i];
    CHECK_TRUE(b.done);
    CHECK_EQUAL(a.collapsed, b.collapsed);
    CHECK_TRUE(a.t_collapse_s == b.t_collapse_s && a.t_exceed_s == b.t_exceed_s);
    DOUBLES_EQUAL(a.max_abs_x_m, b.max_abs_x_m, 0.0);
    CHECK_TRUE(a.t_first_imminent_s == b.t_first_imminent_s);
    CHECK_TRUE(a.t_first_imminent_published_s == b.t_first_imminent_published_s);
    LONGS_EQUAL(a.imminent_late_samples, b.imminent_late_samples);
    LONGS_EQUAL(a.max_late_samples, b.max_late_samples);
    LONGS_EQUAL(a.shed_samples, b.shed_samples);
    LONGS_EQUAL(a.overrun_calls, b.overrun_calls);
    LONGS_EQUAL(a.max_call_units, b.max_call_units);
    CHECK_EQUAL(a.saturated, b.saturated);
    CHECK_EQUAL(a.reference.has_value(), b.reference.has_value());
    if (a.reference) {
      CHECK_EQUAL(a.reference->collapsed, b.reference->collapsed);
      CHECK_TRUE(a.reference->t_collapse_s == b.reference->t_collapse_s);
      DOUBLES_EQUAL(a.reference->max_abs_x_m, b.reference->max_abs_x_m, 0.0);
      CHECK_TRUE(a.reference->t_first_imminent_s == b.reference->t_first_imminent_s);
    }
    CHECK_TRUE(a.collapsed_reference == b.collapsed_reference);
    CHECK_TRUE(a.max_abs_x_reference_m == b.max_abs_x_reference_m);
    STRCMP_EQUAL(a.error.c_str(), b.error.c_str());
  }
  CHECK_FALSE(back[1].done);

  // verdict_differs must agree with the two verdicts it summarises.
  std::string edited = text.str();
  edited.replace(edited.find("3.13,true,3.135,"), 16, "3.13,false,3.135,");
  rockwatch::test::write_text(tmp.file("edited.csv"), edited);
  std::vector<study::RunResult> none;
  try {
    cli::read_runs_csv(tmp.file("edited.csv"), plan, none);
    FAIL("an inconsistent verdict_differs was accepted");
  } catch (const std::exception& e) {
    STRCMP_CONTAINS("verdict_differs", e.what());
  }
}

}  // namespace unity_test_study_alarm
