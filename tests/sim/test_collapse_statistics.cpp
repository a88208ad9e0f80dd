// The study's collapse statistics (sim/study/collapse_statistics, SPEC §6, paper Table 3) on hand-made run tables
// with known answers: survival rates and levels, resurrections, the paper's least-squares normal fit (exact data and
// a brute-force grid search written out here), the lognormal maximum-likelihood fit (exact fractions and a
// brute-force grid over the log-likelihood), the bootstrap intervals, the probabilities at a capacity, undetermined
// cases and rejections, and a case shaped like the paper's r_ana horizontal-only study.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "rockwatch/sim/study/collapse_statistics.hpp"

#include "check_throws.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using namespace rockwatch::sim::study;

namespace {

// Φ written out here (not the library's).
double phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Φ⁻¹ by bisection on Φ (slow but independent).
double phi_inverse(double p) {
  double lo = -10.0, hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (phi(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The study's PGA levels 0.11 … 0.30 g in 0.01 g steps.
std::vector<double> study_levels() {
  std::vector<double> levels;
  for (int i = 0; i < 20; ++i) levels.push_back(0.11 + 0.01 * i);
  return levels;
}

// Record k has capacity capacities[k] and collapses at every level ≥ it (no resurrections).
std::vector<RunOutcome> threshold_runs(const std::vector<double>& capacities, const std::vector<double>& levels) {
  std::vector<RunOutcome> runs;
  for (std::size_t k = 0; k < capacities.size(); ++k) {
    for (const double a : levels) runs.push_back({k, a, a >= capacities[k]});
  }
  return runs;
}

// n capacities at the normal quantiles (k + 1/2)/n of N(mean, sd).
std::vector<double> quantile_capacities(std::size_t n, double mean, double sd) {
  std::vector<double> c;
  for (std::size_t k = 0; k < n; ++k) c.push_back(mean + sd * phi_inverse((static_cast<double>(k) + 0.5) / static_cast<double>(n)));
  return c;
}

std::vector<SurvivalPoint> points_from_fractions(const std::vector<double>& levels, const std::vector<double>& f) {
  std::vector<SurvivalPoint> points;
  for (std::size_t i = 0; i < levels.size(); ++i) points.push_back({levels[i], 0, 0, 1.0 - f[i]});
  return points;
}

double normal_ssr(const std::vector<double>& levels, const std::vector<double>& f, double mu, double sigma) {
  double s = 0.0;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const double r = phi((levels[i] - mu) / sigma) - f[i];
    s += r * r;
  }
  return s;
}

// Binomial log-likelihood of the lognormal fragility over the runs, written out run by run.
double lognormal_log_likelihood(const std::vector<RunOutcome>& runs, double median, double beta) {
  double ll = 0.0;
  for (const RunOutcome& run : runs) {
    const double p = phi(std::log(run.pga_g / median) / beta);
    ll += run.collapsed ? std::log(p) : std::log(1.0 - p);
  }
  return ll;
}

struct GridOptimum {
  double x = 0.0;
  double y = 0.0;
  double value = 0.0;
};

// Brute force: the minimum of f over a grid of (x, y), then again on a grid 50 times finer around the best point.
template <typename F>
GridOptimum grid_minimum(F f, double x_lo, double x_hi, double y_lo, double y_hi, int steps) {
  GridOptimum best{x_lo, y_lo, f(x_lo, y_lo)};
  double dx = (x_hi - x_lo) / steps, dy = (y_hi - y_lo) / steps;
  for (int pass = 0; pass < 2; ++pass) {
    const double x0 = pass == 0 ? x_lo : best.x - 2.0 * dx;
    const double y0 = pass == 0 ? y_lo : best.y - 2.0 * dy;
    if (pass == 1) {
      dx /= 50.0;
      dy /= 50.0;
    }
    const int n = pass == 0 ? steps : 200;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        const double x = x0 + dx * i, y = y0 + dy * j;
        const double v = f(x, y);
        if (v < best.value) best = {x, y, v};
      }
    }
  }
  return best;
}

template <typename Fn>
void check_throws_statistics_error(Fn fn) {
  rockwatch::test::check_throws<StatisticsError>(fn, "expected StatisticsError");
}

BootstrapOptions no_bootstrap() { return {0, 1}; }

}  // namespace

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(SurvivalByPga){};

TEST(SurvivalByPga, LevelsAscendingWithCountsAndRates) {
  // Out of order; 0.1 + 5e-10 is the same level as 0.1 (within 1e-9 g), 0.1 + 1e-8 is not.
  const std::vector<RunOutcome> runs = {
      {0, 0.20, true}, {0, 0.10, false}, {1, 0.10 + 5e-10, true}, {1, 0.20, true},
      {2, 0.15, false}, {2, 0.10, false}, {3, 0.10 + 1e-8, false}, {3, 0.15, true},
  };
  const std::vector<SurvivalPoint> s = survival_by_pga(runs);
  UNSIGNED_LONGS_EQUAL(4, s.size());
  DOUBLES_EQUAL(0.10, s[0].pga_g, 0.0);
  UNSIGNED_LONGS_EQUAL(3, s[0].runs);
  UNSIGNED_LONGS_EQUAL(1, s[0].collapsed);
  DOUBLES_EQUAL(2.0 / 3.0, s[0].survival_rate, 1e-15);
  DOUBLES_EQUAL(0.10 + 1e-8, s[1].pga_g, 0.0);
  UNSIGNED_LONGS_EQUAL(1, s[1].runs);
  DOUBLES_EQUAL(1.0, s[1].survival_rate, 0.0);
  DOUBLES_EQUAL(0.15, s[2].pga_g, 0.0);
  UNSIGNED_LONGS_EQUAL(2, s[2].runs);
  DOUBLES_EQUAL(0.5, s[2].survival_rate, 0.0);
  DOUBLES_EQUAL(0.20, s[3].pga_g, 0.0);
  UNSIGNED_LONGS_EQUAL(2, s[3].collapsed);
  DOUBLES_EQUAL(0.0, s[3].survival_rate, 0.0);
}

TEST(SurvivalByPga, RejectsEmptyAndBadPga) {
  check_throws_statistics_error([] { survival_by_pga({}); });
  check_throws_statistics_error([] { survival_by_pga({{0, 0.0, false}}); });
  check_throws_statistics_error([] { survival_by_pga({{0, 0.1, false}, {0, -0.1, true}}); });
  check_throws_statistics_error([] { survival_by_pga({{0, std::nan(""), false}}); });
  check_throws_statistics_error([] { survival_by_pga({{0, HUGE_VAL, false}}); });
}

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(Resurrections){};

TEST(Resurrections, SurvivalsAfterALowerCollapseOfTheSameRecord) {
  const std::vector<RunOutcome> runs = {
      // Record 7: survives 0.14, collapses 0.15, survives 0.16 and 0.17, collapses 0.18 → 2.
      {7, 0.14, false}, {7, 0.15, true}, {7, 0.16, false}, {7, 0.17, false}, {7, 0.18, true},
      // Record 2: collapses from 0.16 on → 0.
      {2, 0.14, false}, {2, 0.15, false}, {2, 0.16, true}, {2, 0.17, true}, {2, 0.18, true},
      // Record 3: collapses at 0.14 only, listed last → 4 (order of the table does not matter).
      {3, 0.18, false}, {3, 0.17, false}, {3, 0.16, false}, {3, 0.15, false}, {3, 0.14, true},
  };
  UNSIGNED_LONGS_EQUAL(6, count_resurrections(runs));
  // Another record's collapse at a lower level does not count, nor a survival at the same level.
  UNSIGNED_LONGS_EQUAL(0, count_resurrections({{0, 0.14, true}, {1, 0.16, false}, {1, 0.14, false}}));
  UNSIGNED_LONGS_EQUAL(0, count_resurrections({{0, 0.14, true}, {0, 0.14 + 1e-10, false}}));
}

TEST(Resurrections, RejectsEmpty) { check_throws_statistics_error([] { count_resurrections({}); }); }

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(NormalLeastSquares){};

// Fractions exactly Φ((a − 0.22)/0.05) at the 20 study levels: the minimum is S = 0 at the generating values.
TEST(NormalLeastSquares, RecoversExactNormal) {
  const std::vector<double> levels = study_levels();
  std::vector<double> f;
  for (const double a : levels) f.push_back(phi((a - 0.22) / 0.05));
  const NormalFit fit = fit_normal_least_squares(points_from_fractions(levels, f));
  CHECK(fit.ok);
  DOUBLES_EQUAL(0.22, fit.mean_g, 1e-6);
  DOUBLES_EQUAL(0.05, fit.std_g, 1e-6);
  CHECK(fit.sum_squared_residuals < 1e-20);
}

// A curve centred above the levels (only its lower part is seen) and a steep one: still recovered.
TEST(NormalLeastSquares, RecoversCurvesFarFromTheStart) {
  const std::vector<double> levels = study_levels();
  for (const auto& [mu, sigma] : std::vector<std::pair<double, double>>{{0.34, 0.08}, {0.205, 0.004}, {0.15, 0.3}}) {
    std::vector<double> f;
    for (const double a : levels) f.push_back(phi((a - mu) / sigma));
    const NormalFit fit = fit_normal_least_squares(points_from_fractions(levels, f));
    CHECK(fit.ok);
    DOUBLES_EQUAL(mu, fit.mean_g, 1e-6);
    DOUBLES_EQUAL(sigma, fit.std_g, 1e-6);
  }
}

// Noisy, non-monotone fractions k/22: the fit against a brute-force grid search over (μ, σ) done here (a 0.001 g
// grid, then a 2e-5 g grid around its best point). The fit must be at least as good as the grid's best and lie
// within a few fine cells of it.
TEST(NormalLeastSquares, AgreesWithBruteForceGridSearch) {
  const std::vector<double> levels = study_levels();
  const std::vector<int> collapsed = {0, 0, 0, 1, 1, 2, 3, 5, 6, 8, 9, 12, 14, 13, 16, 18, 19, 20, 21, 22};
  std::vector<double> f;
  for (const int k : collapsed) f.push_back(k / 22.0);
  const NormalFit fit = fit_normal_least_squares(points_from_fractions(levels, f));
  CHECK(fit.ok);
  const GridOptimum grid = grid_minimum([&](double mu, double sigma) { return normal_ssr(levels, f, mu, sigma); },
                                        0.10, 0.35, 0.005, 0.205, 200);
  CHECK(fit.sum_squared_residuals <= grid.value + 1e-15);
  DOUBLES_EQUAL(grid.value, fit.sum_squared_residuals, 1e-7);
  DOUBLES_EQUAL(grid.x, fit.mean_g, 6e-5);
  DOUBLES_EQUAL(grid.y, fit.std_g, 6e-5);
  DOUBLES_EQUAL(normal_ssr(levels, f, fit.mean_g, fit.std_g), fit.sum_squared_residuals, 1e-15);
}

// Two intermediate levels already determine the curve (an exact fit through them beats every limit).
TEST(NormalLeastSquares, TwoIntermediateLevelsDetermineTheFit) {
  const NormalFit fit = fit_normal_least_squares(points_from_fractions({0.1, 0.2, 0.3, 0.4}, {0.0, 0.25, 0.75, 1.0}));
  CHECK(fit.ok);
  DOUBLES_EQUAL(0.25, fit.mean_g, 1e-9);  // symmetric data
  CHECK(fit.std_g > 0.05 && fit.std_g < 0.1);
}

// Data whose best fit is a limit (σ → 0 or σ → ∞), not a finite σ > 0: ok = false.
TEST(NormalLeastSquares, UndeterminedCasesAreNotOk) {
  const std::vector<double> four = {0.1, 0.2, 0.3, 0.4};
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions(four, {0, 0, 0, 0})).ok);          // no collapses
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions(four, {1, 1, 1, 1})).ok);          // only collapses
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions({0.2}, {0.5})).ok);                // one level
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions(four, {0.4, 0.4, 0.4, 0.4})).ok);  // constant
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions(four, {0, 0, 1, 1})).ok);          // a step: σ → 0
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions(four, {0, 0.3, 1, 1})).ok);        // one intermediate
  CHECK_FALSE(fit_normal_least_squares(points_from_fractions(four, {1, 0.7, 0.2, 0})).ok);      // falling: σ → ∞
  const NormalFit not_ok = fit_normal_least_squares(points_from_fractions(four, {0, 0, 1, 1}));
  DOUBLES_EQUAL(0.0, not_ok.mean_g, 0.0);
  DOUBLES_EQUAL(0.0, not_ok.std_g, 0.0);
}

TEST(NormalLeastSquares, RejectsBadInput) {
  check_throws_statistics_error([] { fit_normal_least_squares({}); });
  check_throws_statistics_error([] { fit_normal_least_squares(points_from_fractions({0.2, 0.1}, {0.0, 1.0})); });
  check_throws_statistics_error([] { fit_normal_least_squares(points_from_fractions({0.1, 0.1}, {0.0, 1.0})); });
  check_throws_statistics_error([] { fit_normal_least_squares(points_from_fractions({0.1, 0.2}, {0.0, 1.5})); });
  check_throws_statistics_error(
      [] { fit_normal_least_squares(points_from_fractions({0.1, std::nan("")}, {0.0, 1.0})); });
}

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(LognormalMle){};

// 1000 runs per level with round(1000 p) collapses, p from the lognormal (θ = 0.22 g, β = 0.25) at the 20 study
// levels: the fractions represent the curve to ±0.0005, and the MLE recovers θ and β to about 1e-3 (relative).
TEST(LognormalMle, RecoversLognormalFromNearExactFractions) {
  const double median = 0.22, beta = 0.25;
  std::vector<RunOutcome> runs;
  for (const double a : study_levels()) {
    const auto k = static_cast<int>(std::lround(1000.0 * phi(std::log(a / median) / beta)));
    for (int j = 0; j < 1000; ++j) runs.push_back({static_cast<std::size_t>(j), a, j < k});
  }
  const LognormalFit fit = fit_lognormal_mle(runs, no_bootstrap());
  CHECK(fit.ok);
  DOUBLES_EQUAL(median, fit.median_g, 1e-3 * median);
  DOUBLES_EQUAL(beta, fit.beta, 1e-3 * beta);
  UNSIGNED_LONGS_EQUAL(0, fit.bootstrap_samples);
}

// A small noisy table: the MLE against a brute-force grid maximisation of the log-likelihood done here.
TEST(LognormalMle, AgreesWithBruteForceGridSearch) {
  const std::vector<double> levels = {0.12, 0.15, 0.18, 0.21, 0.24, 0.27, 0.30};
  const std::vector<int> collapsed = {0, 1, 1, 4, 3, 6, 7};  // of 8 runs per level
  std::vector<RunOutcome> runs;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    for (int j = 0; j < 8; ++j) runs.push_back({static_cast<std::size_t>(j), levels[i], j < collapsed[i]});
  }
  const LognormalFit fit = fit_lognormal_mle(runs, no_bootstrap());
  CHECK(fit.ok);
  const GridOptimum grid =
      grid_minimum([&](double median, double beta) { return -lognormal_log_likelihood(runs, median, beta); }, 0.10,
                   0.40, 0.05, 1.05, 200);
  const double ll_fit = lognormal_log_likelihood(runs, fit.median_g, fit.beta);
  CHECK(-ll_fit <= grid.value + 1e-12);
  DOUBLES_EQUAL(grid.x, fit.median_g, 1e-4);
  DOUBLES_EQUAL(grid.y, fit.beta, 3e-4);
}

// A steep rise (0.16 g: 1 of 10, 0.32 g: 9 of 10) seen over a wide range (0.01 … 5.12 g, doubling) with one
// collapse far below it at 0.01 g, which widens β to about 0.9: the MLE still matches a brute-force grid.
TEST(LognormalMle, WideRangeWithALowOutlier) {
  std::vector<RunOutcome> runs;
  for (int i = 0; i < 10; ++i) {
    const double a = 0.01 * std::pow(2.0, i);
    const int collapsed = i == 0 ? 1 : i < 4 ? 0 : i == 4 ? 1 : i == 5 ? 9 : 10;  // 0.16 g: 1, 0.32 g: 9 of 10
    for (int j = 0; j < 10; ++j) runs.push_back({static_cast<std::size_t>(j), a, j < collapsed});
  }
  const LognormalFit fit = fit_lognormal_mle(runs, no_bootstrap());
  CHECK(fit.ok);
  const GridOptimum grid =
      grid_minimum([&](double median, double beta) { return -lognormal_log_likelihood(runs, median, beta); }, 0.05,
                   0.55, 0.05, 1.05, 100);
  CHECK(-lognormal_log_likelihood(runs, fit.median_g, fit.beta) <= grid.value + 1e-12);
  DOUBLES_EQUAL(grid.x, fit.median_g, 1e-4);
  DOUBLES_EQUAL(grid.y, fit.beta, 3e-4);
}

// Data that cannot determine the fit: no collapses, only collapses, separated (β → 0), quasi-separated (one mixed
// level at the boundary, β → 0), a single level, and fractions falling with PGA (β → ∞).
TEST(LognormalMle, UndeterminedCasesAreNotOk) {
  const std::vector<double> levels = {0.15, 0.20, 0.25, 0.30};
  auto table = [&](const std::vector<std::vector<bool>>& collapsed_by_record) {
    std::vector<RunOutcome> runs;
    for (std::size_t r = 0; r < collapsed_by_record.size(); ++r) {
      for (std::size_t i = 0; i < levels.size(); ++i) runs.push_back({r, levels[i], collapsed_by_record[r][i]});
    }
    return runs;
  };
  const BootstrapOptions bootstrap{100, 3};
  auto not_ok = [&](const std::vector<RunOutcome>& runs) {
    const LognormalFit fit = fit_lognormal_mle(runs, bootstrap);
    CHECK_FALSE(fit.ok);
    UNSIGNED_LONGS_EQUAL(0, fit.bootstrap_samples);
  };
  not_ok(table({{false, false, false, false}, {false, false, false, false}}));
  not_ok(table({{true, true, true, true}, {true, true, true, true}}));
  not_ok(table({{false, false, true, true}, {false, false, true, true}}));
  not_ok(table({{false, true, true, true}, {false, false, true, true}}));   // 0.20 mixed, nothing overlaps it
  not_ok({{0, 0.2, true}, {1, 0.2, false}, {2, 0.2, true}});                 // one level
  not_ok(table({{true, true, false, false}, {true, false, true, false}}));  // overlapping but falling: γ < 0
  // One survival above a collapse is enough overlap.
  CHECK(fit_lognormal_mle(table({{false, true, true, true}, {false, false, false, true}, {false, true, false, true}}),
                          bootstrap)
            .ok);
}

TEST(LognormalMle, RejectsEmptyAndBadPga) {
  check_throws_statistics_error([] { fit_lognormal_mle({}, BootstrapOptions{}); });
  check_throws_statistics_error([] { fit_lognormal_mle({{0, 0.0, true}, {0, 0.2, false}}, BootstrapOptions{}); });
}

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(Bootstrap){};

TEST(Bootstrap, DeterministicAndContainsTheEstimate) {
  const std::vector<RunOutcome> runs = threshold_runs(quantile_capacities(22, 0.221, 0.055), study_levels());
  const LognormalFit a = fit_lognormal_mle(runs, {1000, 42});
  const LognormalFit b = fit_lognormal_mle(runs, {1000, 42});
  const LognormalFit c = fit_lognormal_mle(runs, {1000, 43});
  CHECK(a.ok);
  UNSIGNED_LONGS_EQUAL(a.bootstrap_samples, b.bootstrap_samples);
  DOUBLES_EQUAL(a.median_ci90_low_g, b.median_ci90_low_g, 0.0);
  DOUBLES_EQUAL(a.median_ci90_high_g, b.median_ci90_high_g, 0.0);
  DOUBLES_EQUAL(a.beta_ci90_low, b.beta_ci90_low, 0.0);
  DOUBLES_EQUAL(a.beta_ci90_high, b.beta_ci90_high, 0.0);
  CHECK(a.median_ci90_low_g != c.median_ci90_low_g || a.median_ci90_high_g != c.median_ci90_high_g);
  // Threshold data of 22 records: a resample separates only when it draws very few distinct records.
  CHECK(a.bootstrap_samples > 990 && a.bootstrap_samples <= 1000);
  CHECK(a.median_ci90_low_g < a.median_g && a.median_g < a.median_ci90_high_g);
  CHECK(a.beta_ci90_low < a.beta && a.beta < a.beta_ci90_high);
  // The point estimate does not depend on the bootstrap.
  DOUBLES_EQUAL(fit_lognormal_mle(runs, no_bootstrap()).median_g, a.median_g, 0.0);
}

// Four times as many records from the same distribution: the intervals shrink (by about half).
TEST(Bootstrap, NarrowerWithMoreRecords) {
  const LognormalFit few = fit_lognormal_mle(threshold_runs(quantile_capacities(22, 0.221, 0.055), study_levels()), {});
  const LognormalFit many = fit_lognormal_mle(threshold_runs(quantile_capacities(88, 0.221, 0.055), study_levels()), {});
  CHECK(few.ok && many.ok);
  const double median_width_few = few.median_ci90_high_g - few.median_ci90_low_g;
  const double median_width_many = many.median_ci90_high_g - many.median_ci90_low_g;
  const double beta_width_few = few.beta_ci90_high - few.beta_ci90_low;
  const double beta_width_many = many.beta_ci90_high - many.beta_ci90_low;
  CHECK(median_width_many < 0.7 * median_width_few);
  CHECK(beta_width_many < 0.7 * beta_width_few);
}

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(CollapseProbabilityAtCapacity){};

TEST(CollapseProbabilityAtCapacity, EmpiricalInterpolationExactLevelsAndRange) {
  const std::vector<SurvivalPoint> s = points_from_fractions({0.10, 0.20, 0.30}, {0.0, 0.5, 1.0});
  const NormalFit no_normal;
  const LognormalFit no_lognormal;
  auto empirical = [&](double capacity) { return collapse_probability(s, no_normal, no_lognormal, capacity).empirical; };
  DOUBLES_EQUAL(0.25, empirical(0.15).value(), 1e-12);
  DOUBLES_EQUAL(0.5 + 0.5 * 0.3, empirical(0.23).value(), 1e-12);
  DOUBLES_EQUAL(0.5, empirical(0.20).value(), 0.0);
  DOUBLES_EQUAL(0.5, empirical(0.20 + 5e-10).value(), 0.0);
  DOUBLES_EQUAL(0.0, empirical(0.10).value(), 0.0);
  DOUBLES_EQUAL(1.0, empirical(0.30).value(), 0.0);
  DOUBLES_EQUAL(0.0, empirical(0.10 - 5e-10).value(), 0.0);
  CHECK_FALSE(empirical(0.099).has_value());
  CHECK_FALSE(empirical(0.301).has_value());
  const CollapseProbability p = collapse_probability(s, no_normal, no_lognormal, 0.15);
  CHECK_FALSE(p.normal_fit.has_value());
  CHECK_FALSE(p.lognormal_fit.has_value());
}

TEST(CollapseProbabilityAtCapacity, FromTheFits) {
  const std::vector<SurvivalPoint> s = points_from_fractions({0.10, 0.20, 0.30}, {0.0, 0.5, 1.0});
  NormalFit normal;
  normal.ok = true;
  normal.mean_g = 0.221;
  normal.std_g = 0.055;
  LognormalFit lognormal;
  lognormal.ok = true;
  lognormal.median_g = 0.21;
  lognormal.beta = 0.27;
  for (const double capacity : {0.139, 0.180, 0.05, 0.35}) {
    const CollapseProbability p = collapse_probability(s, normal, lognormal, capacity);
    DOUBLES_EQUAL(phi((capacity - 0.221) / 0.055), p.normal_fit.value(), 1e-15);
    DOUBLES_EQUAL(phi(std::log(capacity / 0.21) / 0.27), p.lognormal_fit.value(), 1e-15);
  }
  DOUBLES_EQUAL(0.0, collapse_probability(s, normal, lognormal, 0.0).lognormal_fit.value(), 0.0);
}

TEST(CollapseProbabilityAtCapacity, RejectsBadInput) {
  check_throws_statistics_error([] { collapse_probability({}, NormalFit{}, LognormalFit{}, 0.14); });
  check_throws_statistics_error([] {
    collapse_probability(points_from_fractions({0.1, 0.2}, {0.0, 1.0}), NormalFit{}, LognormalFit{}, std::nan(""));
  });
}

// ------------------------------------------------------------------------------------------------------------------

TEST_GROUP(CaseStatistics){};

// Shaped like the paper's r_ana horizontal-only case (Table 3: mean 0.221 g, sd 0.055 g): 22 records whose
// capacities are the quantiles (k + 1/2)/22 of N(0.221, 0.055), each collapsing at every level ≥ its capacity, at
// 0.11 … 0.30 g. The collapse fractions are the empirical distribution of the capacities sampled at 0.01 g steps,
// so the fit reproduces (0.221, 0.055) only up to that discretisation. Tolerance: 0.001 g on both, a tenth of the
// level step (the fit gives 0.22124 g and 0.05506 g: the quantile-placed capacities follow the curve closely).
TEST(CaseStatistics, PaperLikeCase) {
  const std::vector<double> capacities = quantile_capacities(22, 0.221, 0.055);
  const std::vector<double> levels = study_levels();
  const std::vector<RunOutcome> runs = threshold_runs(capacities, levels);
  const CaseStatistics stats = case_statistics(runs, 0.139, 0.180);
  UNSIGNED_LONGS_EQUAL(440, stats.n_runs);
  UNSIGNED_LONGS_EQUAL(20, stats.survival.size());
  UNSIGNED_LONGS_EQUAL(0, stats.resurrections);
  // The lowest capacity is 0.221 − 2.00 · 0.055 = 0.111 g: the first collapse is at 0.12 g.
  const double lowest = *std::min_element(capacities.begin(), capacities.end());
  DOUBLES_EQUAL(0.1110, lowest, 5e-4);
  CHECK(stats.min_pga_collapse_g.has_value());
  DOUBLES_EQUAL(0.12, *stats.min_pga_collapse_g, 1e-12);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    std::size_t collapsed = 0;
    for (const double c : capacities) collapsed += levels[i] >= c ? 1 : 0;
    UNSIGNED_LONGS_EQUAL(collapsed, stats.survival[i].collapsed);
    UNSIGNED_LONGS_EQUAL(22, stats.survival[i].runs);
  }
  CHECK(stats.normal.ok);
  DOUBLES_EQUAL(0.221, stats.normal.mean_g, 0.001);
  DOUBLES_EQUAL(0.055, stats.normal.std_g, 0.001);
  CHECK(stats.lognormal.ok);
  DOUBLES_EQUAL(0.221, stats.lognormal.median_g, 0.01);  // the median of a near-symmetric capacity distribution
  CHECK(stats.lognormal.bootstrap_samples > 990);
  CHECK(stats.lognormal.median_ci90_low_g < stats.lognormal.median_g);
  CHECK(stats.lognormal.median_g < stats.lognormal.median_ci90_high_g);
  // The probabilities at the capacities are those of collapse_probability with the case's fits.
  const CollapseProbability ntc = collapse_probability(stats.survival, stats.normal, stats.lognormal, 0.139);
  DOUBLES_EQUAL(ntc.normal_fit.value(), stats.at_ntc2008.normal_fit.value(), 0.0);
  DOUBLES_EQUAL(ntc.lognormal_fit.value(), stats.at_ntc2008.lognormal_fit.value(), 0.0);
  DOUBLES_EQUAL(ntc.empirical.value(), stats.at_ntc2008.empirical.value(), 0.0);
  // 0.139 g: 0.9 of the way from 0.13 to 0.14; 0.180 g is a level.
  const double f13 = static_cast<double>(stats.survival[2].collapsed) / 22.0;
  const double f14 = static_cast<double>(stats.survival[3].collapsed) / 22.0;
  DOUBLES_EQUAL(f13 + 0.9 * (f14 - f13), stats.at_ntc2008.empirical.value(), 1e-12);
  DOUBLES_EQUAL(static_cast<double>(stats.survival[7].collapsed) / 22.0, stats.at_nzsee2016.empirical.value(), 1e-15);
  DOUBLES_EQUAL(phi((0.180 - stats.normal.mean_g) / stats.normal.std_g), stats.at_nzsee2016.normal_fit.value(), 1e-15);
}

TEST(CaseStatistics, NothingCollapsed) {
  const std::vector<RunOutcome> runs = threshold_runs({1.0, 2.0}, study_levels());
  const CaseStatistics stats = case_statistics(runs, 0.139, 0.180, {50, 1});
  CHECK_FALSE(stats.min_pga_collapse_g.has_value());
  CHECK_FALSE(stats.normal.ok);
  CHECK_FALSE(stats.lognormal.ok);
  CHECK_FALSE(stats.at_ntc2008.normal_fit.has_value());
  CHECK_FALSE(stats.at_ntc2008.lognormal_fit.has_value());
  DOUBLES_EQUAL(0.0, stats.at_ntc2008.empirical.value(), 0.0);
}

TEST(CaseStatistics, CountsResurrections) {
  std::vector<RunOutcome> runs = threshold_runs(quantile_capacities(22, 0.221, 0.055), study_levels());
  // Record 5 survives two levels above its capacity.
  std::size_t changed = 0;
  for (RunOutcome& run : runs) {
    if (run.record_index == 5 && run.collapsed && changed < 3) {
      if (changed > 0) run.collapsed = false;
      ++changed;
    }
  }
  const CaseStatistics stats = case_statistics(runs, 0.139, 0.180, {10, 1});
  UNSIGNED_LONGS_EQUAL(2, stats.resurrections);
}

TEST(CaseStatistics, RejectsBadInput) {
  check_throws_statistics_error([] { case_statistics({}, 0.139, 0.180); });
  check_throws_statistics_error([] { case_statistics({{0, 0.2, true}, {1, 0.1, false}}, std::nan(""), 0.180); });
  check_throws_statistics_error([] { case_statistics({{0, 0.2, true}, {1, 0.1, false}}, 0.139, HUGE_VAL); });
}
