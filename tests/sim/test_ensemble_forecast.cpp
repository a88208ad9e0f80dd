// sim::EnsembleForecaster (SPEC §10): the ground model's fit, determinism (same input and seed → same bits), a wall at
// rest, the limits P → 1 (beyond x_inst, moving outward) and P → 0 (quiet ground, small motion), the Monte-Carlo
// standard error against the spread of independent ensembles, settings out of range, and no allocation per forecast.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/ensemble_forecast.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;

namespace {

constexpr double kPi = 3.14159265358979323846;

sim::EnsembleForecaster make(const sim::ForecastSettings& s) {
  const core::WallParameters w = core::paper_wall();
  return sim::EnsembleForecaster(w, core::ModelKind::linear, core::restitution_energy_ratio(w, core::Restitution{}),
                                 2.0, s);
}

std::vector<double> sine(double amp, double f_hz, double decay_per_s, double dt, double t_end) {
  std::vector<double> v;
  for (int k = 0; double(k) * dt <= t_end + 1e-12; ++k) {
    const double t = double(k) * dt;
    v.push_back(amp * std::exp(decay_per_s * t) * std::sin(2.0 * kPi * f_hz * t + 0.3));
  }
  return v;
}

double x_inst(const sim::EnsembleForecaster& f) { return std::fmin(f.setup().x_inst_m[0], f.setup().x_inst_m[1]); }

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_GROUP(EnsembleForecast){};

TEST(EnsembleForecast, GroundModelFitsFrequencyLevelAndEnvelope) {
  sim::ForecastSettings s;
  const std::vector<double> steady = sine(2.0, 2.0, 0.0, 0.005, 10.0);
  const sim::GroundModel g = sim::fit_ground_model(steady.data(), steady.size(), 0.005, s);
  DOUBLES_EQUAL(4.0, g.zero_crossing_rate_hz, 0.3);     // 2 Hz: 4 sign changes a second
  DOUBLES_EQUAL(2.0 * kPi * 2.0, g.omega_rps, 0.3 * kPi);
  DOUBLES_EQUAL(2.0 / std::sqrt(2.0), g.sigma_now_mps2, 0.05);
  DOUBLES_EQUAL(0.0, g.growth_per_s, 0.03);
  DOUBLES_EQUAL(4.0, g.window_used_s, 1e-9);
  // A decaying motion: β follows the decay, σ_now the level at the forecast time.
  const std::vector<double> decaying = sine(2.0, 3.0, -0.5, 0.005, 10.0);
  const sim::GroundModel d = sim::fit_ground_model(decaying.data(), decaying.size(), 0.005, s);
  DOUBLES_EQUAL(-0.5, d.growth_per_s, 0.05);
  DOUBLES_EQUAL(2.0 * std::exp(-5.0) / std::sqrt(2.0), d.sigma_now_mps2, 0.15 * 2.0 * std::exp(-5.0));
  // Growth is clamped; a record of zeros has no ground to come.
  const std::vector<double> growing = sine(0.01, 3.0, 1.0, 0.005, 10.0);
  DOUBLES_EQUAL(s.growth_max_per_s, sim::fit_ground_model(growing.data(), growing.size(), 0.005, s).growth_per_s, 0.0);
  const std::vector<double> zeros(500, 0.0);
  DOUBLES_EQUAL(0.0, sim::fit_ground_model(zeros.data(), zeros.size(), 0.005, s).sigma_now_mps2, 0.0);
}

// SPEC §10: the discrete ground process has unit variance (with and without the high-pass stage); without the
// high-pass its zero-crossing rate is ω_g/π; the high-pass takes out low-frequency energy (the velocity ∫u).
TEST(EnsembleForecast, UnitGroundProcessHasUnitVarianceAndTheFittedFrequency) {
  constexpr std::size_t kN = 200000;  // 2000 s at 10 ms
  std::vector<double> u(kN);
  double velocity_rms[2] = {};
  for (int hp = 0; hp < 2; ++hp) {
    sim::ForecastSettings s;
    s.highpass_ratio = hp == 0 ? 0.0 : 0.1;
    const double omega = 2.0 * kPi * 3.0;
    sim::sample_unit_ground(omega, s, 7, u.data(), kN);
    double sum2 = 0.0, v = 0.0, v_sum = 0.0, v_sum2 = 0.0;
    int crossings = 0;
    for (std::size_t i = 0; i < kN; ++i) {
      sum2 += u[i] * u[i];
      if (i > 0 && (u[i] > 0.0) != (u[i - 1] > 0.0)) ++crossings;
      v += u[i] * s.step_s;
      v_sum += v;
      v_sum2 += v * v;
    }
    DOUBLES_EQUAL(1.0, sum2 / double(kN), 0.05);
    const double rate_hz = double(crossings) / (double(kN) * s.step_s);
    if (hp == 0) DOUBLES_EQUAL(omega / kPi, rate_hz, 0.1 * omega / kPi);
    velocity_rms[hp] = std::sqrt(v_sum2 / double(kN) - (v_sum / double(kN)) * (v_sum / double(kN)));
  }
  CHECK_TEXT(velocity_rms[1] < 0.5 * velocity_rms[0],
             (std::to_string(velocity_rms[1]) + " vs " + std::to_string(velocity_rms[0])).c_str());
}

TEST(EnsembleForecast, SameInputAndSeedGiveTheSameBits) {
  sim::ForecastSettings s;
  s.members = 40;
  s.horizon_s = 2.0;
  sim::EnsembleForecaster a = make(s), b = make(s);
  const std::vector<double> ug = sine(0.5, 2.0, 0.0, 0.01, 6.0);
  sim::ForecastState st;
  st.moving = true;
  st.x_m = 0.2 * x_inst(a);
  st.xd_mps = 0.3 * a.velocity_scale_mps();
  st.ug_now_mps2 = ug.back();
  const sim::ForecastResult ra = a.forecast(st, ug.data(), ug.size(), 0.01);
  const sim::ForecastResult rb = b.forecast(st, ug.data(), ug.size(), 0.01);
  const sim::ForecastResult ra2 = a.forecast(st, ug.data(), ug.size(), 0.01);  // a second call on the same object
  CHECK(ra.status == sim::ForecastStatus::ok);
  LONGS_EQUAL(40, ra.members);
  for (const sim::ForecastResult* r : {&rb, &ra2}) {
    LONGS_EQUAL(ra.collapsed, r->collapsed);
    CHECK(same_bits(ra.p_collapse, r->p_collapse));
    CHECK(same_bits(ra.q50_max_x_over_x_inst, r->q50_max_x_over_x_inst));
    CHECK(same_bits(ra.q90_max_x_over_x_inst, r->q90_max_x_over_x_inst));
  }
  CHECK(ra.q90_max_x_over_x_inst >= ra.q50_max_x_over_x_inst);
  // Another seed draws other members.
  s.seed = 30;
  sim::EnsembleForecaster c = make(s);
  const sim::ForecastResult rc = c.forecast(st, ug.data(), ug.size(), 0.01);
  CHECK(!same_bits(ra.q50_max_x_over_x_inst, rc.q50_max_x_over_x_inst) ||
        !same_bits(ra.q90_max_x_over_x_inst, rc.q90_max_x_over_x_inst) || ra.collapsed != rc.collapsed);
}

TEST(EnsembleForecast, AWallAtRestSaysSo) {
  sim::EnsembleForecaster f = make(sim::ForecastSettings{});
  const std::vector<double> ug = sine(1.0, 2.0, 0.0, 0.01, 5.0);
  sim::ForecastState st;  // moving = false
  const sim::ForecastResult r = f.forecast(st, ug.data(), ug.size(), 0.01);
  CHECK(r.status == sim::ForecastStatus::wall_at_rest);
  LONGS_EQUAL(0, r.members);
  DOUBLES_EQUAL(0.0, r.p_collapse, 0.0);
}

TEST(EnsembleForecast, BeyondInstabilityMovingOutwardCollapses) {
  sim::ForecastSettings s;
  s.members = 50;
  s.horizon_s = 3.0;
  sim::EnsembleForecaster f = make(s);
  sim::ForecastState st;
  st.moving = true;
  st.x_m = -1.3 * x_inst(f);
  st.xd_mps = -0.2 * f.velocity_scale_mps();
  sim::GroundModel quiet;  // no ground to come
  quiet.omega_rps = 10.0;
  const sim::ForecastResult r = f.forecast(st, quiet);
  LONGS_EQUAL(50, r.collapsed);
  DOUBLES_EQUAL(1.0, r.p_collapse, 0.0);
  DOUBLES_EQUAL(0.0, r.p_collapse_se, 0.0);
  DOUBLES_EQUAL(2.0, r.q50_max_x_over_x_inst, 1e-12);  // κ
}

TEST(EnsembleForecast, QuietGroundAndSmallMotionDoNotCollapse) {
  sim::ForecastSettings s;
  s.members = 50;
  s.horizon_s = 3.0;
  sim::EnsembleForecaster f = make(s);
  const std::vector<double> ug = sine(0.05, 3.0, 0.0, 0.01, 5.0);  // far below the start threshold
  sim::ForecastState st;
  st.moving = true;
  st.x_m = 0.05 * x_inst(f);
  st.xd_mps = 0.05 * f.velocity_scale_mps();
  st.ug_now_mps2 = ug.back();
  const sim::ForecastResult r = f.forecast(st, ug.data(), ug.size(), 0.01);
  // At most one member of 50: the intensity to come has a long tail (s_I = 1.5: one member in 50 draws a factor of
  // about 10), and with the default state spread (5 %) or the ground's phase one such member falls (P = 0.02);
  // with the 1 % spread of the first version and no conditioning none did.
  CHECK(r.collapsed <= 1);
  CHECK(r.p_collapse <= 0.02);
  CHECK(r.q90_max_x_over_x_inst < 0.2);
  CHECK(r.q50_max_x_over_x_inst > 0.0);
}

// Independent ensembles (other seeds) spread around their mean by √(p(1−p)/N), the standard error each reports.
TEST(EnsembleForecast, StandardErrorMatchesTheSpreadOfIndependentEnsembles) {
  sim::ForecastSettings s;
  s.members = 50;
  s.horizon_s = 2.0;
  s.default_sigma_fraction = 0.05;
  const std::vector<double> ug = sine(0.5, 1.5, 0.0, 0.01, 5.0);
  constexpr int kEnsembles = 30;
  double sum = 0.0, sum2 = 0.0, se_sum = 0.0;
  for (int e = 0; e < kEnsembles; ++e) {
    s.seed = 1000 + std::uint64_t(e);
    sim::EnsembleForecaster f = make(s);
    sim::ForecastState st;
    st.moving = true;
    st.x_m = 0.2 * x_inst(f);
    st.xd_mps = 0.2 * f.velocity_scale_mps();
    st.ug_now_mps2 = ug.back();
    const sim::ForecastResult r = f.forecast(st, ug.data(), ug.size(), 0.01);
    DOUBLES_EQUAL(std::sqrt(r.p_collapse * (1.0 - r.p_collapse) / 50.0), r.p_collapse_se, 1e-15);
    sum += r.p_collapse;
    sum2 += r.p_collapse * r.p_collapse;
    se_sum += r.p_collapse_se;
  }
  const double mean = sum / kEnsembles;
  const double sd = std::sqrt((sum2 - kEnsembles * mean * mean) / (kEnsembles - 1));
  CHECK_TEXT(mean > 0.1 && mean < 0.9, ("mean p = " + std::to_string(mean)).c_str());
  const double predicted = std::sqrt(mean * (1.0 - mean) / 50.0);
  // With 30 ensembles the sample SD is within ±13 % (1σ) of the truth: allow ±45 %.
  CHECK_TEXT(sd > 0.55 * predicted && sd < 1.45 * predicted,
             ("sd " + std::to_string(sd) + " predicted " + std::to_string(predicted)).c_str());
  DOUBLES_EQUAL(predicted, se_sum / kEnsembles, 0.25 * predicted);
}

TEST(EnsembleForecast, SettingsOutOfRangeAreNamed) {
  auto error_of = [](sim::ForecastSettings s) -> std::string {
    try {
      make(s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  sim::ForecastSettings s;
  s.members = 0;
  CHECK(error_of(s).find("members") != std::string::npos);
  s = sim::ForecastSettings{};
  s.horizon_s = 0.0;
  CHECK(error_of(s).find("horizon_s") != std::string::npos);
  s.horizon_s = 61.0;
  CHECK(error_of(s).find("horizon_s") != std::string::npos);
  s = sim::ForecastSettings{};
  s.step_s = 0.02;
  CHECK(error_of(s).find("step_s") != std::string::npos);
  CHECK(error_of(sim::ForecastSettings{}).empty());
}

// The ground's phase (SPEC §10, condition_on_record): the filter's state at the forecast time, conditioned on the
// record by a Kalman filter, reproduces the record's ü(t)/σ_now and carries the sign of its velocity (∫ü), for
// both ends of a cycle; without conditioning the ground model carries no state.
TEST(EnsembleForecast, GroundPhaseIsConditionedOnTheRecord) {
  sim::ForecastSettings s;
  s.members = 20;
  s.horizon_s = 1.0;
  CHECK(s.condition_on_record);  // the default
  sim::EnsembleForecaster f = make(s);
  sim::ForecastState st;
  st.moving = true;
  st.x_m = 0.1 * x_inst(f);
  for (const double t_end : {5.0, 5.5, 5.25, 5.75}) {  // 1 Hz: velocity −cos: t = 5 → v < 0, 5.5 → v > 0
    const std::vector<double> ug = sine(2.0, 1.0, 0.0, 0.005, t_end);
    const double phase = 2.0 * kPi * 1.0 * t_end + 0.3;
    st.ug_now_mps2 = ug.back();
    const sim::ForecastResult r = f.forecast(st, ug.data(), ug.size(), 0.005);
    CHECK(r.ground.conditioned);
    const double omega_f = s.highpass_ratio * r.ground.omega_rps;
    const double* m = r.ground.filter_mean;
    const double u = m[0] - 2.0 * s.damping * omega_f * m[3] - omega_f * omega_f * m[2];
    DOUBLES_EQUAL(ug.back() / r.ground.sigma_now_mps2, u, 0.15);
    const double velocity = -2.0 / (2.0 * kPi) * std::cos(phase);  // ∫ü of the sine
    if (std::fabs(velocity) > 0.1) CHECK_TEXT((m[3] > 0.0) == (velocity > 0.0), std::to_string(t_end).c_str());
  }
  s.condition_on_record = false;
  sim::EnsembleForecaster g = make(s);
  const std::vector<double> ug = sine(2.0, 1.0, 0.0, 0.005, 5.0);
  CHECK_FALSE(g.forecast(st, ug.data(), ug.size(), 0.005).ground.conditioned);
}
