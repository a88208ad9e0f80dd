// sim::ForecastCalibration (SPEC §10 "Calibrated P"): the logistic fit recovers a known logistic model from synthetic
// data drawn from it, the clamp of logit P at half a member, the rows left out of a fit are never used, the
// coefficients' text, and the trailing maximum of the live monitor's energy feature.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/sim/synthesis/random_stream.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;

TEST_GROUP(ForecastCalibration){};

// 40 000 rows of (1, logit p̃, ρ, |x|/x_inst, logit p̃·min(ρ, 2)) drawn at random, outcomes drawn from a known
// logistic model: maximum likelihood must find its coefficients within a few standard errors (≈ 0.02–0.1 here).
TEST(ForecastCalibration, FitRecoversAKnownLogisticModel) {
  const double truth[5] = {-3.0, 0.8, 1.5, 2.0, -0.25};
  sim::synthesis::RandomStream rs(2029);
  const std::size_t n = 40000, k = sim::kCalibrationFeatures;
  std::vector<double> x(n * k);
  std::vector<std::uint8_t> y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double p = rs.uniform();
    const auto f = sim::calibration_features(p, 100, 2.5 * rs.uniform(), rs.uniform());
    double z = 0.0;
    for (std::size_t a = 0; a < k; ++a) {
      x[i * k + a] = f[a];
      z += truth[a] * f[a];
    }
    y[i] = rs.uniform() < 1.0 / (1.0 + std::exp(-z)) ? 1 : 0;
  }
  const std::vector<double> w = sim::fit_logistic_regression(x, k, y);
  LONGS_EQUAL(5, static_cast<long>(w.size()));
  DOUBLES_EQUAL(truth[0], w[0], 0.15);
  DOUBLES_EQUAL(truth[1], w[1], 0.08);
  DOUBLES_EQUAL(truth[2], w[2], 0.15);
  DOUBLES_EQUAL(truth[3], w[3], 0.2);
  DOUBLES_EQUAL(truth[4], w[4], 0.06);
  // Rows excluded by `use` play no part: the fit on the first half equals the fit on the first half's rows alone.
  std::vector<std::uint8_t> use(n, 0);
  for (std::size_t i = 0; i < n / 2; ++i) use[i] = 1;
  std::vector<double> x_half(x.begin(), x.begin() + static_cast<long>(n / 2 * k));
  std::vector<std::uint8_t> y_half(y.begin(), y.begin() + static_cast<long>(n / 2));
  const std::vector<double> a = sim::fit_logistic_regression(x, k, y, use);
  const std::vector<double> b = sim::fit_logistic_regression(x_half, k, y_half);
  for (std::size_t i = 0; i < k; ++i) DOUBLES_EQUAL(b[i], a[i], 0.0);
  // ... and flipping every outcome of the excluded rows changes nothing.
  std::vector<std::uint8_t> y_flip = y;
  for (std::size_t i = n / 2; i < n; ++i) y_flip[i] = y_flip[i] ? 0 : 1;
  const std::vector<double> c = sim::fit_logistic_regression(x, k, y_flip, use);
  for (std::size_t i = 0; i < k; ++i) DOUBLES_EQUAL(a[i], c[i], 0.0);
  // The fitted model is calibrated in sample: its mean probability equals the outcomes' frequency (the score
  // equation of the constant).
  double sum_p = 0.0, sum_y = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double z = 0.0;
    for (std::size_t j = 0; j < k; ++j) z += w[j] * x[i * k + j];
    sum_p += 1.0 / (1.0 + std::exp(-z));
    sum_y += y[i];
  }
  DOUBLES_EQUAL(sum_y / double(n), sum_p / double(n), 1e-6);
}

// Separable classes: the ridge keeps the weights finite and the probabilities on the right sides.
TEST(ForecastCalibration, SeparableDataStaysFinite) {
  std::vector<double> x;
  std::vector<std::uint8_t> y;
  for (int i = 0; i < 200; ++i) {
    const double v = double(i) / 200.0;
    x.insert(x.end(), {1.0, v});
    y.push_back(v > 0.5 ? 1 : 0);
  }
  const std::vector<double> w = sim::fit_logistic_regression(x, 2, y);
  CHECK(std::isfinite(w[0]) && std::isfinite(w[1]));
  CHECK(w[0] + w[1] * 0.9 > 0.0);
  CHECK(w[0] + w[1] * 0.1 < 0.0);
}

TEST(ForecastCalibration, LogitIsClampedAtHalfAMember) {
  DOUBLES_EQUAL(std::log(0.005 / 0.995), sim::ensemble_logit(0.0, 100), 1e-12);
  DOUBLES_EQUAL(-std::log(0.005 / 0.995), sim::ensemble_logit(1.0, 100), 1e-12);
  DOUBLES_EQUAL(0.0, sim::ensemble_logit(0.5, 100), 1e-15);
  DOUBLES_EQUAL(std::log(0.3 / 0.7), sim::ensemble_logit(0.3, 200), 1e-12);
  // P_cal with c = (c0, 1, 0, 0) is Platt's scaling: the logistic of logit p + c0.
  sim::ForecastCalibration cal;
  cal.c = {0.0, 1.0, 0.0, 0.0, 0.0};
  DOUBLES_EQUAL(0.3, sim::calibrated_probability(cal, 0.3, 100, 5.0, 5.0), 1e-12);
  cal.c = {-1.0, 0.5, 2.0, -1.0, 0.0};
  const double z = -1.0 + 0.5 * std::log(0.2 / 0.8) + 2.0 * 0.7 - 1.0 * 0.4;
  DOUBLES_EQUAL(1.0 / (1.0 + std::exp(-z)), sim::calibrated_probability(cal, 0.2, 50, 0.7, 0.4), 1e-12);
  // The shipped coefficients (3 s and 5 s, none for 4 s): P rises with the ensemble's P, and the state's own features
  // only correct it (the ensemble carries the state: at the same raw P, |x|/x_inst from 0.1 to 0.8 moves P by less
  // than 0.1 either way; fitted on all real records the 5 s c3 is slightly negative, SPEC §10).
  CHECK_FALSE(sim::default_forecast_calibration(4.0).has_value());
  CHECK_FALSE(sim::default_forecast_calibration(4.0, true).has_value());
  for (const double h : {3.0, 5.0}) {
    // The fused state's own coefficients at the same horizons, fitted on fused forecasts: not the open loop's.
    const sim::ForecastCalibration open = *sim::default_forecast_calibration(h);
    const sim::ForecastCalibration fused = *sim::default_forecast_calibration(h, true);
    DOUBLES_EQUAL(h, fused.horizon_s, 0.0);
    CHECK(open.c != fused.c);
    CHECK(fused.source.find("from the fused state") != std::string::npos);
    CHECK(open.source.find("fused") == std::string::npos);
  }
  for (const auto& [h, from_fused] : {std::pair{3.0, false}, std::pair{5.0, false}, std::pair{3.0, true},
                                      std::pair{5.0, true}}) {
    const sim::ForecastCalibration d = *sim::default_forecast_calibration(h, from_fused);
    DOUBLES_EQUAL(h, d.horizon_s, 0.0);
    CHECK(sim::calibrated_probability(d, 0.9, 100, 0.5, 0.3) > sim::calibrated_probability(d, 0.1, 100, 0.5, 0.3));
    const double moved =
        sim::calibrated_probability(d, 0.5, 100, 0.5, 0.8) - sim::calibrated_probability(d, 0.5, 100, 0.5, 0.1);
    CHECK(std::fabs(moved) < 0.1);
  }
}

// The interaction c4·logit p̃·min(ρ_max, 2) (issue 29's second calibration): the weight of the ensemble's logit
// moves with the energy up to twice the barrier and no further; with c4 = 0 the first calibration's P exactly.
TEST(ForecastCalibration, InteractionOfLogitAndCappedEnergy) {
  const auto f = sim::calibration_features(0.2, 100, 1.5, 0.3);
  const double l = std::log(0.2 / 0.8);
  DOUBLES_EQUAL(l * 1.5, f[4], 1e-12);
  DOUBLES_EQUAL(l * 2.0, sim::calibration_features(0.2, 100, 3.7, 0.3)[4], 1e-12);  // capped at 2
  DOUBLES_EQUAL(1.5, sim::calibration_features(0.2, 100, 1.5, 0.3)[2], 0.0);
  DOUBLES_EQUAL(3.7, sim::calibration_features(0.2, 100, 3.7, 0.3)[2], 0.0);        // ρ_max itself is not capped
  sim::ForecastCalibration first, second;
  first.c = {-1.0, 0.8, 0.3, 1.5, 0.0};
  second = first;
  second.c[4] = -0.2;
  const double z = -1.0 + 0.8 * l + 0.3 * 1.5 + 1.5 * 0.3;
  DOUBLES_EQUAL(1.0 / (1.0 + std::exp(-z)), sim::calibrated_probability(first, 0.2, 100, 1.5, 0.3), 1e-12);
  DOUBLES_EQUAL(1.0 / (1.0 + std::exp(-(z - 0.2 * l * 1.5))), sim::calibrated_probability(second, 0.2, 100, 1.5, 0.3),
                1e-12);
  // c4 < 0: at high energy a high raw P is trusted less (P_cal lower) and a low raw P less too (P_cal higher).
  CHECK(sim::calibrated_probability(second, 0.9, 100, 1.8, 0.3) <
        sim::calibrated_probability(first, 0.9, 100, 1.8, 0.3));
  CHECK(sim::calibrated_probability(second, 0.05, 100, 1.8, 0.3) >
        sim::calibrated_probability(first, 0.05, 100, 1.8, 0.3));
  // Monotone in the raw P whenever c1 + c4·min(ρ, 2) > 0 (the shipped coefficients at every ρ up to the cap and
  // beyond), and deterministic.
  for (const auto& [h, from_fused] : {std::pair{3.0, false}, std::pair{5.0, false}, std::pair{3.0, true},
                                      std::pair{5.0, true}}) {
    const sim::ForecastCalibration d = *sim::default_forecast_calibration(h, from_fused);
    CHECK(d.c[1] + std::min(0.0, d.c[4]) * sim::kCalibrationInteractionEnergyCap > 0.0);
    for (const double rho : {0.0, 0.5, 1.0, 1.5, 2.0, 4.0}) {
      double last = -1.0;
      for (int k = 0; k <= 100; ++k) {
        const double p = sim::calibrated_probability(d, k / 100.0, 100, rho, 0.4);
        CHECK(p >= last);
        DOUBLES_EQUAL(p, sim::calibrated_probability(d, k / 100.0, 100, rho, 0.4), 0.0);
        last = p;
      }
    }
  }
}

TEST(ForecastCalibration, CoefficientsText) {
  std::string why;
  const auto c = sim::parse_forecast_calibration("-2.5,0.75,1e0,0", 3.0, &why);
  CHECK(c.has_value());
  DOUBLES_EQUAL(-2.5, c->c[0], 0.0);
  DOUBLES_EQUAL(0.75, c->c[1], 0.0);
  DOUBLES_EQUAL(1.0, c->c[2], 0.0);
  DOUBLES_EQUAL(0.0, c->c[3], 0.0);
  DOUBLES_EQUAL(3.0, c->horizon_s, 0.0);
  DOUBLES_EQUAL(0.0, c->c[4], 0.0);  // four numbers: the first calibration's model, no interaction
  const auto five = sim::parse_forecast_calibration("-2.5,0.75,1e0,0,-0.125", 5.0, &why);
  CHECK(five.has_value());
  DOUBLES_EQUAL(-0.125, five->c[4], 0.0);
  DOUBLES_EQUAL(0.75, five->c[1], 0.0);
  for (const char* bad : {"", "1,2,3", "1,2,3,4,5,6", "1,,3,4", "1,2,3,x", "1,2,3,nan", "1,2,3,inf", "1,2,3,4,",
                          "1,2,3,4,x", "1,2,3,4,nan"}) {
    CHECK_FALSE_TEXT(sim::parse_forecast_calibration(bad, 3.0, &why).has_value(), bad);
  }
}

TEST(ForecastCalibration, TrailingMaxOverTwoSeconds) {
  sim::TrailingMax m(8, 2.0);
  CHECK_FALSE(m.max().has_value());
  m.push(0.0, 3.0);
  m.push(1.0, 1.0);
  DOUBLES_EQUAL(3.0, *m.max(), 0.0);
  m.push(2.0, 0.5);
  DOUBLES_EQUAL(3.0, *m.max(), 0.0);  // t = 0 is still within [0, 2]
  m.push(2.5, 0.2);
  DOUBLES_EQUAL(1.0, *m.max(), 0.0);  // [0.5, 2.5]
  m.push(1.0, 0.1);                   // back in time: the window starts again
  DOUBLES_EQUAL(0.1, *m.max(), 0.0);
  // A full ring keeps the last 8 samples.
  sim::TrailingMax r(4, 100.0);
  for (int i = 0; i < 10; ++i) r.push(double(i), double(10 - i));
  DOUBLES_EQUAL(4.0, *r.max(), 0.0);  // samples 6..9: 4, 3, 2, 1
}
