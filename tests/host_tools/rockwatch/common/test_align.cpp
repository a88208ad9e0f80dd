// resample_linear: the vertical record put on the horizontal record's grid.
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <vector>

#include "common/records_in/align.hpp"

#include <CppUTest/TestHarness.h>

using rockwatch::cli::resample_linear;
using rockwatch::cli::TimeGrid;

TEST_GROUP(ResampleLinear){};

TEST(ResampleLinear, IdenticalGridCopiesBitForBit) {
  const std::vector<double> v{0.1, -0.2, 0.30000000000000004, 1e-300, -7.0};
  const std::vector<double> out = resample_linear(v, {0.0, 0.01, v.size()}, {0.0, 0.01, v.size()});
  CHECK_TRUE(out == v);
}

TEST(ResampleLinear, SameGridWithNonzeroStartCopies) {
  const std::vector<double> v{1.0, 2.0, 3.0};
  CHECK_TRUE(resample_linear(v, {12.34, 0.005, 3}, {12.34, 0.005, 3}) == v);
}

TEST(ResampleLinear, LongerSourceIsCut) {
  const std::vector<double> v{1.0, 2.0, 3.0, 4.0, 5.0};
  const std::vector<double> out = resample_linear(v, {0.0, 0.01, 5}, {0.0, 0.01, 3});
  CHECK_TRUE(out == std::vector<double>({1.0, 2.0, 3.0}));
}

TEST(ResampleLinear, ShorterSourceIsZeroAfterItsEnd) {
  const std::vector<double> v{1.0, 2.0};
  const std::vector<double> out = resample_linear(v, {0.0, 0.01, 2}, {0.0, 0.01, 4});
  CHECK_TRUE(out == std::vector<double>({1.0, 2.0, 0.0, 0.0}));
}

TEST(ResampleLinear, FinerTargetInterpolatesLinearly) {
  const std::vector<double> v{0.0, 1.0, -1.0};
  const std::vector<double> out = resample_linear(v, {0.0, 0.02, 3}, {0.0, 0.005, 9});
  const double expected[] = {0.0, 0.25, 0.5, 0.75, 1.0, 0.5, 0.0, -0.5, -1.0};
  for (std::size_t k = 0; k < 9; ++k) DOUBLES_EQUAL(expected[k], out[k], 1e-15);
}

TEST(ResampleLinear, CoarserTargetSamplesTheSource) {
  const std::vector<double> v{0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  const std::vector<double> out = resample_linear(v, {0.0, 0.005, 7}, {0.0, 0.01, 4});
  for (std::size_t k = 0; k < 4; ++k) DOUBLES_EQUAL(2.0 * static_cast<double>(k), out[k], 1e-15);
}

TEST(ResampleLinear, LaterStartIsZeroBeforeIt) {
  // Source starts at t = 0.02 s; the target grid starts at 0.
  const std::vector<double> v{5.0, 6.0, 7.0};
  const std::vector<double> out = resample_linear(v, {0.02, 0.01, 3}, {0.0, 0.01, 6});
  const double expected[] = {0.0, 0.0, 5.0, 6.0, 7.0, 0.0};
  for (std::size_t k = 0; k < 6; ++k) DOUBLES_EQUAL(expected[k], out[k], 1e-15);
}

TEST(ResampleLinear, EarlierStartIsShifted) {
  // Source starts at t = -0.015 s: target time 0 is half-way between its samples 1 and 2.
  const std::vector<double> v{0.0, 10.0, 20.0, 30.0};
  const std::vector<double> out = resample_linear(v, {-0.015, 0.01, 4}, {0.0, 0.01, 3});
  DOUBLES_EQUAL(15.0, out[0], 1e-12);
  DOUBLES_EQUAL(25.0, out[1], 1e-12);
  DOUBLES_EQUAL(0.0, out[2], 0.0);  // t = 0.02 is past the source's end at 0.015
}

TEST(ResampleLinear, RoundingAtTheSpanEndsKeepsTheEndSamples) {
  // 0.1 + 0.2 is not 0.3 in binary; the end sample must still be taken, not zeroed or extrapolated.
  const std::vector<double> v{1.0, 2.0, 3.0};
  const std::vector<double> out = resample_linear(v, {0.1, 0.1, 3}, {0.1 + 0.2 - 0.2, 0.1, 3});
  DOUBLES_EQUAL(1.0, out[0], 0.0);
  DOUBLES_EQUAL(3.0, out[2], 0.0);
}

TEST(ResampleLinear, EmptySourceGivesZeros) {
  const std::vector<double> out = resample_linear({}, {0.0, 0.01, 0}, {0.0, 0.01, 3});
  CHECK_TRUE(out == std::vector<double>(3, 0.0));
}

TEST(ResampleLinear, EmptyTarget) { CHECK_TRUE(resample_linear({1.0}, {0.0, 0.01, 1}, {0.0, 0.01, 0}).empty()); }

TEST(ResampleLinear, InvalidGridsThrow) {
  const std::vector<double> v{1.0, 2.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS(std::invalid_argument, resample_linear(v, {0.0, 0.0, 2}, {0.0, 0.01, 2}));
  CHECK_THROWS(std::invalid_argument, resample_linear(v, {0.0, 0.01, 2}, {0.0, -0.01, 2}));
  CHECK_THROWS(std::invalid_argument, resample_linear(v, {nan, 0.01, 2}, {0.0, 0.01, 2}));
}
