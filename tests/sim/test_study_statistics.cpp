// The study's statistics in sim/study on hand-made inputs whose answers are known: the type-7 quantile and the spread
// (quantile), the alarm's recall, false alarms and lead times (alarm_scores), the logistic fit of the forecast
// baseline against a brute-force likelihood (logistic_fit), and the forecast scores' Brier score, reliability bins and
// threshold (forecast_scores). The same functions are rockwatch.study.… in Python (tests/python).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "rockwatch/sim/study/alarm_scores.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/forecast_scores.hpp"
#include "rockwatch/sim/study/logistic_fit.hpp"
#include "rockwatch/sim/study/quantile.hpp"

#include <CppUTest/TestHarness.h>

namespace study = rockwatch::sim::study;

TEST_GROUP(StudyQuantile){};

TEST(StudyQuantile, QuantileIsLinearBetweenOrderStatistics) {
  CHECK_FALSE(study::quantile_type7({}, 0.5).has_value());
  DOUBLES_EQUAL(3.0, *study::quantile_type7({3.0}, 0.05), 0.0);
  const std::vector<double> v{1.0, 2.0, 4.0, 8.0, 16.0};
  DOUBLES_EQUAL(4.0, *study::quantile_type7(v, 0.5), 0.0);
  DOUBLES_EQUAL(1.2, *study::quantile_type7(v, 0.05), 1e-15);  // h = 0.2: 1 + 0.2 (2 − 1)
  DOUBLES_EQUAL(16.0, *study::quantile_type7(v, 1.0), 0.0);
  DOUBLES_EQUAL(1.0, *study::quantile_type7(v, 0.0), 0.0);
  DOUBLES_EQUAL(3.0, *study::quantile_type7({2.0, 4.0}, 0.5), 0.0);
}

TEST(StudyQuantile, SpreadSortsItsValues) {
  const study::Spread s = study::spread_of({16.0, 1.0, 8.0, 2.0, 4.0});
  LONGS_EQUAL(5, s.n);
  DOUBLES_EQUAL(4.0, *s.median, 0.0);
  DOUBLES_EQUAL(8.0 + 0.8 * 8.0, *s.p95, 1e-12);  // h = 3.8
  DOUBLES_EQUAL(16.0, *s.max, 0.0);
  const study::Spread none = study::spread_of({});
  LONGS_EQUAL(0, none.n);
  CHECK_FALSE(none.median.has_value() || none.p95.has_value() || none.max.has_value());
}

TEST_GROUP(StudyAlarmScores){};

TEST(StudyAlarmScores, RecallFalseAlarmsAndLeadTimes) {
  std::vector<study::RunResult> results(6);
  for (study::RunResult& r : results) r.done = true;
  // Collapses: flagged 2 s ahead, flagged 0.5 s ahead, flagged only at the collapse (not in time).
  results[0].collapsed = true;
  results[0].t_collapse_s = 5.0;
  results[0].t_first_imminent_s = 3.0;
  results[1].collapsed = true;
  results[1].t_collapse_s = 4.0;
  results[1].t_first_imminent_s = 3.5;
  results[2].collapsed = true;
  results[2].t_collapse_s = 6.0;
  results[2].t_first_imminent_s = 6.0;
  // Survivors: one flagged, one not; and a run the engine refused (left out).
  results[3].t_first_imminent_s = 2.0;
  results[5].error = "G <= 0";
  const study::AlarmOutcome a = study::alarm_outcome(results);
  LONGS_EQUAL(5, a.runs);
  LONGS_EQUAL(3, a.collapsed);
  LONGS_EQUAL(2, a.collapsed_flagged);
  LONGS_EQUAL(2, a.survivors);
  LONGS_EQUAL(1, a.survivors_flagged);
  DOUBLES_EQUAL(2.0 / 3.0, *a.recall, 1e-15);
  DOUBLES_EQUAL(0.5, *a.false_alarm_rate, 0.0);
  DOUBLES_EQUAL(1.25, *a.lead_time_s_median, 1e-15);
  DOUBLES_EQUAL(0.5 + 0.05 * 1.5, *a.lead_time_s_p05, 1e-15);
  DOUBLES_EQUAL(0.5, *a.lead_time_s_min, 0.0);

  // In a fixed-point study the verdict of record is the double engine's.
  results[3].reference = study::DoubleReference{true, 2.5, 0.3, 1.0};
  const study::AlarmOutcome f = study::alarm_outcome(results);
  LONGS_EQUAL(4, f.collapsed);
  LONGS_EQUAL(3, f.collapsed_flagged);
  LONGS_EQUAL(1, f.survivors);
  DOUBLES_EQUAL(0.0, *f.false_alarm_rate, 0.0);

  const study::AlarmOutcome none = study::alarm_outcome(std::vector<study::RunResult>(2, study::RunResult{}));
  LONGS_EQUAL(0, none.runs);
  CHECK_FALSE(none.recall.has_value() || none.false_alarm_rate.has_value() || none.lead_time_s_median.has_value());
}

TEST(StudyAlarmScores, RunsGivenDirectlyScoreAsResults) {
  const std::vector<study::AlarmRun> runs{{true, 5.0, 3.0}, {true, 4.0, 3.5}, {true, 6.0, 6.0},
                                          {false, std::nullopt, 2.0}, {false, std::nullopt, std::nullopt}};
  const study::AlarmOutcome a = study::alarm_outcome(runs);
  LONGS_EQUAL(5, a.runs);
  LONGS_EQUAL(2, a.collapsed_flagged);
  DOUBLES_EQUAL(2.0 / 3.0, *a.recall, 1e-15);
  DOUBLES_EQUAL(0.5, *a.false_alarm_rate, 0.0);
  LONGS_EQUAL(2, a.lead_times_s.size());
  DOUBLES_EQUAL(0.5, a.lead_times_s[0], 0.0);
  DOUBLES_EQUAL(2.0, a.lead_times_s[1], 0.0);
}

TEST_GROUP(StudyLogisticFit){};

// Overlapping classes: the fit maximises the likelihood (no neighbour on a fine grid does better), and the
// probability it gives is the logistic of the weighted features.
TEST(StudyLogisticFit, MaximisesTheLikelihood) {
  const std::vector<double> f{0.1, 0.4, 0.5, 0.9, 1.2, 1.3, 1.7, 2.0, 2.4, 2.8};
  const std::vector<std::uint8_t> y{0, 0, 1, 0, 0, 1, 1, 0, 1, 1};
  std::vector<double> x;
  for (const double v : f) x.insert(x.end(), {1.0, v});
  const std::vector<double> w = study::fit_logistic(x, 2, y);
  LONGS_EQUAL(2, w.size());
  const auto log_likelihood = [&](double w0, double w1) {
    double sum = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const double p = 1.0 / (1.0 + std::exp(-(w0 + w1 * f[i])));
      sum += y[i] ? std::log(p) : std::log(1.0 - p);
    }
    return sum;
  };
  const double best = log_likelihood(w[0], w[1]);
  for (int a = -2; a <= 2; ++a) {
    for (int b = -2; b <= 2; ++b) CHECK_TRUE(log_likelihood(w[0] + 1e-3 * a, w[1] + 1e-3 * b) <= best + 1e-12);
  }
  CHECK_TRUE(w[1] > 0.0);  // outcomes grow with the feature
  const double row[2] = {1.0, 1.2};
  DOUBLES_EQUAL(1.0 / (1.0 + std::exp(-(w[0] + w[1] * 1.2))), study::logistic_probability(w, row), 1e-15);
}

TEST(StudyLogisticFit, LeavesOutTheRowsNotUsedAndRejectsBadSizes) {
  const std::vector<double> x{1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0, 1.0, 10.0};
  const std::vector<std::uint8_t> y{0, 1, 0, 1, 1};
  const std::vector<std::uint8_t> use{1, 1, 1, 1, 0};
  const std::vector<double> a = study::fit_logistic(x, 2, y, use);
  const std::vector<double> b = study::fit_logistic({1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0}, 2, {0, 1, 0, 1});
  DOUBLES_EQUAL(b[0], a[0], 0.0);
  DOUBLES_EQUAL(b[1], a[1], 0.0);
  const std::vector<double> bad = study::fit_logistic({1.0, 2.0, 3.0}, 2, {0, 1});
  LONGS_EQUAL(2, bad.size());
  DOUBLES_EQUAL(0.0, bad[0], 0.0);
  DOUBLES_EQUAL(0.0, bad[1], 0.0);
}

TEST_GROUP(StudyForecastScores){};

TEST(StudyForecastScores, BrierReliabilityAndThreshold) {
  const std::vector<double> p{0.05, 0.05, 0.95, 0.5};
  const std::vector<std::uint8_t> o{0, 1, 1, 0};
  DOUBLES_EQUAL((0.0025 + 0.9025 + 0.0025 + 0.25) / 4.0, study::brier_score(p, o), 1e-15);
  std::size_t judged = 99;
  std::optional<double> max_error = 1.0;
  const std::vector<study::ReliabilityBin> bins = study::reliability_bins(p, o, judged, max_error);
  LONGS_EQUAL(3, bins.size());  // [0, 0.1), [0.5, 0.6), [0.9, 1]
  DOUBLES_EQUAL(0.0, bins[0].lo, 0.0);
  LONGS_EQUAL(2, bins[0].n);
  DOUBLES_EQUAL(0.5, bins[0].observed, 0.0);
  DOUBLES_EQUAL(0.05, bins[0].mean_p, 1e-15);
  DOUBLES_EQUAL(0.9, bins[2].lo, 1e-15);
  LONGS_EQUAL(0, judged);  // fewer than kCalibrationMinForecasts in every bin
  CHECK_FALSE(max_error.has_value());
  // Survivors' largest P: 0.1, 0.3, 0.3, 0.8; one may reach p*: 0.31 is the first grid value only 0.8 reaches.
  DOUBLES_EQUAL(0.31, *study::threshold_for({0.1, 0.3, 0.3, 0.8}, 1), 1e-15);
  DOUBLES_EQUAL(0.01, *study::threshold_for({0.1, 0.3}, 2), 1e-15);
  CHECK_FALSE(study::threshold_for({1.0, 1.0}, 1).has_value());
}
