// sim::response_spectrum and sim::log_spaced_periods: the spectrum of the shared real records (PSA at short period
// = PGA), agreement with single oscillators, and every rejection.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "reference_data.hpp"
#include "rockwatch/core/response_oscillator.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/measure_error.hpp"
#include "rockwatch/sim/response_spectrum.hpp"

#include "check_throws.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

namespace sim = rockwatch::sim;
namespace core = rockwatch::core;
namespace records = rockwatch::records;
using rockwatch::test::data_path;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;

struct RecordCase {
  const char* file;
  double pga_g;  // the record collection's manifest: max |a| over the whole file, 4 decimals
};

// tests/data/records/SOURCES.md
constexpr RecordCase kRecords[] = {
    {"RSN6_IMPVALL.I_I-ELC180-hor1.AT2", 0.2808},
    {"RSN6_IMPVALL.I_I-ELC270-hor2.AT2", 0.2107},
    {"RSN6_IMPVALL.I_I-ELC-UP.AT2", 0.1781},
    {"RSN175_IMPVALL.H_H-E12140.AT2", 0.1449},
};

records::Record read(const char* file) { return records::read_record(data_path(std::string("records/") + file)); }

double peak(const std::vector<double>& v) {
  double p = 0.0;
  for (const double x : v) p = std::fmax(p, std::fabs(x));
  return p;
}

template <typename Fn>
void check_throws_measure_error(Fn fn) {
  rockwatch::test::check_throws<sim::MeasureError>(fn, "expected sim::MeasureError");
}

}  // namespace

TEST_GROUP(LogSpacedPeriods){};

TEST(LogSpacedPeriods, EndsExactAndConstantRatio) {
  const std::vector<double> p = sim::log_spaced_periods(0.02, 4.0, 100);
  LONGS_EQUAL(100, p.size());
  DOUBLES_EQUAL(0.02, p.front(), 0.0);
  DOUBLES_EQUAL(4.0, p.back(), 0.0);
  const double ratio = std::pow(4.0 / 0.02, 1.0 / 99.0);
  for (std::size_t i = 1; i < p.size(); ++i) DOUBLES_EQUAL(ratio, p[i] / p[i - 1], 1e-12);
  const std::vector<double> two = sim::log_spaced_periods(0.1, 10.0, 3);
  DOUBLES_EQUAL(1.0, two[1], 1e-15);
}

TEST(LogSpacedPeriods, DefaultIsTwoHundredthsToFourSecondsAtOneHundred) {
  const std::vector<double> p = sim::default_spectrum_periods();
  LONGS_EQUAL(100, p.size());
  DOUBLES_EQUAL(0.02, p.front(), 0.0);
  DOUBLES_EQUAL(4.0, p.back(), 0.0);
}

TEST(LogSpacedPeriods, Rejections) {
  check_throws_measure_error([] { sim::log_spaced_periods(0.0, 4.0, 10); });
  check_throws_measure_error([] { sim::log_spaced_periods(-1.0, 4.0, 10); });
  check_throws_measure_error([] { sim::log_spaced_periods(1.0, 1.0, 10); });
  check_throws_measure_error([] { sim::log_spaced_periods(2.0, 1.0, 10); });
  check_throws_measure_error([] { sim::log_spaced_periods(0.1, 1.0, 1); });
  check_throws_measure_error([] { sim::log_spaced_periods(std::nan(""), 1.0, 10); });
  check_throws_measure_error([] { sim::log_spaced_periods(0.1, HUGE_VAL, 10); });
}

TEST_GROUP(ResponseSpectrum){};

// At T = 0.02 s an oscillator barely amplifies records sampled at 100–200 Hz: PSA within a few % of the PGA.
TEST(ResponseSpectrum, ShortPeriodPsaIsThePgaOfTheRealRecords) {
  for (const RecordCase& c : kRecords) {
    const records::Record r = read(c.file);
    const double pga = peak(r.horizontal_mps2);
    DOUBLES_EQUAL_TEXT(c.pga_g, pga / kG, 0.5e-4, c.file);
    const sim::ResponseSpectrum s = sim::response_spectrum(r.horizontal_mps2, r.dt_s, {0.02, r.dt_s / 100.0});
    DOUBLES_EQUAL_TEXT(pga, s.psa_mps2[0], 0.05 * pga, c.file);
    // Far below dt the exact recurrence needs no special case: the oscillator follows the ground.
    DOUBLES_EQUAL_TEXT(pga, s.psa_mps2[1], 1e-3 * pga, c.file);
    DOUBLES_EQUAL_TEXT(pga, s.sa_abs_mps2[1], 1e-3 * pga, c.file);
  }
}

// The spectrum of El Centro 180 at 5 %: the plateau of this record lies between about 0.2 and 0.6 s with PSA
// around 2.5–3 × PGA, and the spectrum falls at long periods.
TEST(ResponseSpectrum, ElCentroShapeIsPlausible) {
  const records::Record r = read(kRecords[0].file);
  const double pga = peak(r.horizontal_mps2);
  const sim::ResponseSpectrum s = sim::response_spectrum(r.horizontal_mps2, r.dt_s, sim::default_spectrum_periods());
  double max_psa = 0.0, t_max = 0.0;
  for (std::size_t i = 0; i < s.periods_s.size(); ++i) {
    if (s.psa_mps2[i] > max_psa) {
      max_psa = s.psa_mps2[i];
      t_max = s.periods_s[i];
    }
    CHECK(s.sd_m[i] >= 0.0);
    DOUBLES_EQUAL(s.psa_mps2[i], s.psv_mps[i] * 2.0 * kPi / s.periods_s[i], 1e-12 * s.psa_mps2[i]);
  }
  CHECK(max_psa > 2.0 * pga && max_psa < 4.0 * pga);
  CHECK(t_max > 0.15 && t_max < 0.7);
  CHECK(s.psa_mps2.back() < 0.5 * pga);
  DOUBLES_EQUAL(0.05, s.damping, 0.0);
}

// Each entry is one oscillator run over the samples, whatever the other periods are.
TEST(ResponseSpectrum, EqualsOneOscillatorPerPeriod) {
  const records::Record r = read(kRecords[3].file);
  const std::vector<double> periods{0.1, 0.37, 2.5};
  const sim::ResponseSpectrum s = sim::response_spectrum(r.horizontal_mps2, r.dt_s, periods, 0.02);
  for (std::size_t i = 0; i < periods.size(); ++i) {
    core::ResponseOscillator osc;
    CHECK(osc.init(periods[i], 0.02, r.dt_s) == core::OscillatorStatus::ok);
    osc.reset(r.horizontal_mps2.front());
    for (std::size_t k = 1; k < r.horizontal_mps2.size(); ++k) osc.step(r.horizontal_mps2[k]);
    DOUBLES_EQUAL(osc.sd_m(), s.sd_m[i], 0.0);
    DOUBLES_EQUAL(osc.psa_mps2(), s.psa_mps2[i], 0.0);
    DOUBLES_EQUAL(osc.max_abs_acceleration_mps2(), s.sa_abs_mps2[i], 0.0);
  }
  const sim::ResponseSpectrum single = sim::response_spectrum(r.horizontal_mps2, r.dt_s, {0.37}, 0.02);
  DOUBLES_EQUAL(s.psa_mps2[1], single.psa_mps2[0], 0.0);
}

// Linear in the input: scaling the record scales the spectrum.
TEST(ResponseSpectrum, ScalesWithTheRecord) {
  const records::Record r = read(kRecords[0].file);
  std::vector<double> doubled = r.horizontal_mps2;
  for (double& a : doubled) a *= 2.0;
  const std::vector<double> periods = sim::log_spaced_periods(0.05, 3.0, 7);
  const sim::ResponseSpectrum s1 = sim::response_spectrum(r.horizontal_mps2, r.dt_s, periods);
  const sim::ResponseSpectrum s2 = sim::response_spectrum(doubled, r.dt_s, periods);
  for (std::size_t i = 0; i < periods.size(); ++i) DOUBLES_EQUAL(2.0 * s1.psa_mps2[i], s2.psa_mps2[i], 1e-12 * s2.psa_mps2[i]);
}

TEST(ResponseSpectrum, Rejections) {
  const std::vector<double> ok{0.0, 1.0, -1.0, 0.5};
  const std::vector<double> periods{0.1, 1.0};
  check_throws_measure_error([&] { sim::response_spectrum({}, 0.01, periods); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, 0.0, periods); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, -0.01, periods); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, std::nan(""), periods); });
  check_throws_measure_error([&] { sim::response_spectrum({0.0, std::nan(""), 1.0}, 0.01, periods); });
  check_throws_measure_error([&] { sim::response_spectrum({0.0, HUGE_VAL}, 0.01, periods); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, 0.01, {0.1, 0.0}); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, 0.01, {-0.5}); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, 0.01, periods, 1.0); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, 0.01, periods, -0.05); });
  check_throws_measure_error([&] { sim::response_spectrum(ok, 0.01, {}, 1.5); });
  const sim::ResponseSpectrum empty = sim::response_spectrum(ok, 0.01, {});
  CHECK(empty.psa_mps2.empty());
}
