// sim::intensity_measures and its parts: Arias intensity and Husid times of signals with known integrals, the
// significant durations the record collection's manifest lists, PGV/PGD of hand-made pulses through the baseline
// correction, and rejections.
#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "reference_data.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/measure_error.hpp"

#include "check_throws.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_intensity_measures {

namespace sim = rockwatch::sim;
namespace records = rockwatch::records;
using rockwatch::test::data_path;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;

std::vector<double> sampled(const std::function<double(double)>& a, double dt_s, std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t k = 0; k < n; ++k) v[k] = a(dt_s * static_cast<double>(k));
  return v;
}

// A full-sine acceleration pulse A sin(2π(t − t0)/Tp) on [t0, t0 + Tp], zero elsewhere; `sign` flips it.
double sine_pulse(double t, double amp, double t0, double tp, double sign = 1.0) {
  if (t < t0 || t > t0 + tp) return 0.0;
  return sign * amp * std::sin(2.0 * kPi * (t - t0) / tp);
}

records::Record read(const char* file) { return records::read_record(data_path(std::string("records/") + file)); }

template <typename Fn>
void check_throws_measure_error(Fn fn) {
  rockwatch::test::check_throws<sim::MeasureError>(fn, "expected sim::MeasureError");
}

}  // namespace

TEST_GROUP(AriasIntensity){};

// A sin over whole cycles: ∫ a² dt = A²/2 · duration. The trapezoidal sum of sin² over whole cycles with ≥ 3
// samples per cycle is exactly that, so only rounding remains.
TEST(AriasIntensity, SineOverWholeCycles) {
  const double amp = 2.3, period_s = 0.25, dt_s = 0.005;  // 50 samples per cycle
  const std::size_t cycles = 40;
  const std::size_t n = cycles * 50 + 1;
  const std::vector<double> a = sampled([&](double t) { return amp * std::sin(2.0 * kPi * t / period_s); }, dt_s, n);
  const double duration_s = period_s * static_cast<double>(cycles);
  const double expected = kPi / (2.0 * kG) * amp * amp / 2.0 * duration_s;
  DOUBLES_EQUAL(expected, sim::arias_intensity_mps(a, dt_s, kG), 1e-12 * expected);
  DOUBLES_EQUAL(expected, sim::intensity_measures(a, dt_s, kG).arias_mps, 1e-12 * expected);
  // I_A ∝ 1/g: the same record with another g.
  DOUBLES_EQUAL(expected * kG / 9.80665, sim::arias_intensity_mps(a, dt_s, 9.80665), 1e-12 * expected);
}

// Constant |a|: the Husid curve is a straight line, so t_f = f·T and D5-75 = 0.70 T, D5-95 = 0.90 T.
TEST(AriasIntensity, HusidOfConstantPowerIsLinear) {
  const double dt_s = 0.01;
  const std::vector<double> a = sampled([](double t) { return std::fmod(t, 0.02) < 0.005 ? 1.5 : -1.5; }, dt_s, 1001);
  const double duration_s = 10.0;
  const sim::IntensityMeasures im = sim::intensity_measures(a, dt_s, kG);
  CHECK(im.t5_s && im.t75_s && im.t95_s && im.d5_75_s && im.d5_95_s);
  DOUBLES_EQUAL(0.05 * duration_s, *im.t5_s, 1e-12);
  DOUBLES_EQUAL(0.75 * duration_s, *im.t75_s, 1e-12);
  DOUBLES_EQUAL(0.95 * duration_s, *im.t95_s, 1e-12);
  DOUBLES_EQUAL(0.70 * duration_s, *im.d5_75_s, 1e-12);
  DOUBLES_EQUAL(0.90 * duration_s, *im.d5_95_s, 1e-12);
  const std::vector<double> h = sim::husid_curve(a, dt_s);
  DOUBLES_EQUAL(0.0, h.front(), 0.0);
  DOUBLES_EQUAL(1.0, h.back(), 0.0);
}

// The crossing is interpolated linearly between the samples around it.
TEST(AriasIntensity, HusidCrossingIsInterpolated) {
  const std::vector<double> h{0.0, 0.2, 0.6, 1.0};
  DOUBLES_EQUAL(0.5 * 0.1, *sim::husid_time_s(h, 0.1, 0.1), 1e-15);
  DOUBLES_EQUAL(0.1 + 0.75 * 0.1, *sim::husid_time_s(h, 0.1, 0.5), 1e-15);
  DOUBLES_EQUAL(0.2, *sim::husid_time_s(h, 0.1, 0.6), 1e-15);
  DOUBLES_EQUAL(0.3, *sim::husid_time_s(h, 0.1, 1.0), 1e-15);
  check_throws_measure_error([&] { sim::husid_time_s(h, 0.1, 0.0); });
  check_throws_measure_error([&] { sim::husid_time_s(h, 0.1, 1.5); });
}

// The manifest of the shared record collection (D5-75, D5-95 from the normalised Arias intensity of the whole
// file, quoted to 0.1 s).
TEST(AriasIntensity, SignificantDurationsOfTheRealRecords) {
  struct Case {
    const char* file;
    double d5_75_s, d5_95_s;
  };
  const Case cases[] = {{"RSN6_IMPVALL.I_I-ELC180-hor1.AT2", 12.2, 24.2}, {"RSN175_IMPVALL.H_H-E12140.AT2", 9.6, 19.6}};
  for (const Case& c : cases) {
    const records::Record r = read(c.file);
    const sim::IntensityMeasures im = sim::intensity_measures(r.horizontal_mps2, r.dt_s, kG);
    DOUBLES_EQUAL_TEXT(c.d5_75_s, *im.d5_75_s, 0.1, c.file);
    DOUBLES_EQUAL_TEXT(c.d5_95_s, *im.d5_95_s, 0.1, c.file);
    CHECK(im.arias_mps > 0.0);
  }
}

TEST(AriasIntensity, SilentRecordHasNoDurations) {
  const std::vector<double> a(100, 0.0);
  const sim::IntensityMeasures im = sim::intensity_measures(a, 0.01, kG);
  DOUBLES_EQUAL(0.0, im.pga_mps2, 0.0);
  DOUBLES_EQUAL(0.0, im.pgv_mps, 0.0);
  DOUBLES_EQUAL(0.0, im.pgd_m, 0.0);
  DOUBLES_EQUAL(0.0, im.arias_mps, 0.0);
  CHECK_FALSE(im.t5_s.has_value());
  CHECK_FALSE(im.d5_75_s.has_value());
  CHECK_FALSE(im.d5_95_s.has_value());
}

TEST_GROUP(PeakGroundMotion){};

// Two opposite full-sine pulses: the velocity A·Tp/(2π)·(1 − cos) returns to zero after each, and the displacement
// rises to D = A·Tp²/(2π) at the end of the first and returns to 0 after the second: PGV = A·Tp/π, PGD = D, no
// residual. On a 40 s record the fitted baseline of such a compact pulse is small (of order Tp/L of the motion).
TEST(PeakGroundMotion, OppositeSinePulsesKeepTheirPeaks) {
  const double amp = 3.0, tp = 1.0, t0 = 2.0, dt_s = 0.005;
  const std::vector<double> a = sampled(
      [&](double t) { return sine_pulse(t, amp, t0, tp) + sine_pulse(t, amp, t0 + tp, tp, -1.0); }, dt_s, 8001);
  const sim::IntensityMeasures im = sim::intensity_measures(a, dt_s, kG);
  const double pgv = amp * tp / kPi;
  const double pgd = amp * tp * tp / (2.0 * kPi);
  DOUBLES_EQUAL(amp, im.pga_mps2, 1e-3 * amp);
  DOUBLES_EQUAL(pgv, im.pgv_mps, 0.002 * pgv);  // 4e-5 measured
  DOUBLES_EQUAL(pgd, im.pgd_m, 0.005 * pgd);    // 2e-4 measured
  // The corrected motion ends near rest where it started (4e-4 and 4e-3 of the peaks measured).
  const sim::BaselineCorrectedMotion m = sim::baseline_corrected_motion(a, dt_s);
  DOUBLES_EQUAL(0.0, m.vel_mps.back(), 0.002 * pgv);
  DOUBLES_EQUAL(0.0, m.disp_m.back(), 0.01 * pgd);
}

// One full-sine pulse ends with zero velocity and a residual displacement A·Tp²/(2π). The polynomial baseline
// removes that (as it removes any permanent offset), but must leave the velocity pulse nearly intact.
TEST(PeakGroundMotion, SingleSinePulseKeepsItsVelocity) {
  const double amp = 2.0, tp = 0.8, t0 = 1.0, dt_s = 0.005;
  const std::vector<double> a = sampled([&](double t) { return sine_pulse(t, amp, t0, tp); }, dt_s, 8001);
  const sim::IntensityMeasures im = sim::intensity_measures(a, dt_s, kG);
  const double pgv = amp * tp / kPi;
  DOUBLES_EQUAL(pgv, im.pgv_mps, 0.01 * pgv);  // 0.5 % measured
  // At the end of the pulse the velocity is back to ~0 (0.6 % of PGV measured); afterwards the correction, which
  // takes the residual displacement out, leaves a slow velocity of order residual/L.
  const sim::BaselineCorrectedMotion m = sim::baseline_corrected_motion(a, dt_s);
  const auto end_of_pulse = static_cast<std::size_t>((t0 + tp) / dt_s + 0.5);
  DOUBLES_EQUAL(0.0, m.vel_mps[end_of_pulse], 0.01 * pgv);
  const double residual_m = amp * tp * tp / (2.0 * kPi);
  CHECK(im.pgd_m <= residual_m * 1.01);
}

// An instrument offset (constant over the whole record, 2 % of the peak) would integrate to a velocity drift of
// 0.02·A·L = 2.4 m/s over 40 s; it integrates exactly to c·t²/2, which the fit's t² term removes exactly, so the
// result equals the clean signal's to rounding.
TEST(PeakGroundMotion, ConstantOffsetIsRemovedExactly) {
  const double amp = 3.0, tp = 1.0, t0 = 2.0, dt_s = 0.005, offset = 0.02 * amp;
  const auto clean = [&](double t) { return sine_pulse(t, amp, t0, tp) + sine_pulse(t, amp, t0 + tp, tp, -1.0); };
  const std::vector<double> a_clean = sampled(clean, dt_s, 8001);
  const std::vector<double> a_offset = sampled([&](double t) { return clean(t) + offset; }, dt_s, 8001);
  const sim::BaselineCorrectedMotion m_clean = sim::baseline_corrected_motion(a_clean, dt_s);
  const sim::BaselineCorrectedMotion m_offset = sim::baseline_corrected_motion(a_offset, dt_s);
  DOUBLES_EQUAL(m_clean.c2_mps2 + offset / 2.0, m_offset.c2_mps2, 1e-9);
  DOUBLES_EQUAL(m_clean.c3_mps3, m_offset.c3_mps3, 1e-9);
  const sim::IntensityMeasures im_clean = sim::intensity_measures(a_clean, dt_s, kG);
  const sim::IntensityMeasures im_offset = sim::intensity_measures(a_offset, dt_s, kG);
  DOUBLES_EQUAL(im_clean.pgv_mps, im_offset.pgv_mps, 1e-9);
  DOUBLES_EQUAL(im_clean.pgd_m, im_offset.pgd_m, 1e-9);
}

// A constant acceleration error that starts with the motion (a tilt or a jump of the sensor) makes velocity drift
// linearly from t0 on; the fit removes most of it (not exactly: (t − t0)² is not in the span of t², t³).
TEST(PeakGroundMotion, AccelerationStepIsRemovedByThePolynomial) {
  const double amp = 3.0, tp = 1.0, t0 = 2.0, dt_s = 0.005;
  const auto clean = [&](double t) { return sine_pulse(t, amp, t0, tp) + sine_pulse(t, amp, t0 + tp, tp, -1.0); };
  const std::vector<double> a_drift = sampled([&](double t) { return clean(t) + (t >= t0 ? 0.002 * amp : 0.0); },
                                              dt_s, 8001);
  const sim::IntensityMeasures im = sim::intensity_measures(a_drift, dt_s, kG);
  const double pgv = amp * tp / kPi;
  const double pgd = amp * tp * tp / (2.0 * kPi);
  DOUBLES_EQUAL(pgv, im.pgv_mps, 0.02 * pgv);  // 0.7 % measured
  DOUBLES_EQUAL(pgd, im.pgd_m, 0.05 * pgd);    // 3.5 % measured
}

TEST(PeakGroundMotion, Rejections) {
  const std::vector<double> ok{0.0, 1.0, -1.0, 0.5};
  check_throws_measure_error([] { sim::intensity_measures({}, 0.01, kG); });
  check_throws_measure_error([&] { sim::intensity_measures(ok, 0.0, kG); });
  check_throws_measure_error([&] { sim::intensity_measures(ok, HUGE_VAL, kG); });
  check_throws_measure_error([&] { sim::intensity_measures({1.0, std::nan("")}, 0.01, kG); });
  check_throws_measure_error([&] { sim::intensity_measures(ok, 0.01, 0.0); });
  check_throws_measure_error([&] { sim::intensity_measures(ok, 0.01, -9.81); });
  check_throws_measure_error([&] { sim::arias_intensity_mps(ok, 0.01, std::nan("")); });
  check_throws_measure_error([&] { sim::baseline_corrected_motion({}, 0.01); });
  check_throws_measure_error([&] { sim::husid_curve(ok, -1.0); });
  // Too short to fit a polynomial: integrated as is.
  const sim::BaselineCorrectedMotion m = sim::baseline_corrected_motion({0.0, 2.0}, 0.5);
  DOUBLES_EQUAL(0.5, m.vel_mps[1], 1e-15);
}

}  // namespace unity_test_intensity_measures
