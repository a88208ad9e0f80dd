// `rockwatch study --forecast` (issue 29 item 4) on a tiny plan: summary.json's forecast object and its figures
// recomputed from forecast.csv (Brier, base rate, skill, reliability bins, the baseline's Brier, each outcome from
// the run's collapse time), the reliability figure, the text report and the option rejections; and the
// leave-one-record-out scoring (forecast_outcome) on hand-made runs whose answers are known.
#include <cmath>
#include <cstddef>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/sim/study/forecast_evaluation.hpp"
#include "study/report/study_forecast.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_study_forecast {

using rockwatch::test::describe;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace study = rockwatch::sim::study;
namespace cli = rockwatch::cli;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;

// Sets 3 and 4 (two records, so leave one out works), X and Y, horizontal only, r_exp, 0.2, 0.25, 0.3 g: 12 runs;
// 20 members over 2 s, a forecast every 0.5 s.
std::vector<std::string> tiny_plan(const std::string& out) {
  return {"study", "--suite", kSuite, "--sets", "3,4", "--r", "exp", "--vertical", "without", "--pga", "0.2:0.3:0.05",
          "--forecast", "--forecast-members", "20", "--forecast-horizon-s", "2", "--forecast-every-s", "0.5",
          "--jobs", "2", "--out", out};
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) header.push_back(f);
  }
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::size_t start = 0;
    for (const std::string& h : header) {
      const std::size_t comma = line.find(',', start);
      row[h] = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      start = comma == std::string::npos ? line.size() : comma + 1;
    }
    rows.push_back(row);
  }
  return rows;
}

study::ForecastPoint point(double t, double p, bool outcome, double e = 0.0, double xr = 0.0) {
  study::ForecastPoint f;
  f.t_s = t;
  f.p_collapse = p;
  f.outcome = outcome;
  f.energy_ratio_max = e;
  f.x_over_x_inst = xr;
  return f;
}

}  // namespace

TEST_GROUP(StudyForecast){};

TEST(StudyForecast, SummaryFiguresAreThoseOfTheForecastsInTheCsv) {
  TempDir dir;
  const std::string out = dir.file("study");
  const ProcessResult r = run_rockwatch(tiny_plan(out));
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  CHECK_TEXT(r.out.find("Ensemble forecast evaluation") != std::string::npos, what.c_str());
  CHECK_TEXT(r.out.find("forecast_reliability.png") != std::string::npos, what.c_str());
  std::ifstream png(out + "/forecast_reliability.png", std::ios::binary);
  CHECK_TEXT(png.good(), "forecast_reliability.png written");
  const nlohmann::json f = read_json(out + "/summary.json")["forecast"];
  LONGS_EQUAL(12, f["runs"].get<long>());
  LONGS_EQUAL(2, f["record_groups"].get<long>());
  LONGS_EQUAL(20, f["settings"]["members"].get<long>());
  const auto rows = read_csv(out + "/forecast.csv");
  LONGS_EQUAL(static_cast<long>(rows.size()), f["forecasts"].get<long>());
  CHECK(rows.size() > 20);

  double brier = 0.0, brier_b = 0.0;
  std::size_t positives = 0;
  std::vector<std::size_t> n(10, 0);
  std::vector<double> sum_p(10, 0.0), sum_o(10, 0.0);
  for (const auto& row : rows) {
    const double t = std::stod(row.at("t_s")), p = std::stod(row.at("p_collapse"));
    const int o = std::stoi(row.at("outcome"));
    // The outcome is the run's own: collapse in (t, t + 2 s].
    const bool collapsed = row.at("collapsed") == "true";
    const bool expected = collapsed && t < std::stod(row.at("t_collapse_s")) &&
                          std::stod(row.at("t_collapse_s")) <= t + 2.0 + 1e-9;
    LONGS_EQUAL(expected ? 1 : 0, o);
    CHECK(p >= 0.0 && p <= 1.0);
    // P is a count of 20 members.
    DOUBLES_EQUAL(std::round(p * 20.0), p * 20.0, 1e-9);
    brier += (p - o) * (p - o);
    const double b = std::stod(row.at("baseline_p"));
    CHECK(b > 0.0 && b < 1.0);
    brier_b += (b - o) * (b - o);
    positives += static_cast<std::size_t>(o);
    const int bin = std::min(9, static_cast<int>(std::floor(p * 10.0 + 1e-12)));
    ++n[static_cast<std::size_t>(bin)];
    sum_p[static_cast<std::size_t>(bin)] += p;
    sum_o[static_cast<std::size_t>(bin)] += o;
  }
  const double count = double(rows.size());
  const double base = double(positives) / count;
  CHECK(positives > 0 && positives < rows.size());
  DOUBLES_EQUAL(base, f["base_rate"].get<double>(), 1e-12);
  DOUBLES_EQUAL(brier / count, f["brier"].get<double>(), 1e-12);
  DOUBLES_EQUAL(base * (1.0 - base), f["brier_base_rate"].get<double>(), 1e-12);
  DOUBLES_EQUAL(1.0 - (brier / count) / (base * (1.0 - base)), f["brier_skill"].get<double>(), 1e-9);
  DOUBLES_EQUAL(brier_b / count, f["baseline"]["brier"].get<double>(), 1e-9);
  DOUBLES_EQUAL(1.0 - brier / brier_b, f["brier_skill_vs_baseline"].get<double>(), 1e-9);
  std::size_t k = 0;
  for (std::size_t b = 0; b < 10; ++b) {
    if (n[b] == 0) continue;
    const nlohmann::json& bin = f["reliability"][k++];
    LONGS_EQUAL(static_cast<long>(n[b]), bin["n"].get<long>());
    DOUBLES_EQUAL(sum_p[b] / double(n[b]), bin["mean_p"].get<double>(), 1e-12);
    DOUBLES_EQUAL(sum_o[b] / double(n[b]), bin["observed"].get<double>(), 1e-12);
  }
  LONGS_EQUAL(static_cast<long>(k), static_cast<long>(f["reliability"].size()));
  // The lead scores cover every run, and the goals are judged.
  const nlohmann::json& lead = f["lead"];
  for (const char* rule : {"ensemble_5_percent", "baseline_5_percent", "imminent", "ensemble_at_imminent_false_alarms",
                           "baseline_at_imminent_false_alarms"}) {
    LONGS_EQUAL(f["surviving_runs"].get<long>(), lead[rule]["survivors"].get<long>());
    LONGS_EQUAL(f["collapsing_runs"].get<long>(), lead[rule]["collapsed"].get<long>());
  }
  for (const char* goal : {"calibrated", "skill_above_baseline", "longer_lead_than_imminent_at_no_more_false_alarms"}) {
    CHECK_TEXT(f["goals"][goal].is_boolean(), goal);
    CHECK_TEXT(f["goals_raw_ensemble"][goal].is_boolean(), goal);
  }
  // The calibrated P (SPEC §10 "Calibrated P") beside the raw one, judged by `goals`.
  const nlohmann::json& c = f["calibrated"];
  CHECK(c["brier"].is_number());
  // Its figures recomputed from forecast.csv's p_calibrated (issue 42: only is_number before): Brier, skill against
  // the base rate and the baseline, the reliability bins.
  {
    double brier_c = 0.0;
    std::vector<std::size_t> nc(10, 0);
    std::vector<double> pc_sum(10, 0.0), oc_sum(10, 0.0);
    for (const auto& row : rows) {
      const double pc = std::stod(row.at("p_calibrated"));
      const int o = std::stoi(row.at("outcome"));
      CHECK(pc > 0.0 && pc < 1.0);
      brier_c += (pc - o) * (pc - o);
      const auto bin = static_cast<std::size_t>(std::min(9, static_cast<int>(std::floor(pc * 10.0 + 1e-12))));
      ++nc[bin];
      pc_sum[bin] += pc;
      oc_sum[bin] += o;
    }
    DOUBLES_EQUAL(brier_c / count, c["brier"].get<double>(), 1e-9);
    DOUBLES_EQUAL(1.0 - (brier_c / count) / (base * (1.0 - base)), c["brier_skill"].get<double>(), 1e-9);
    DOUBLES_EQUAL(1.0 - brier_c / brier_b, c["brier_skill_vs_baseline"].get<double>(), 1e-9);
    std::size_t kc = 0;
    for (std::size_t bin = 0; bin < 10; ++bin) {
      if (nc[bin] == 0) continue;
      const nlohmann::json& jb = c["reliability"][kc++];
      LONGS_EQUAL(static_cast<long>(nc[bin]), jb["n"].get<long>());
      DOUBLES_EQUAL(pc_sum[bin] / double(nc[bin]), jb["mean_p"].get<double>(), 1e-9);
      DOUBLES_EQUAL(oc_sum[bin] / double(nc[bin]), jb["observed"].get<double>(), 1e-12);
    }
    LONGS_EQUAL(static_cast<long>(kc), static_cast<long>(c["reliability"].size()));
  }
  CHECK_EQUAL(f["goals"]["calibrated"].get<bool>(), c["calibration"]["calibrated"].get<bool>());
  CHECK_EQUAL(f["goals"]["skill_above_baseline"].get<bool>(),
              c["brier_skill"].get<double>() > f["baseline"]["brier_skill"].get<double>());
  CHECK_EQUAL(f["goals_raw_ensemble"]["calibrated"].get<bool>(), f["calibration"]["calibrated"].get<bool>());
  LONGS_EQUAL(5, static_cast<long>(c["coefficients_all_records"].size()));
}

TEST(StudyForecast, RejectsBadOptionsNamingThem) {
  TempDir dir;
  const std::string out = dir.file("s");
  const std::vector<std::string> base{"--suite", kSuite, "--sets", "3", "--vertical", "without", "--out", out};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  expect_command_rejected("study", with({"--forecast-members", "10"}), {"--forecast-members", "--forecast"});
  expect_command_rejected("study", with({"--forecast", "--forecast-members", "0"}), {"--forecast-members"});
  expect_command_rejected("study", with({"--forecast", "--forecast-members", "1e9"}), {"--forecast-members"});
  expect_command_rejected("study", with({"--forecast", "--forecast-horizon-s", "61"}), {"--forecast-horizon-s"});
  expect_command_rejected("study", with({"--forecast", "--forecast-horizon-s", "nan"}), {"--forecast-horizon-s"});
  expect_command_rejected("study", with({"--forecast", "--forecast-every-s", "0.001"}), {"--forecast-every-s"});
  expect_command_rejected("study", with({"--forecast", "--forecast-seed", "-1"}), {"--forecast-seed"});
  expect_command_rejected("study", {"--suite", kSuite, "--sets", "3", "--vertical", "with", "--forecast", "--out", out},
                          {"--forecast", "--vertical"});
  expect_command_rejected("study", with({"--forecast", "--shard", "1/2"}), {"--shard", "--forecast"});
  expect_command_rejected("study", with({"--forecast-setting", "damping=0.5"}), {"--forecast-setting", "--forecast"});
  expect_command_rejected("study", with({"--forecast", "--forecast-setting", "nonsense=1"}), {"--forecast-setting"});
  expect_command_rejected("study", with({"--forecast", "--forecast-setting", "damping"}), {"--forecast-setting"});
  expect_command_rejected("study", with({"--forecast", "--forecast-setting", "damping=2"}), {"--forecast-setting"});
  expect_command_rejected("study", with({"--forecast", "--forecast-setting", "condition_on_record=0.5"}),
                          {"--forecast-setting"});
}

// Two records (groups), each with a collapsing and a surviving run; the baseline needs both outcomes in each fold.
TEST(StudyForecast, LeadThresholdsAreChosenWithoutTheRecordScored) {
  study::StudyPlan plan;
  plan.records.resize(2);
  plan.records[0].name = "a";
  plan.records[1].name = "b";
  plan.pga_g = {0.1, 0.2};
  plan.restitutions.resize(1);
  plan.vertical = {false};
  // Run order: record, level. Record a: 0.1 g survives (max P 0.3), 0.2 g collapses at 5 s (P 0.6 at 2 s).
  // Record b: 0.1 g survives (max P 0.7), 0.2 g collapses at 4 s (P 0.4 at 1 s, 0.8 at 3 s).
  std::vector<study::ForecastRunResult> runs(4);
  for (auto& r : runs) r.done = true;
  runs[0].points = {point(1.0, 0.1, false, 0.1, 0.1), point(2.0, 0.3, false, 0.5, 0.2)};
  runs[1].collapsed = true;
  runs[1].t_collapse_s = 5.0;
  runs[1].t_first_imminent_s = 4.5;
  runs[1].points = {point(1.0, 0.2, false, 0.3, 0.1), point(2.0, 0.6, false, 0.9, 0.5), point(4.0, 0.9, true, 1.5, 0.9)};
  runs[2].t_first_imminent_s = 3.0;  // a false IMMINENT
  runs[2].points = {point(1.0, 0.7, false, 0.8, 0.6)};
  runs[3].collapsed = true;
  runs[3].t_collapse_s = 4.0;
  runs[3].points = {point(1.0, 0.4, false, 0.2, 0.3), point(3.0, 0.8, true, 1.2, 0.8)};
  const study::ForecastOutcome o = study::forecast_outcome(plan, runs);
  LONGS_EQUAL(2, static_cast<long>(o.groups));
  LONGS_EQUAL(8, static_cast<long>(o.forecasts));
  DOUBLES_EQUAL(2.0 / 8.0, *o.base_rate, 1e-15);
  // 5 % of one survivor: none may reach p*. Fold a (p* from b's survivor, max 0.7): 0.71; run 1 reaches 0.9 at 4 s
  // (lead 1 s), run 0 never. Fold b (p* from a's survivor, 0.3): 0.31; run 2 reaches it (false alarm), run 3 at 1 s
  // (lead 3 s).
  LONGS_EQUAL(2, static_cast<long>(o.ensemble_5.survivors));
  LONGS_EQUAL(1, static_cast<long>(o.ensemble_5.survivors_flagged));
  LONGS_EQUAL(2, static_cast<long>(o.ensemble_5.collapsed_flagged));
  DOUBLES_EQUAL(0.31, *o.ensemble_5.p_star_min, 1e-12);
  DOUBLES_EQUAL(0.71, *o.ensemble_5.p_star_max, 1e-12);
  DOUBLES_EQUAL(2.0, *o.ensemble_5.lead_time_s_median, 1e-12);  // leads 1 and 3 s
  // IMMINENT: one false alarm of two survivors, one collapse flagged 0.5 s ahead.
  LONGS_EQUAL(1, static_cast<long>(o.imminent.survivors_flagged));
  LONGS_EQUAL(1, static_cast<long>(o.imminent.collapsed_flagged));
  DOUBLES_EQUAL(0.5, *o.imminent.lead_time_s_median, 1e-12);
  DOUBLES_EQUAL(0.25, *o.imminent.lead_time_s_median_all_collapses, 1e-12);  // run 3 missed: 0 s and 0.5 s
  DOUBLES_EQUAL(2.0, *o.ensemble_5.lead_time_s_median_all_collapses, 1e-12);  // none missed
  // At IMMINENT's false alarms on the other record: fold a allows 1 of b's survivors (b flagged one): p* 0.01, so
  // run 0 is flagged at 1 s and run 1 at 1 s (lead 4 s); fold b allows 0 of a's: 0.31 as above.
  LONGS_EQUAL(2, static_cast<long>(o.ensemble_at_imminent.survivors_flagged));
  DOUBLES_EQUAL(0.01, *o.ensemble_at_imminent.p_star_min, 1e-12);
  DOUBLES_EQUAL(3.5, *o.ensemble_at_imminent.lead_time_s_median, 1e-12);  // leads 4 and 3 s
  // Reliability: 8 forecasts in 8 bins (0.1, 0.2, 0.3, 0.4, 0.6, 0.7, 0.8 and 0.9; none with 30: none judged).
  LONGS_EQUAL(0, static_cast<long>(o.bins_judged));
  CHECK_FALSE(o.calibrated);
  // The baseline was fitted without each record: its probabilities exist for all 8 forecasts.
  LONGS_EQUAL(8, static_cast<long>(o.baseline_p.size()));
}

// One record (set 3: its X and Y are one record): nothing to leave out, so the baseline and the thresholds are not
// fitted (null, and said so), while the forecasts' own scores and IMMINENT's are there.
TEST(StudyForecast, OneRecordHasNothingToLeaveOut) {
  TempDir dir;
  const std::string out = dir.file("one");
  const ProcessResult r = run_rockwatch({"study", "--suite", kSuite, "--sets", "3", "--r", "exp", "--vertical", "without",
                                         "--pga", "0.2:0.3:0.1", "--forecast", "--forecast-members", "10",
                                         "--forecast-every-s", "1", "--jobs", "2", "--out", out});
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  CHECK_TEXT(r.out.find("not fitted: one record") != std::string::npos, what.c_str());
  const nlohmann::json f = read_json(out + "/summary.json")["forecast"];
  LONGS_EQUAL(1, f["record_groups"].get<long>());
  LONGS_EQUAL(4, f["runs"].get<long>());
  CHECK(f["brier"].is_number());
  CHECK(f["baseline"]["brier"].is_null());
  CHECK(f["lead"]["ensemble_5_percent"].is_null());
  CHECK(f["lead"]["imminent"].is_object());
  CHECK_FALSE(f["goals"]["skill_above_baseline"].get<bool>());
  // forecast.csv's baseline column is empty then.
  const auto rows = read_csv(out + "/forecast.csv");
  CHECK(!rows.empty());
  for (const auto& row : rows) CHECK(row.at("baseline_p").empty());
}

// The recalibrated P (SPEC §10 "Calibrated P") is fitted leave one record out: the calibrated P of a record's
// forecasts does not change, to the bit, when that record's outcomes are changed (its forecasts are not among the
// rows that fit its fold), while the other records' do; and each fold's P is the fit on the other records alone.
TEST(StudyForecast, CalibrationNeverSeesTheRecordScored) {
  study::StudyPlan plan;
  plan.records.resize(3);
  plan.records[0].name = "a";
  plan.records[1].name = "b";
  plan.records[2].name = "c";
  plan.pga_g = {0.1, 0.2};
  plan.restitutions.resize(1);
  plan.vertical = {false};
  // Run order: record, level: runs 0-1 record a, 2-3 b, 4-5 c. Forecasts on a grid with mixed outcomes.
  // Runs 2g and 2g + 1 are record g's; flip_record g flips their outcomes (-1: none).
  auto make_runs = [](int flip_record) {
    std::vector<study::ForecastRunResult> runs(6);
    for (std::size_t r = 0; r < runs.size(); ++r) {
      runs[r].done = true;
      for (int k = 0; k < 40; ++k) {
        const double p = double((k * 7 + int(r) * 3) % 20) / 20.0;
        const double e = double((k * 3 + int(r)) % 11) / 5.0;
        const double xr = double((k * 5 + int(r) * 2) % 9) / 9.0;
        bool outcome = (k * 13 + int(r) * 5) % 7 < int(1 + 5 * p);
        if (int(r) / 2 == flip_record) outcome = !outcome;
        runs[r].points.push_back(point(0.1 * k, p, outcome, e, xr));
      }
    }
    return runs;
  };
  const std::vector<study::ForecastRunResult> runs = make_runs(-1);
  const study::ForecastOutcome o = study::forecast_outcome(plan, runs, 100);
  const study::CalibratedForecast& c = o.calibrated_forecast;
  CHECK(c.fitted);
  LONGS_EQUAL(3, static_cast<long>(c.folds));
  LONGS_EQUAL(240, static_cast<long>(c.p.size()));
  LONGS_EQUAL(240, static_cast<long>(c.fold_rows_checked));
  // Every fold, the last included (issue 42: one record flipped and one point of one other fold were checked).
  // Record g's forecasts are 80g .. 80g + 79 (forecast.csv order).
  for (int g = 0; g < 3; ++g) {
    const std::string fold = "fold of record " + std::to_string(g);
    // g's outcomes flipped: g's calibrated P unchanged to the bit, the other records' changed.
    const study::ForecastOutcome f = study::forecast_outcome(plan, make_runs(g), 100);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < 240; ++i) {
      if (i / 80 == std::size_t(g)) {
        DOUBLES_EQUAL_TEXT(c.p[i], f.calibrated_forecast.p[i], 0.0, fold.c_str());
      } else {
        changed += c.p[i] != f.calibrated_forecast.p[i] ? 1 : 0;
      }
    }
    CHECK_TEXT(changed > 100, fold.c_str());
    // Every one of g's forecasts: the fit on the other two records' forecasts only.
    std::vector<double> x;
    std::vector<std::uint8_t> y;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (int(r) / 2 == g) continue;
      for (const study::ForecastPoint& p : runs[r].points) {
        const auto feat = rockwatch::sim::calibration_features(p.p_collapse, 100, p.energy_ratio_max, p.x_over_x_inst);
        x.insert(x.end(), feat.begin(), feat.end());
        y.push_back(p.outcome ? 1 : 0);
      }
    }
    const std::vector<double> w = rockwatch::sim::fit_logistic_regression(x, rockwatch::sim::kCalibrationFeatures, y);
    rockwatch::sim::ForecastCalibration cal;
    for (std::size_t a = 0; a < std::size_t(rockwatch::sim::kCalibrationFeatures); ++a) cal.c[a] = w[a];
    for (std::size_t r = std::size_t(2 * g), i = std::size_t(80 * g); r < std::size_t(2 * g + 2); ++r) {
      for (const study::ForecastPoint& q : runs[r].points) {
        DOUBLES_EQUAL_TEXT(rockwatch::sim::calibrated_probability(cal, q.p_collapse, 100, q.energy_ratio_max, q.x_over_x_inst),
                           c.p[i++], 1e-12, fold.c_str());
      }
    }
  }
  // Scored as the raw P is: Brier, skill, reliability over every forecast.
  double brier = 0.0;
  for (std::size_t r = 0, i = 0; r < runs.size(); ++r) {
    for (const study::ForecastPoint& p : runs[r].points) {
      const double d = c.p[i++] - (p.outcome ? 1.0 : 0.0);
      brier += d * d;
    }
  }
  DOUBLES_EQUAL(brier / 240.0, *c.brier, 1e-12);
  std::size_t binned = 0;
  for (const study::ReliabilityBin& b : c.bins) binned += b.n;
  LONGS_EQUAL(240, static_cast<long>(binned));
  LONGS_EQUAL(5, static_cast<long>(c.coefficients_all_records.size()));
}

}  // namespace unity_test_study_forecast
