// The shipped NPR 9998-compatible suite (sim/suites/npr9998-2015), checked from its files: every acceptance figure
// is recomputed from the samples here, none is read from the manifest. A generator change that alters the suite
// fails the regeneration test, like a golden-output test: regenerate and commit the suite deliberately.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"
#include "trapezoid_from_rest.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;
using sim::synthesis::Component;

namespace {

const std::string kSuiteDir = ROCKWATCH_SUITE_DIR;

struct ShippedSet {
  int set = 0;
  records::SuiteRecordFile file;
};

std::vector<ShippedSet> read_suite() {
  std::vector<ShippedSet> out;
  for (const int set : records::suite_sets(kSuiteDir)) {
    out.push_back({set, records::read_suite_record(records::suite_set_path(kSuiteDir, set))});
  }
  return out;
}

// Read once before the tests run (CppUTest would count a lazily made static as a leak of the first test).
const std::vector<ShippedSet> kSuite = read_suite();

const std::vector<double> kCheckPeriods = sim::log_spaced_periods(0.05, 2.5, 100);

std::vector<double> ratio_to_target(const std::vector<double>& a, double dt_s, const core::SpectrumShape& shape,
                                    double pga_mps2) {
  const sim::ResponseSpectrum rs = sim::response_spectrum(a, dt_s, kCheckPeriods, 0.05);
  std::vector<double> r(kCheckPeriods.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    r[i] = rs.psa_mps2[i] / (pga_mps2 * core::spectrum_shape(shape, kCheckPeriods[i]));
  }
  return r;
}

std::string where(int set, std::size_t component) {
  return "set " + std::to_string(set) + " component " + std::string(1, "XYZ"[component]);
}

}  // namespace

TEST_GROUP(ShippedSuite){};

TEST(ShippedSuite, HasElevenSetsOfThreeComponentsAtFiveMilliseconds) {
  CHECK_EQUAL(11U, kSuite.size());
  for (std::size_t i = 0; i < kSuite.size(); ++i) {
    const records::SuiteRecordFile& f = kSuite[i].file;
    CHECK_EQUAL(static_cast<int>(i) + 1, f.set);
    CHECK_EQUAL(0.005, f.dt_s);
    CHECK_EQUAL(f.components_mps2[0].size(), f.components_mps2[2].size());
    CHECK_TRUE(f.components_mps2[0].size() > 1000);
  }
}

TEST(ShippedSuite, EveryComponentIsWithinPointNineToOnePointThreeOfItsTargetAndAnchoredToItsPga) {
  for (const ShippedSet& s : kSuite) {
    for (std::size_t c = 0; c < 3; ++c) {
      const bool vertical = c == 2;
      const double pga = vertical ? s.file.avg_mps2 : s.file.ag_mps2;
      const core::SpectrumShape shape = vertical ? core::spectrum_vertical_default() : core::spectrum_npr9998_2015();
      const std::vector<double>& a = s.file.components_mps2[c];
      DOUBLES_EQUAL_TEXT(pga, sim::peak_abs(a), 1e-9 * pga, where(s.set, c).c_str());
      for (const double r : ratio_to_target(a, s.file.dt_s, shape, pga)) {
        CHECK_TEXT(r >= 0.9 && r <= 1.3, (where(s.set, c) + ": spectral ratio " + std::to_string(r)).c_str());
      }
    }
  }
}

TEST(ShippedSuite, SuiteMeanOfEachDirectionIsWithinTenPercent) {
  std::vector<double> horizontal(kCheckPeriods.size(), 0.0), vertical(kCheckPeriods.size(), 0.0);
  for (const ShippedSet& s : kSuite) {
    for (std::size_t c = 0; c < 3; ++c) {
      const bool is_z = c == 2;
      const std::vector<double> r =
          ratio_to_target(s.file.components_mps2[c], s.file.dt_s,
                          is_z ? core::spectrum_vertical_default() : core::spectrum_npr9998_2015(),
                          is_z ? s.file.avg_mps2 : s.file.ag_mps2);
      std::vector<double>& sum = is_z ? vertical : horizontal;
      for (std::size_t i = 0; i < r.size(); ++i) sum[i] += r[i];
    }
  }
  const double n = static_cast<double>(kSuite.size());
  for (std::size_t i = 0; i < kCheckPeriods.size(); ++i) {
    const double h = horizontal[i] / (2.0 * n);
    const double v = vertical[i] / n;
    CHECK_TEXT(h >= 0.9 && h <= 1.1, ("horizontal mean " + std::to_string(h)).c_str());
    CHECK_TEXT(v >= 0.9 && v <= 1.1, ("vertical mean " + std::to_string(v)).c_str());
  }
}

TEST(ShippedSuite, NoResidualVelocityOrDisplacementDrift) {
  for (const ShippedSet& s : kSuite) {
    for (std::size_t c = 0; c < 3; ++c) {
      const test::TrapezoidState end = test::trapezoid_from_rest(s.file.components_mps2[c], s.file.dt_s);
      const double v = end.v_mps, d = end.d_m, max_d = end.max_abs_d_m;
      // Exactly zero before the values were rounded to 10 digits; rounding moves the end by ~1e-9 m/s, 1e-8 m.
      CHECK_TEXT(std::abs(v) < 1e-7, (where(s.set, c) + ": final velocity " + std::to_string(v)).c_str());
      CHECK_TEXT(std::abs(d) < 1e-6, (where(s.set, c) + ": final displacement " + std::to_string(d)).c_str());
      CHECK_TEXT(max_d < 0.1, (where(s.set, c) + ": PGD " + std::to_string(max_d)).c_str());
    }
  }
}

TEST(ShippedSuite, SignificantDurationsAreGroningenLikeAndTheVerticalStartsEarlier) {
  for (const ShippedSet& s : kSuite) {
    std::vector<sim::IntensityMeasures> im;
    for (std::size_t c = 0; c < 3; ++c) {
      im.push_back(sim::intensity_measures(s.file.components_mps2[c], s.file.dt_s, s.file.g_mps2));
      const double d75 = *im.back().d5_75_s, d95 = *im.back().d5_95_s;
      const double d95_min = c == 2 ? 3.0 : 6.0;  // horizontal: the calibrated 6–8 s (SPEC §6)
      CHECK_TEXT(d75 >= 1.5 && d75 <= 4.0, (where(s.set, c) + ": D5-75 " + std::to_string(d75)).c_str());
      CHECK_TEXT(d95 >= d95_min && d95 <= 8.0, (where(s.set, c) + ": D5-95 " + std::to_string(d95)).c_str());
    }
    CHECK_TEXT(*im[2].t5_s < *im[0].t5_s && *im[2].t5_s < *im[1].t5_s, where(s.set, 2).c_str());
  }
}

// Regenerates one set with the settings the suite was made with (the defaults) and compares every sample. The
// suite was written by `rockwatch generate` (generate_set: components on threads); here they are made one after
// the other (CppUTest's allocation bookkeeping is not thread-safe), so this also shows the threads change nothing.
TEST(ShippedSuite, RegeneratingSetThreeReproducesTheShippedFile) {
  const sim::synthesis::GeneratorSettings settings;
  const records::SuiteRecordFile& shipped = kSuite.at(2).file;
  CHECK_EQUAL(settings.seed, shipped.seed);
  DOUBLES_EQUAL(settings.pga_g * settings.g_mps2, shipped.ag_mps2, 1e-12);
  for (std::size_t c = 0; c < 3; ++c) {
    const std::vector<double> a =
        sim::synthesis::generate_component(settings, 3, sim::synthesis::kAllComponents[c]).acc_mps2;
    const std::vector<double>& b = shipped.components_mps2[c];
    CHECK_EQUAL(a.size(), b.size());
    const double tolerance = 1e-9 * sim::peak_abs(a);  // the file holds 10 significant digits
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (std::abs(a[k] - b[k]) > tolerance) {
        FAIL((where(3, c) + ": sample " + std::to_string(k) + " regenerated " + std::to_string(a[k]) + ", shipped " +
              std::to_string(b[k]))
                 .c_str());
      }
    }
  }
}
