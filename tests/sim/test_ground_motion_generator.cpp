// The spectrum-compatible generator: its random stream, envelope and filter, and the acceptance properties of a
// generated record recomputed here from the samples (not taken from the generator's own report).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "rockwatch/sim/analysis.hpp"
#include "trapezoid_from_rest.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"
#include "rockwatch/sim/synthesis/random_stream.hpp"

#include "check_throws.hpp"  // brings in CppUTest: after every header that may use operator new
#include <CppUTest/TestHarness.h>

using namespace rockwatch;
using namespace rockwatch::sim::synthesis;

namespace {

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ab += a[k] * b[k];
    aa += a[k] * a[k];
    bb += b[k] * b[k];
  }
  return ab / std::sqrt(aa * bb);
}

// Set 3 of the default suite (5 draws in all, one of the quickest sets), made once before the tests start
// (CppUTest's leak check would count a set first made inside a test as leaked) and one component after the other:
// generate_set's threads would race in CppUTest's allocation bookkeeping, which is not thread-safe. That the
// threaded generate_set gives the same bits is checked against the shipped suite (made by `rockwatch generate`)
// in test_shipped_suite.cpp.
GeneratedSet sequential_set(int set_number) {
  GeneratedSet set;
  set.set_number = set_number;
  for (std::size_t i = 0; i < 3; ++i) {
    set.components[i] = generate_component(GeneratorSettings{}, set_number, kAllComponents[i]);
  }
  return set;
}
const GeneratedSet kDefaultSet3 = sequential_set(3);
const GeneratedSet& default_set_3() { return kDefaultSet3; }

}  // namespace

TEST_GROUP(RandomStream){};

TEST(RandomStream, SplitMix64MatchesItsPublishedFirstOutput) {
  // SplitMix64 from state 0 (Steele, Lea & Flood 2014; the reference seeding of xoshiro): first output.
  std::uint64_t state = 0;
  CHECK_EQUAL(0xE220A8397B1DCDAFULL, splitmix64(state));
}

TEST(RandomStream, SameSeedSameStreamOtherSeedOtherStream) {
  RandomStream a(42), b(42), c(43);
  bool any_difference = false;
  for (int i = 0; i < 1000; ++i) {
    const double x = a.normal();
    CHECK_EQUAL(x, b.normal());
    any_difference = any_difference || x != c.normal();
  }
  CHECK_TRUE(any_difference);
}

TEST(RandomStream, UniformAndNormalMoments) {
  RandomStream s(7);
  constexpr int kN = 200000;
  double sum_u = 0.0, sum = 0.0, sum2 = 0.0, sum4 = 0.0;
  for (int i = 0; i < kN; ++i) {
    const double u = s.uniform();
    CHECK_TRUE(u >= 0.0 && u < 1.0);
    sum_u += u;
  }
  for (int i = 0; i < kN; ++i) {
    const double z = s.normal();
    sum += z;
    sum2 += z * z;
    sum4 += z * z * z * z;
  }
  // Standard errors at n = 2e5: mean of U 6e-4, mean of Z 2.2e-3, variance 3.2e-3, kurtosis 0.02; 4σ bounds.
  DOUBLES_EQUAL(0.5, sum_u / kN, 3e-3);
  DOUBLES_EQUAL(0.0, sum / kN, 0.01);
  DOUBLES_EQUAL(1.0, sum2 / kN, 0.015);
  DOUBLES_EQUAL(3.0, sum4 / kN, 0.1);
}

TEST(RandomStream, ComponentSeedsAreDistinctAndDependOnTheSuiteSeed) {
  std::set<std::uint64_t> seeds;
  for (int set = 1; set <= 11; ++set) {
    for (const Component c : kAllComponents) seeds.insert(component_seed(9998, set, c));
  }
  CHECK_EQUAL(33U, seeds.size());
  CHECK_TRUE(component_seed(9998, 1, Component::x) != component_seed(9999, 1, Component::x));
}

TEST_GROUP(EnvelopeAndFilter){};

TEST(EnvelopeAndFilter, EnvelopeBranches) {
  Envelope e;
  e.lead_s = 1.0;
  e.rise_s = 2.0;
  e.strong_s = 1.0;
  e.decay_per_s = 1.0;
  e.coda_fraction = 0.25;
  e.coda_decay_per_s = 0.1;
  e.taper_s = 2.0;
  const double duration_s = 20.0;
  DOUBLES_EQUAL(0.0, envelope_value(e, 0.5, duration_s), 0.0);
  DOUBLES_EQUAL(0.25, envelope_value(e, 2.0, duration_s), 1e-15);   // ((2 − 1)/2)²
  DOUBLES_EQUAL(1.0, envelope_value(e, 3.5, duration_s), 0.0);
  DOUBLES_EQUAL(0.75 * std::exp(-2.0) + 0.25 * std::exp(-0.2), envelope_value(e, 6.0, duration_s), 1e-15);
  // Half way through the end taper: half of the decayed value.
  const double decayed = 0.75 * std::exp(-15.0) + 0.25 * std::exp(-1.5);
  DOUBLES_EQUAL(0.5 * decayed, envelope_value(e, 19.0, duration_s), 1e-15);
  DOUBLES_EQUAL(0.0, envelope_value(e, 20.0, duration_s), 0.0);
}

TEST(EnvelopeAndFilter, KanaiTajimiCloughPenzienGain) {
  GroundFilter g;  // fg 4 Hz, ff 0.3 Hz
  DOUBLES_EQUAL(0.0, ground_filter_gain(g, 0.0), 0.0);
  // At f = fg the Kanai–Tajimi factor is (1 + 4ζ²)/(4ζ²); the high-pass is ≈ 1 there (f/ff ≈ 13).
  const double kt_at_fg = std::sqrt((1.0 + 4.0 * g.zg * g.zg) / (4.0 * g.zg * g.zg));
  DOUBLES_EQUAL(kt_at_fg, ground_filter_gain(g, g.fg_hz), 0.01 * kt_at_fg);
  // The high-pass removes what would drift: the amplitude falls as (f/ff)², 1e-2 at a tenth of the corner.
  const double low = ground_filter_gain(g, g.ff_hz / 10.0);
  CHECK_TRUE(low > 0.9e-2 && low < 1.1e-2);
}

TEST_GROUP(Generator){};

TEST(Generator, RecordMeetsTheAcceptanceCriteriaRecomputedFromItsSamples) {
  const GeneratorSettings s;
  const GeneratedComponent& g = default_set_3().components[0];
  const double ag = s.pga_g * s.g_mps2;
  CHECK_TRUE(g.accepted);
  CHECK_EQUAL(static_cast<std::size_t>(std::llround(s.duration_s / s.dt_s)) + 1, g.acc_mps2.size());

  DOUBLES_EQUAL(ag, sim::peak_abs(g.acc_mps2), 1e-12 * ag);  // PGA anchored to a_g

  const std::vector<double> periods = sim::log_spaced_periods(0.05, 2.5, 100);
  const sim::ResponseSpectrum rs = sim::response_spectrum(g.acc_mps2, s.dt_s, periods, 0.05);
  for (std::size_t i = 0; i < periods.size(); ++i) {
    const double ratio = rs.psa_mps2[i] / (ag * core::spectrum_shape(core::spectrum_npr9998_2015(), periods[i]));
    CHECK_TRUE(ratio >= 0.9 && ratio <= 1.3);
  }

  const rockwatch::test::TrapezoidState end = rockwatch::test::trapezoid_from_rest(g.acc_mps2, s.dt_s);
  CHECK_TRUE(std::abs(end.v_mps) < 1e-12);
  CHECK_TRUE(std::abs(end.d_m) < 1e-12);
  CHECK_TRUE(end.max_abs_d_m < 0.1);  // no drift on the way either (PGD of such records is centimetres)

  const sim::IntensityMeasures im = sim::intensity_measures(g.acc_mps2, s.dt_s, s.g_mps2);
  CHECK_TRUE(*im.d5_75_s >= 1.5 && *im.d5_75_s <= 4.0);
  CHECK_TRUE(*im.d5_95_s >= 6.0 && *im.d5_95_s <= 8.0);
  DOUBLES_EQUAL(*im.d5_95_s, g.d5_95_s, 1e-12);

  // Quiet lead (the envelope is zero before lead_s, and so are the baseline pulses) and a tail tapered to zero.
  const auto lead_samples = static_cast<std::size_t>(component_target(s, Component::x).envelope.lead_s / s.dt_s);
  for (std::size_t k = 0; k < lead_samples; ++k) CHECK_EQUAL(0.0, g.acc_mps2[k]);
  CHECK_EQUAL(0.0, g.acc_mps2.back());
}

TEST(Generator, SetIsBitForBitReproducibleAndItsComponentsIndependent) {
  const GeneratorSettings s;
  const GeneratedSet& a = default_set_3();
  // Made again: the same bits.
  const GeneratedComponent z = generate_component(s, 3, Component::z);
  CHECK_TRUE(a.components[2].acc_mps2 == z.acc_mps2);
  CHECK_TRUE(a.components[2].accepted);
  // Different streams: X, Y, Z of one set are uncorrelated (|ρ| for independent records of ~800 effective
  // samples is ~0.04; matching shapes the spectra alike but not the phases).
  CHECK_TRUE(std::abs(correlation(a.components[0].acc_mps2, a.components[1].acc_mps2)) < 0.2);
  CHECK_TRUE(std::abs(correlation(a.components[0].acc_mps2, a.components[2].acc_mps2)) < 0.2);
}

TEST(Generator, VerticalHasEarlierOnsetAndHigherFrequencyContent) {
  const GeneratorSettings s;
  const GeneratedSet& set = default_set_3();
  const sim::IntensityMeasures x = sim::intensity_measures(set.components[0].acc_mps2, s.dt_s, s.g_mps2);
  const sim::IntensityMeasures z = sim::intensity_measures(set.components[2].acc_mps2, s.dt_s, s.g_mps2);
  CHECK_TRUE(*z.t5_s < *x.t5_s);
  // Equal PGA, but the vertical's energy sits at shorter periods: lower PGV.
  CHECK_TRUE(z.pgv_mps < x.pgv_mps);
}

TEST(Generator, SuiteMeanAveragesTheRatiosOfEachDirection) {
  GeneratorSettings s;
  s.check_periods = 2;
  const auto component = [](Component c, double r0, double r1) {
    GeneratedComponent g;
    g.component = c;
    g.check.ratio = {r0, r1};
    return g;
  };
  GeneratedSet one, two;
  one.components = {component(Component::x, 1.0, 1.2), component(Component::y, 1.0, 1.0),
                    component(Component::z, 0.8, 1.0)};
  two.components = {component(Component::x, 1.0, 1.0), component(Component::y, 1.0, 1.2),
                    component(Component::z, 0.9, 1.0)};
  const SuiteMean m = suite_mean(s, {one, two});
  DOUBLES_EQUAL(1.0, m.horizontal.ratio[0], 1e-15);
  DOUBLES_EQUAL(1.1, m.horizontal.ratio[1], 1e-15);
  CHECK_TRUE(m.horizontal_accepted);  // 1.1 is on the ±10 % limit
  DOUBLES_EQUAL(0.85, m.vertical.min, 1e-15);
  CHECK_FALSE(m.vertical_accepted);
}

TEST(Generator, InvalidSettingsAreRejectedNamingTheSetting) {
  const auto rejected = [](const GeneratorSettings& bad, const std::string& fragment) {
    std::string message;
    try {
      validate_settings(bad);
    } catch (const GeneratorError& e) {
      message = e.what();
    }
    CHECK_TEXT(message.find(fragment) != std::string::npos, ("expected a message naming " + fragment + ", got: " + message).c_str());
  };
  GeneratorSettings s;
  s.dt_s = 0.0;
  rejected(s, "dt");
  s = {};
  s.pga_g = -0.1;
  rejected(s, "PGA");
  s = {};
  s.duration_s = 5.0;
  rejected(s, "duration");
  s = {};
  s.check_to_s = s.check_from_s;
  rejected(s, "check band");
  s = {};
  s.horizontal_target.tb_s = 0.5;
  rejected(s, "horizontal target");
  s = {};
  s.match_level = 1.5;
  rejected(s, "matched level");
  s = {};
  s.horizontal_d5_95_s = {8.0, 6.0};
  rejected(s, "duration windows");
  s = {};
  s.iterations = 0;
  rejected(s, "iterations");
  rockwatch::test::check_throws<GeneratorError>([] { generate_component(GeneratorSettings{}, 0, Component::x); },
                                                "set number 0 rejected");
}
