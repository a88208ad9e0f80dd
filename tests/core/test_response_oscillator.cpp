// core::ResponseOscillator against closed-form SDOF responses ü + 2ζωu̇ + ω²u = −a_g(t) from rest. The recurrence is
// exact for input linear between samples, so step and ramp inputs must agree to rounding at any dt; a sine is only
// sampled, so it agrees to the interpolation error, O((Ωdt)²).
#include <cmath>
#include <cstddef>
#include <initializer_list>

#include "rockwatch/core/response_oscillator.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;

namespace {

constexpr double kPi = 3.14159265358979323846;

double omega_of(double period_s) { return 2.0 * kPi / period_s; }

// Constant a0 from t = 0: u(t) = −(a0/ω²)(1 − e^{−ζωt}(cos ω_d t + ζ/√(1−ζ²) sin ω_d t)).
double step_response_m(double a0, double omega, double zeta, double t) {
  const double root = std::sqrt(1.0 - zeta * zeta);
  const double wd = omega * root;
  return -(a0 / (omega * omega)) *
         (1.0 - std::exp(-zeta * omega * t) * (std::cos(wd * t) + zeta / root * std::sin(wd * t)));
}

// a_g = r·t from rest: u = −(r/ω²)(t − 2ζ/ω) + e^{−ζωt}(C1 cos ω_d t + C2 sin ω_d t).
double ramp_response_m(double r, double omega, double zeta, double t) {
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  const double c1 = -2.0 * zeta * r / (omega * omega * omega);
  const double c2 = r * (1.0 - 2.0 * zeta * zeta) / (omega * omega * wd);
  return -(r / (omega * omega)) * (t - 2.0 * zeta / omega) +
         std::exp(-zeta * omega * t) * (c1 * std::cos(wd * t) + c2 * std::sin(wd * t));
}

// a_g = A sin(Ωt) from rest: steady state X sin Ωt + Y cos Ωt plus the transient that starts it at rest.
double harmonic_response_m(double amp, double big_omega, double omega, double zeta, double t) {
  const double w2 = omega * omega, o2 = big_omega * big_omega;
  const double d = (w2 - o2) * (w2 - o2) + 4.0 * zeta * zeta * w2 * o2;
  const double x = -amp * (w2 - o2) / d;
  const double y = amp * 2.0 * zeta * omega * big_omega / d;
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  const double c1 = -y;
  const double c2 = (zeta * omega * c1 - x * big_omega) / wd;
  return x * std::sin(big_omega * t) + y * std::cos(big_omega * t) +
         std::exp(-zeta * omega * t) * (c1 * std::cos(wd * t) + c2 * std::sin(wd * t));
}

// Max |u − u_exact| over the run, relative to max(|u_exact|, `scale_m`): the scale keeps the ratio meaningful when
// every sample falls on a zero of the exact response (undamped, dt a multiple of T).
template <typename Input, typename Exact>
double max_relative_error(double period_s, double zeta, double dt_s, double t_end_s, Input input, Exact exact,
                          double scale_m = 0.0) {
  ResponseOscillator osc;
  CHECK(osc.init(period_s, zeta, dt_s) == OscillatorStatus::ok);
  osc.reset(input(0.0));
  const auto n = static_cast<std::size_t>(t_end_s / dt_s + 0.5);
  double max_error = 0.0, max_value = scale_m;
  for (std::size_t k = 1; k <= n; ++k) {
    const double t = dt_s * static_cast<double>(k);
    osc.step(input(t));
    const double expected = exact(t);
    max_error = std::fmax(max_error, std::fabs(osc.displacement_m() - expected));
    max_value = std::fmax(max_value, std::fabs(expected));
  }
  return max_error / max_value;
}

}  // namespace

TEST_GROUP(ResponseOscillator){};

// Periods from well below to well above dt: θ = ωdt from 0.0016 (series coefficients) to 628 (closed form).
TEST(ResponseOscillator, StepInputIsExactAtAnyDt) {
  const double a0 = 1.7;
  for (const double period_s : {0.01, 0.3, 1.0, 4.0}) {
    for (const double zeta : {0.0, 0.05, 0.3, 0.9}) {
      for (const double dt_s : {0.001, 0.005, 0.02, 0.1, 1.0}) {
        const double omega = omega_of(period_s);
        const double t_end_s = std::fmin(30.0 * period_s, 2000.0 * dt_s) + dt_s;
        const double err = max_relative_error(
            period_s, zeta, dt_s, t_end_s, [&](double) { return a0; },
            [&](double t) { return step_response_m(a0, omega, zeta, t); }, a0 / (omega * omega));
        CHECK_TEXT(err < 1e-12, "step response");
      }
    }
  }
}

TEST(ResponseOscillator, RampInputIsExactAtAnyDt) {
  const double r = 0.8;  // [m/s³]
  for (const double period_s : {0.05, 0.5, 3.0}) {
    for (const double zeta : {0.0, 0.05, 0.5}) {
      for (const double dt_s : {0.002, 0.01, 0.05, 0.2}) {
        const double omega = omega_of(period_s);
        const double err = max_relative_error(
            period_s, zeta, dt_s, 1000.0 * dt_s, [&](double t) { return r * t; },
            [&](double t) { return ramp_response_m(r, omega, zeta, t); });
        CHECK_TEXT(err < 1e-11, "ramp response");
      }
    }
  }
}

// Sampled sine: the interpolation error of the input is ≤ (Ωdt)²/8 of its amplitude; at 2000 samples per cycle that
// is 1.2e-6, so 1e-5 of the peak response is a bound with margin, at and away from resonance.
TEST(ResponseOscillator, HarmonicInputMatchesTransientPlusSteadyState) {
  const double amp = 2.0;
  for (const double ratio : {0.5, 1.0, 1.7}) {  // Ω/ω
    for (const double zeta : {0.02, 0.05, 0.2}) {
      const double period_s = 0.4;
      const double omega = omega_of(period_s);
      const double big_omega = ratio * omega;
      const double dt_s = 2.0 * kPi / big_omega / 2000.0;
      const double err = max_relative_error(
          period_s, zeta, dt_s, 40.0 * period_s, [&](double t) { return amp * std::sin(big_omega * t); },
          [&](double t) { return harmonic_response_m(amp, big_omega, omega, zeta, t); });
      CHECK_TEXT(err < 1e-5, "harmonic response");
    }
  }
}

// At resonance the steady-state amplitude is A/(2ζω²); after 30/(ζω) s the transient has decayed by e^{-30}, and
// the sampled peak of a 200-samples-per-cycle response is within (π/200)²/2 = 1.2e-4 of the true one.
TEST(ResponseOscillator, ResonantSteadyStateAmplitude) {
  const double amp = 1.0, period_s = 0.5, zeta = 0.05;
  const double omega = omega_of(period_s);
  const double dt_s = period_s / 200.0;
  ResponseOscillator osc;
  CHECK(osc.init(period_s, zeta, dt_s) == OscillatorStatus::ok);
  osc.reset(0.0);
  const double settle_s = 30.0 / (zeta * omega);
  const auto n_settle = static_cast<std::size_t>(settle_s / dt_s);
  std::size_t k = 1;
  for (; k <= n_settle; ++k) osc.step(amp * std::sin(omega * dt_s * static_cast<double>(k)));
  double peak = 0.0;
  for (const std::size_t end = k + 2000; k < end; ++k) {
    osc.step(amp * std::sin(omega * dt_s * static_cast<double>(k)));
    peak = std::fmax(peak, std::fabs(osc.displacement_m()));
  }
  const double expected = amp / (2.0 * zeta * omega * omega);
  DOUBLES_EQUAL(expected, peak, 2e-4 * expected);
}

// Undamped: A is a rotation of (ωu, u̇), so after the input stops ½u̇² + ½ω²u² stays constant. det A = 1 holds to
// rounding (~2e-16), so over 1e5 steps the energy may drift by ~1e5·2ε = 4e-11 (2.4e-11 measured): bound 1e-10.
TEST(ResponseOscillator, UndampedFreeVibrationKeepsItsEnergy) {
  for (const double dt_s : {0.001, 0.01, 0.3}) {
    const double period_s = 0.7;
    const double omega = omega_of(period_s);
    ResponseOscillator osc;
    CHECK(osc.init(period_s, 0.0, dt_s) == OscillatorStatus::ok);
    osc.reset(0.0);
    osc.step(3.0);  // a triangular pulse, then nothing
    osc.step(0.0);
    const auto energy = [&] {
      const double u = osc.displacement_m(), v = osc.velocity_mps();
      return 0.5 * v * v + 0.5 * omega * omega * u * u;
    };
    const double e0 = energy();
    CHECK(e0 > 0.0);
    for (int k = 0; k < 100000; ++k) {
      osc.step(0.0);
      DOUBLES_EQUAL(e0, energy(), 1e-10 * e0);
    }
    const OscillatorCoefficients& c = osc.coefficients();
    DOUBLES_EQUAL(1.0, c.a11 * c.a22 - c.a12 * c.a21, 1e-14);
  }
}

// Where the coefficients switch from the series to the closed form, both must give the same numbers.
TEST(ResponseOscillator, SeriesAndClosedFormAgreeAtTheSwitch) {
  for (const double zeta : {0.0, 0.05, 0.5, 0.95}) {
    for (const double theta : {0.3, detail::kSeriesBelowOmegaDt, 0.8}) {
      const double omega = 7.0, dt = theta / omega;
      const OscillatorCoefficients s = detail::series_coefficients(omega, zeta, dt);
      const OscillatorCoefficients c = detail::closed_form_coefficients(omega, zeta, dt);
      const double pairs[8][2] = {{s.a11, c.a11}, {s.a12, c.a12}, {s.a21, c.a21}, {s.a22, c.a22},
                                  {s.b11, c.b11}, {s.b12, c.b12}, {s.b21, c.b21}, {s.b22, c.b22}};
      for (const auto& p : pairs) DOUBLES_EQUAL(p[1], p[0], 1e-12 * std::fabs(p[1]));
    }
  }
}

// A period far below dt: the oscillator follows u ≈ −a_g/ω², so PSA is the peak sample (the PGA).
TEST(ResponseOscillator, VeryShortPeriodGivesThePga) {
  const double dt_s = 0.01;
  ResponseOscillator osc;
  CHECK(osc.init(dt_s / 100.0, 0.05, dt_s) == OscillatorStatus::ok);
  const double samples[] = {0.0, 0.3, -1.2, 2.5, -0.7, 1.1, 0.0, -2.4, 0.2, 0.0};
  osc.reset(samples[0]);
  for (std::size_t k = 1; k < sizeof samples / sizeof samples[0]; ++k) osc.step(samples[k]);
  DOUBLES_EQUAL(2.5, osc.psa_mps2(), 1e-3 * 2.5);
  DOUBLES_EQUAL(2.5, osc.max_abs_acceleration_mps2(), 1e-3 * 2.5);
}

TEST(ResponseOscillator, PeaksAndPseudoValues) {
  ResponseOscillator osc;
  CHECK(osc.init(1.0, kDefaultDampingRatio, 0.01) == OscillatorStatus::ok);
  osc.reset(0.0);
  for (int k = 1; k <= 300; ++k) osc.step(k < 50 ? 1.0 : 0.0);
  const double w = omega_of(1.0);
  CHECK(osc.sd_m() > 0.0);
  DOUBLES_EQUAL(w * osc.sd_m(), osc.psv_mps(), 1e-15);
  DOUBLES_EQUAL(w * w * osc.sd_m(), osc.psa_mps2(), 1e-14);
  // For small damping the peak absolute acceleration is close to the pseudo-acceleration.
  DOUBLES_EQUAL(osc.psa_mps2(), osc.max_abs_acceleration_mps2(), 0.1 * osc.psa_mps2());
  osc.reset(0.5);
  DOUBLES_EQUAL(0.0, osc.sd_m(), 0.0);
  DOUBLES_EQUAL(0.0, osc.displacement_m(), 0.0);
}

TEST(ResponseOscillator, RejectsInvalidInit) {
  ResponseOscillator osc;
  const double nan = std::nan("");
  const double inf = HUGE_VAL;
  CHECK(osc.init(0.0, 0.05, 0.01) == OscillatorStatus::period_not_positive);
  CHECK(osc.init(-1.0, 0.05, 0.01) == OscillatorStatus::period_not_positive);
  CHECK(osc.init(nan, 0.05, 0.01) == OscillatorStatus::period_not_positive);
  CHECK(osc.init(inf, 0.05, 0.01) == OscillatorStatus::period_not_positive);
  CHECK(osc.init(1.0, -0.01, 0.01) == OscillatorStatus::damping_out_of_range);
  CHECK(osc.init(1.0, 1.0, 0.01) == OscillatorStatus::damping_out_of_range);
  CHECK(osc.init(1.0, nan, 0.01) == OscillatorStatus::damping_out_of_range);
  CHECK(osc.init(1.0, 0.05, 0.0) == OscillatorStatus::dt_not_positive);
  CHECK(osc.init(1.0, 0.05, -0.01) == OscillatorStatus::dt_not_positive);
  CHECK(osc.init(1.0, 0.05, inf) == OscillatorStatus::dt_not_positive);
  CHECK(osc.init(1e-200, 0.05, 0.01) == OscillatorStatus::not_computable);
  CHECK_FALSE(osc.ready());
  osc.step(1.0);  // ignored while not initialised
  DOUBLES_EQUAL(0.0, osc.sd_m(), 0.0);
  CHECK(osc.init(1.0, 0.0, 0.01) == OscillatorStatus::ok);  // ζ = 0 is allowed
  CHECK(osc.ready());
  STRCMP_EQUAL("damping ratio must be in [0, 1)", oscillator_status_text(OscillatorStatus::damping_out_of_range));
}
