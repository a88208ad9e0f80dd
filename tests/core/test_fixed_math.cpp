// fixed_log and fixed_atanh against std::log/std::atanh of the exact fixed-point input, over dense sweeps,
// every binade, the mantissa fold at √2, z near ±1, and the invalid inputs.
#include <cmath>
#include <cstdint>

#include "rockwatch/core/fixed_math.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;

namespace {

using Q7_24 = Fixed<7, 24>;
using Q4_27 = Fixed<4, 27>;
using Q1_30 = Fixed<1, 30>;
using Q0_31 = Fixed<0, 31>;
using Q2_29 = Fixed<2, 29>;
using Q5_26 = Fixed<5, 26>;
using Q15_16 = Fixed<15, 16>;
using Q31_0 = Fixed<31, 0>;
using Qm12_43 = Fixed<-12, 43>;

// The accuracy target for the alarm (Q7.24 output).
constexpr double kTargetError = 2e-7;
// What the header states: Out's half resolution plus the kernel's error.
constexpr double kKernelError = 5e-9;
template <typename Out>
double stated_bound() {
  return 0.5 * Out::resolution_value() + kKernelError;
}

// Largest |fixed_log − std::log| over n + 1 log-spaced inputs in [lo, hi], each rounded into the input format.
template <typename Out, typename In>
double worst_log_error(double lo, double hi, int n) {
  double worst = 0.0;
  for (int i = 0; i <= n; ++i) {
    const In u(lo * std::pow(hi / lo, double(i) / double(n)));
    if (u.raw() <= 0) continue;
    const double expected = std::log(u.to_double());
    worst = std::fmax(worst, std::fabs(fixed_log<Out>(u).to_double() - expected));
  }
  return worst;
}

double atanh_error_q7_24(Q1_30 z) { return std::fabs(fixed_atanh<Q7_24>(z).to_double() - std::atanh(z.to_double())); }

// Constant expressions: ln 2 · 2^24 = 11629079.97, atanh(½) · 2^24 = 9215827.83.
static_assert(fixed_log<Q7_24>(Q7_24(1)).raw() == 0, "ln 1 = 0 exactly");
static_assert(fixed_log<Q7_24>(Q7_24(2)).raw() == 11629080, "ln 2");
static_assert(fixed_log<Q7_24>(Q0_31(0.5)).raw() == -11629080, "ln ½");
static_assert(fixed_log<Q7_24>(Q7_24(0)) == Q7_24::lowest(), "ln 0");
static_assert(fixed_atanh<Q7_24>(Q1_30(0.0)).raw() == 0, "atanh 0 = 0 exactly");
static_assert(fixed_atanh<Q7_24>(Q1_30(0.5)).raw() == 9215828, "atanh ½");
static_assert(fixed_atanh<Q7_24>(Q1_30(1.0)) == Q7_24::highest(), "atanh 1 saturates");

}  // namespace

TEST_GROUP(FixedMath){};

TEST(FixedMath, LogMatchesStdLogFrom2ToThe30ToThe7) {
  // The alarm's range: (2^−30, 2^7), each part in a format that holds it, 4000 points per part.
  const double from_q0_31 = worst_log_error<Q7_24, Q0_31>(std::ldexp(1.0, -30), 0.999, 4000);
  const double from_q1_30 = worst_log_error<Q7_24, Q1_30>(std::ldexp(1.0, -29), 1.999, 4000);
  const double from_q7_24 = worst_log_error<Q7_24, Q7_24>(std::ldexp(1.0, -23), 127.99, 4000);
  CHECK(from_q0_31 <= stated_bound<Q7_24>());
  CHECK(from_q1_30 <= stated_bound<Q7_24>());
  CHECK(from_q7_24 <= stated_bound<Q7_24>());
  CHECK(stated_bound<Q7_24>() < kTargetError);
  // A finer output format shows the kernel's own error.
  CHECK((worst_log_error<Q4_27, Q0_31>(std::ldexp(1.0, -11), 0.999, 4000) <= stated_bound<Q4_27>()));
  CHECK((worst_log_error<Q4_27, Q7_24>(1.0, 127.99, 4000) <= stated_bound<Q4_27>()));
}

TEST(FixedMath, LogIsAccurateInEveryFormatAndAtTheRangeEnds) {
  CHECK((worst_log_error<Q7_24, Q15_16>(std::ldexp(1.0, -16), 32767.0, 4000) <= stated_bound<Q7_24>()));
  CHECK((worst_log_error<Q7_24, Q31_0>(1.0, 2147483647.0, 4000) <= stated_bound<Q7_24>()));
  // More than 31 fraction bits: ln down to 2^−43 (−29.8).
  CHECK((worst_log_error<Q7_24, Qm12_43>(std::ldexp(1.0, -42), std::ldexp(0.999, -12), 4000) <= stated_bound<Q7_24>()));
  DOUBLES_EQUAL(-43.0 * std::log(2.0), fixed_log<Q7_24>(Qm12_43::resolution()).to_double(), stated_bound<Q7_24>());
  // The smallest and largest positive raw values of a few formats (|ln| up to 31·ln 2).
  DOUBLES_EQUAL(std::log(std::ldexp(1.0, -31)), fixed_log<Q7_24>(Q0_31::resolution()).to_double(),
                stated_bound<Q7_24>());
  DOUBLES_EQUAL(std::log(2147483647.0), fixed_log<Q7_24>(Q31_0::highest()).to_double(), stated_bound<Q7_24>());
  DOUBLES_EQUAL(std::log(Q7_24::highest().to_double()), fixed_log<Q7_24>(Q7_24::highest()).to_double(),
                stated_bound<Q7_24>());
}

TEST(FixedMath, LogIsAccurateAtEveryPowerOfTwoAndAroundTheMantissaFold) {
  // Q5.26 holds ln down to 2^−31 (−21.5) with a resolution of 1.5e-8.
  for (int p = 0; p <= 30; ++p) {
    const auto u = Q0_31::from_raw(std::int32_t{1} << p);
    DOUBLES_EQUAL(double(p - 31) * std::log(2.0), fixed_log<Q5_26>(u).to_double(), stated_bound<Q5_26>());
    // Just below: the mantissa at the top of [1, 2).
    if (p > 0) {
      const auto below = Q0_31::from_raw((std::int32_t{1} << p) - 1);
      DOUBLES_EQUAL(std::log(below.to_double()), fixed_log<Q5_26>(below).to_double(), stated_bound<Q5_26>());
    }
  }
  // Around √2·2^k, where the mantissa is folded to m/2: both sides, in the Q.30 mantissa's last bits.
  const std::int64_t sqrt2_q30 = 1518500250;
  for (int shift = 0; shift <= 6; ++shift) {
    for (std::int64_t d = -3; d <= 3; ++d) {
      const auto u = Q1_30::from_raw(static_cast<std::int32_t>((sqrt2_q30 + d) >> shift));
      DOUBLES_EQUAL(std::log(u.to_double()), fixed_log<Q4_27>(u).to_double(), stated_bound<Q4_27>());
    }
  }
}

TEST(FixedMath, LogOfZeroOrNegativeIsLowestAndNarrowOutputsSaturate) {
  CHECK(fixed_log<Q7_24>(Q7_24(0)) == Q7_24::lowest());
  CHECK(fixed_log<Q7_24>(Q7_24(-1)) == Q7_24::lowest());
  CHECK(fixed_log<Q7_24>(Q7_24::lowest()) == Q7_24::lowest());
  CHECK(fixed_log<Q1_30>(Q7_24(-0.5)) == Q1_30::lowest());
  // Q2.29 holds ±4: ln 100 = 4.6 and ln 2^−30 = −20.8 saturate; ln 50 = 3.9 does not.
  CHECK(fixed_log<Q2_29>(Q7_24(100)) == Q2_29::highest());
  CHECK(fixed_log<Q2_29>(Q1_30::resolution()) == Q2_29::lowest());
  DOUBLES_EQUAL(std::log(50.0), fixed_log<Q2_29>(Q7_24(50)).to_double(), stated_bound<Q2_29>());
}

TEST(FixedMath, AtanhMatchesStdAtanhUpTo1Minus2ToThe20) {
  // 20000 points over [0, 1 − 2^−20].
  const double z_max = 1.0 - std::ldexp(1.0, -20);
  double worst = 0.0;
  double worst_q4_27 = 0.0;
  const int n = 20000;
  for (int i = 0; i <= n; ++i) {
    const Q1_30 z(z_max * double(i) / double(n));
    worst = std::fmax(worst, atanh_error_q7_24(z));
    worst_q4_27 = std::fmax(worst_q4_27, std::fabs(fixed_atanh<Q4_27>(z).to_double() - std::atanh(z.to_double())));
  }
  CHECK(worst <= stated_bound<Q7_24>());
  CHECK(worst <= kTargetError);
  CHECK(worst_q4_27 <= stated_bound<Q4_27>());
}

TEST(FixedMath, AtanhIsAccurateCloseToOne) {
  // z = 1 − 2^−j for every j the format holds, and the neighbours of the largest z.
  for (int j = 1; j <= 30; ++j) {
    const Q1_30 z = Q1_30::from_raw((std::int32_t{1} << 30) - (std::int32_t{1} << (30 - j)));
    CHECK(atanh_error_q7_24(z) <= stated_bound<Q7_24>());
    CHECK(atanh_error_q7_24(Q1_30::from_raw(z.raw() - 1)) <= stated_bound<Q7_24>());
  }
  DOUBLES_EQUAL(0.5 * std::log(2147483647.0), fixed_atanh<Q7_24>(Q1_30::from_raw((1 << 30) - 1)).to_double(),
                stated_bound<Q7_24>());
}

TEST(FixedMath, AtanhIsOddAndExactAtZero) {
  LONGS_EQUAL(0, fixed_atanh<Q7_24>(Q1_30(0.0)).raw());
  LONGS_EQUAL(0, fixed_atanh<Q4_27>(Q1_30(0.0)).raw());
  // Smallest |z|: atanh z ≈ z = 2^−30, below half a Q7.24 step, so 0; in Q1.30 it is one step.
  LONGS_EQUAL(0, fixed_atanh<Q7_24>(Q1_30::resolution()).raw());
  LONGS_EQUAL(1, fixed_atanh<Q1_30>(Q1_30::resolution()).raw());
  LONGS_EQUAL(-1, fixed_atanh<Q1_30>(-Q1_30::resolution()).raw());
  const int n = 5000;
  for (int i = 0; i <= n; ++i) {
    const Q1_30 z(0.999999 * double(i) / double(n));
    CHECK(fixed_atanh<Q7_24>(-z) == -fixed_atanh<Q7_24>(z));
    CHECK(atanh_error_q7_24(-z) <= stated_bound<Q7_24>());
  }
}

TEST(FixedMath, AtanhSaturatesAtAndBeyondOne) {
  CHECK(fixed_atanh<Q7_24>(Q1_30(1.0)) == Q7_24::highest());
  CHECK(fixed_atanh<Q7_24>(Q1_30(-1.0)) == Q7_24::lowest());
  CHECK(fixed_atanh<Q7_24>(Q1_30(1.5)) == Q7_24::highest());
  CHECK(fixed_atanh<Q7_24>(Q1_30(-1.5)) == Q7_24::lowest());
  CHECK(fixed_atanh<Q7_24>(Q1_30::highest()) == Q7_24::highest());
  CHECK(fixed_atanh<Q7_24>(Q1_30::lowest()) == Q7_24::lowest());
  // A format too narrow for atanh near 1 (Q2.29 holds ±4; atanh(1 − 2^−30) = 10.7) saturates too.
  CHECK(fixed_atanh<Q2_29>(Q1_30::from_raw((1 << 30) - 1)) == Q2_29::highest());
  CHECK(fixed_atanh<Q2_29>(Q1_30::from_raw(-(1 << 30) + 1)) == Q2_29::lowest());
}

TEST(FixedMath, TimeToInstabilityExample) {
  // t = atanh(z)/ω entirely in fixed point: z = 0.9, ω = 2.5 rad/s → t = 0.588 s.
  const Q7_24 atanh_z = fixed_atanh<Q7_24>(Q1_30(0.9));
  const Q7_24 t_s = atanh_z / Q7_24(2.5);
  DOUBLES_EQUAL(std::atanh(0.9) / 2.5, t_s.to_double(), 2.0 * Q7_24::resolution_value());
}
