// Fixed<I, F>: conversions, same-format arithmetic and the mixed-format operations, against exact references.
// The random cases come from a fixed-seed SplitMix64 written here (not std:: distributions, whose output
// differs between standard libraries), so every run and platform checks the same values.
#include <cmath>
#include <cstdint>
#include <limits>

#include "rockwatch/core/fixed_point.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_fixed_point {

using namespace rockwatch::core;

namespace {

using Q7_24 = Fixed<7, 24>;
using Q0_31 = Fixed<0, 31>;
using Q1_30 = Fixed<1, 30>;
using Q15_16 = Fixed<15, 16>;
using Q31_0 = Fixed<31, 0>;
// Negative integer bits: values below 2^IntBits in magnitude, more than 31 fraction bits.
using Qm12_43 = Fixed<-12, 43>;
using Qm30_61 = Fixed<-30, 61>;

constexpr int kRandomCases = 4000;

// The references hold products of two int32 raws (62 bits) and quotients exactly enough to round correctly.
static_assert(std::numeric_limits<long double>::digits >= 64, "the exact references need a 64-bit mantissa");

// SplitMix64 (Steele, Lea, Flood 2014): tiny, full-period, identical everywhere.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // A raw value of random sign whose magnitude has 0..31 significant bits, so small values, values near 1
  // and values near the range ends all appear (a uniform raw would almost always be huge).
  std::int32_t raw() {
    const auto bits = static_cast<int>(next() % 32u);
    const std::uint64_t magnitude = next() & ((std::uint64_t{1} << bits) - 1u);
    const auto v = static_cast<std::int32_t>(magnitude);
    return (next() & 1u) != 0 ? -v : v;
  }
};

// The raw value of Out nearest to `exact_raw` (ties away from zero), clamped to ±(2^31 − 1).
std::int32_t reference_raw(long double exact_raw) {
  const long double r = std::round(exact_raw);  // std::round: halfway cases away from zero
  if (r >= 2147483647.0L) return INT32_MAX;
  if (r <= -2147483647.0L) return -INT32_MAX;
  return static_cast<std::int32_t>(r);
}

template <typename Out, typename A, typename B>
std::int32_t reference_mul(A a, B b) {
  // The product of the raws is exact in long double; scaling by a power of two is exact too.
  const long double product = static_cast<long double>(std::int64_t{a.raw()} * b.raw());
  return reference_raw(std::ldexp(product, Out::kFracBits - A::kFracBits - B::kFracBits));
}

template <typename Out, typename A, typename B>
std::int32_t reference_div(A a, B b) {
  if (b.raw() == 0) return a.raw() == 0 ? 0 : (a.raw() > 0 ? INT32_MAX : -INT32_MAX);
  // a/b · 2^F_out = (raw_a · 2^(F_out + F_b − F_a)) / raw_b: an exact dividend; the quotient is rounded to 64
  // bits, which cannot move it across a halfway point (those are at least 1/|raw_b| ≥ 2^−31 away).
  const int widen = Out::kFracBits + B::kFracBits - A::kFracBits;
  const long double dividend = std::ldexp(static_cast<long double>(a.raw()), widen);
  return reference_raw(dividend / static_cast<long double>(b.raw()));
}

template <typename Out, typename A>
std::int32_t reference_convert(A a) {
  return reference_raw(std::ldexp(static_cast<long double>(a.raw()), Out::kFracBits - A::kFracBits));
}

// Same-format operators against the reference, on random operands.
template <typename Q>
void check_same_format_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const Q a = Q::from_raw(rng.raw());
    const Q b = Q::from_raw(rng.raw());
    LONGS_EQUAL(reference_raw(static_cast<long double>(std::int64_t{a.raw()} + b.raw())), (a + b).raw());
    LONGS_EQUAL(reference_raw(static_cast<long double>(std::int64_t{a.raw()} - b.raw())), (a - b).raw());
    LONGS_EQUAL(-a.raw(), (-a).raw());
    LONGS_EQUAL(reference_mul<Q>(a, b), (a * b).raw());
    LONGS_EQUAL(reference_div<Q>(a, b), (a / b).raw());
  }
}

template <typename Out, typename A, typename B>
void check_mixed_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const A a = A::from_raw(rng.raw());
    const B b = B::from_raw(rng.raw());
    LONGS_EQUAL(reference_mul<Out>(a, b), (fixed_mul<Out>(a, b)).raw());
    LONGS_EQUAL(reference_convert<Out>(a), (fixed_convert<Out>(a)).raw());
  }
}

template <typename Out, typename A, typename B>
void check_mixed_div_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const A a = A::from_raw(rng.raw());
    const B b = B::from_raw(rng.raw());
    LONGS_EQUAL(reference_div<Out>(a, b), (fixed_div<Out>(a, b)).raw());
  }
}

// Usable in constant expressions: tables and constants can be built at compile time.
static_assert(Q7_24(1.5).raw() == 3 << 23, "exact conversion");
static_assert(Q7_24(-0.5) + Q7_24(2) == Q7_24(1.5), "addition");
static_assert((Q7_24(1.5) * Q7_24(-2)).raw() == -(3 << 24), "multiplication");
static_assert((Q7_24(1) / Q7_24(4)).raw() == 1 << 22, "division");
static_assert((Q31_0(1) / Q31_0(2)).raw() == 1 && (Q31_0(-1) / Q31_0(2)).raw() == -1, "ties away from zero");
static_assert(fixed_mul<Q1_30>(Q7_24(0.5), Q0_31(0.5)) == Q1_30(0.25), "mixed-format product");
static_assert(fixed_div<Q7_24>(Q1_30(0.75), Q1_30(0.25)) == Q7_24(3), "mixed-format quotient");
static_assert(fixed_convert<Q15_16>(Q7_24(-3.25)) == Q15_16(-3.25), "conversion");
static_assert(abs(Q7_24(-2)) == Q7_24(2) && Q7_24::from_raw(INT32_MIN) == Q7_24::lowest(), "abs, from_raw");
static_assert(Q7_24(128.0) == Q7_24::highest() && Q7_24(100) + Q7_24(100) == Q7_24::highest(), "saturation");

}  // namespace

TEST_GROUP(FixedPoint){};

TEST(FixedPoint, ConversionFromDoubleRoundsHalfwayCasesAwayFromZero) {
  LONGS_EQUAL(1, Q31_0(0.5).raw());
  LONGS_EQUAL(-1, Q31_0(-0.5).raw());
  LONGS_EQUAL(2, Q31_0(1.5).raw());
  LONGS_EQUAL(-2, Q31_0(-1.5).raw());
  LONGS_EQUAL(3, Q31_0(2.5).raw());  // away from zero, not to even
  LONGS_EQUAL(-3, Q31_0(-2.5).raw());
  LONGS_EQUAL(2, Q31_0(2.4999999).raw());
  LONGS_EQUAL(-2, Q31_0(-2.4999999).raw());
  // The largest double below one half: adding ½ in floating point would round it up to 1.
  const double below_half = std::nextafter(0.5, 0.0);
  LONGS_EQUAL(0, Q31_0(below_half).raw());
  LONGS_EQUAL(0, Q31_0(-below_half).raw());
  LONGS_EQUAL(0, Q7_24(std::ldexp(below_half, -24)).raw());
  LONGS_EQUAL(1, Q31_0(std::nextafter(0.5, 1.0)).raw());
  // Halfway between two Q7.24 steps, both signs, at several magnitudes.
  for (const std::int32_t k : {0, 1, 7, 1 << 20, (1 << 24) + 3, INT32_MAX - 1}) {
    const double half_step_above = std::ldexp(double(k) + 0.5, -24);
    LONGS_EQUAL(k + 1, Q7_24(half_step_above).raw());
    LONGS_EQUAL(-(k + 1), Q7_24(-half_step_above).raw());
    LONGS_EQUAL(k, Q7_24(std::ldexp(double(k) + 0.49, -24)).raw());
    LONGS_EQUAL(-k, Q7_24(-std::ldexp(double(k) + 0.49, -24)).raw());
  }
  LONGS_EQUAL(1 << 30, Q0_31(0.5).raw());
  LONGS_EQUAL(1, Q0_31(std::ldexp(1.0, -32)).raw());  // half a step rounds up
  LONGS_EQUAL(-1, Q0_31(-std::ldexp(1.0, -32)).raw());
  LONGS_EQUAL(0, Q0_31(std::ldexp(0.99, -32)).raw());
}

TEST(FixedPoint, ConversionFromDoubleSaturatesAndMapsNanToZero) {
  CHECK(Q7_24(128.0) == Q7_24::highest());
  CHECK(Q7_24(1e300) == Q7_24::highest());
  CHECK(Q7_24(std::numeric_limits<double>::infinity()) == Q7_24::highest());
  CHECK(Q7_24(-128.0) == Q7_24::lowest());
  CHECK(Q7_24(-1e300) == Q7_24::lowest());
  CHECK(Q7_24(-std::numeric_limits<double>::infinity()) == Q7_24::lowest());
  LONGS_EQUAL(0, Q7_24(std::numeric_limits<double>::quiet_NaN()).raw());
  LONGS_EQUAL(0, Q7_24(-std::numeric_limits<double>::quiet_NaN()).raw());
  // The last values before the ends: the largest raw is reached exactly and by rounding, never exceeded.
  LONGS_EQUAL(INT32_MAX, Q7_24(std::ldexp(2147483647.0, -24)).raw());
  LONGS_EQUAL(INT32_MAX, Q7_24(std::ldexp(2147483646.5, -24)).raw());
  LONGS_EQUAL(INT32_MAX - 1, Q7_24(std::ldexp(2147483646.25, -24)).raw());
  LONGS_EQUAL(-INT32_MAX, Q7_24(-std::ldexp(2147483646.5, -24)).raw());
  LONGS_EQUAL(-INT32_MAX, Q7_24(-std::ldexp(2147483647.75, -24)).raw());
  CHECK(Q0_31(1.0) == Q0_31::highest());
  CHECK(Q0_31(-1.0) == Q0_31::lowest());  // −1 itself is INT32_MIN raw, outside the symmetric range
  CHECK(Q31_0(3e9) == Q31_0::highest());
  CHECK(Q7_24(-128.0).saturated() && Q7_24(128.0).saturated() && !Q7_24(127.0).saturated());
}

TEST(FixedPoint, ConversionFromIntIsExactOrSaturates) {
  LONGS_EQUAL(127 << 24, Q7_24(127).raw());
  LONGS_EQUAL(-(127 << 24), Q7_24(-127).raw());
  CHECK(Q7_24(128) == Q7_24::highest());
  CHECK(Q7_24(-128) == Q7_24::lowest());
  CHECK(Q7_24(INT32_MAX) == Q7_24::highest());
  CHECK(Q7_24(INT32_MIN) == Q7_24::lowest());
  CHECK(Q0_31(1) == Q0_31::highest());
  CHECK(Q0_31(-1) == Q0_31::lowest());
  LONGS_EQUAL(0, Q0_31(0).raw());
  CHECK(Q31_0(INT32_MIN) == Q31_0::lowest());
  LONGS_EQUAL(INT32_MAX, Q31_0(INT32_MAX).raw());
}

TEST(FixedPoint, ConversionToDoubleIsExactAndRoundTrips) {
  SplitMix64 rng{1};
  for (int i = 0; i < kRandomCases; ++i) {
    const std::int32_t raw = rng.raw();
    const Q7_24 a = Q7_24::from_raw(raw);
    const Q0_31 b = Q0_31::from_raw(raw);
    const Q31_0 c = Q31_0::from_raw(raw);
    DOUBLES_EQUAL(std::ldexp(double(raw), -24), a.to_double(), 0.0);
    DOUBLES_EQUAL(std::ldexp(double(raw), -31), b.to_double(), 0.0);
    DOUBLES_EQUAL(double(raw), c.to_double(), 0.0);
    CHECK(Q7_24(a.to_double()) == a);
    CHECK(Q0_31(b.to_double()) == b);
    CHECK(Q31_0(c.to_double()) == c);
  }
  DOUBLES_EQUAL(std::ldexp(1.0, -24), Q7_24::resolution().to_double(), 0.0);
  DOUBLES_EQUAL(std::ldexp(1.0, -24), Q7_24::resolution_value(), 0.0);
  DOUBLES_EQUAL(128.0 - std::ldexp(1.0, -24), Q7_24::highest().to_double(), 0.0);
}

TEST(FixedPoint, FromRawMapsInt32MinToLowest) {
  LONGS_EQUAL(-INT32_MAX, Q7_24::from_raw(INT32_MIN).raw());
  LONGS_EQUAL(-INT32_MAX, Q0_31::from_raw(INT32_MIN).raw());
  LONGS_EQUAL(INT32_MAX, (-Q7_24::from_raw(INT32_MIN)).raw());
  LONGS_EQUAL(INT32_MAX, abs(Q7_24::from_raw(INT32_MIN)).raw());
  LONGS_EQUAL(-INT32_MAX + 1, Q7_24::from_raw(-INT32_MAX + 1).raw());
  CHECK(Q7_24::from_raw(INT32_MIN).saturated());
}

TEST(FixedPoint, AdditionAndSubtractionAreExactAndSaturateAtBothEnds) {
  CHECK(Q7_24(1.25) + Q7_24(-3.5) == Q7_24(-2.25));
  CHECK(Q7_24(1.25) - Q7_24(-3.5) == Q7_24(4.75));
  CHECK(Q7_24::highest() + Q7_24::resolution() == Q7_24::highest());
  CHECK(Q7_24::lowest() - Q7_24::resolution() == Q7_24::lowest());
  CHECK(Q7_24::highest() + Q7_24::highest() == Q7_24::highest());
  CHECK(Q7_24::lowest() + Q7_24::lowest() == Q7_24::lowest());
  CHECK(Q7_24::highest() - Q7_24::lowest() == Q7_24::highest());
  CHECK(Q7_24::lowest() - Q7_24::highest() == Q7_24::lowest());
  CHECK(Q7_24::highest() + Q7_24::lowest() == Q7_24(0));
  CHECK(Q7_24(100) + Q7_24(100) - Q7_24(100) == Q7_24::highest() - Q7_24(100));  // saturation is not undone
  CHECK(-Q7_24::highest() == Q7_24::lowest());
  CHECK(-Q7_24::lowest() == Q7_24::highest());
  CHECK(-Q7_24(0) == Q7_24(0));
  Q7_24 acc(1);
  acc += Q7_24(2);
  acc -= Q7_24(0.5);
  CHECK(acc == Q7_24(2.5));
  acc *= Q7_24(-2);
  CHECK(acc == Q7_24(-5));
  acc /= Q7_24(4);
  CHECK(acc == Q7_24(-1.25));
}

TEST(FixedPoint, MultiplicationRoundsOnceHalfwayAwayFromZero) {
  CHECK(Q7_24(1.5) * Q7_24(-2.25) == Q7_24(-3.375));
  CHECK(Q7_24(0) * Q7_24::highest() == Q7_24(0));
  // Half a step: ties away from zero, with every sign combination.
  const Q7_24 half(0.5);
  const Q7_24 step = Q7_24::resolution();
  LONGS_EQUAL(1, (half * step).raw());
  LONGS_EQUAL(-1, (-half * step).raw());
  LONGS_EQUAL(-1, (half * -step).raw());
  LONGS_EQUAL(1, (-half * -step).raw());
  LONGS_EQUAL(2, (Q7_24(1.5) * step).raw());  // 1.5 steps → 2
  LONGS_EQUAL(-2, (Q7_24(-1.5) * step).raw());
  LONGS_EQUAL(3, (Q7_24(2.5) * step).raw());  // 2.5 steps → 3 (not to even)
  LONGS_EQUAL(0, (Q7_24(0.4999999) * step).raw());
  LONGS_EQUAL(0, (Q7_24(-0.4999999) * step).raw());
  // Q0.31: 0.5 · 2^−31 is half a step.
  LONGS_EQUAL(1, (Q0_31(0.5) * Q0_31::resolution()).raw());
  LONGS_EQUAL(-1, (Q0_31(-0.5) * Q0_31::resolution()).raw());
  // Saturation at both ends.
  CHECK(Q7_24(12) * Q7_24(11) == Q7_24::highest());
  CHECK(Q7_24(-12) * Q7_24(11) == Q7_24::lowest());
  CHECK(Q7_24(12) * Q7_24(-11) == Q7_24::lowest());
  CHECK(Q7_24(-12) * Q7_24(-11) == Q7_24::highest());
  CHECK(Q7_24::highest() * Q7_24::highest() == Q7_24::highest());
  CHECK(Q7_24::lowest() * Q7_24::highest() == Q7_24::lowest());
  CHECK(Q7_24::lowest() * Q7_24::lowest() == Q7_24::highest());
  CHECK(Q31_0(65536) * Q31_0(32768) == Q31_0::highest());
  LONGS_EQUAL(INT32_MAX - 1, (Q0_31::highest() * Q0_31::highest()).raw());  // (1 − 2^−31)² rounds below 1
}

TEST(FixedPoint, DivisionRoundsOnceAndSaturatesIncludingDivisionByZero) {
  CHECK(Q7_24(1) / Q7_24(4) == Q7_24(0.25));
  CHECK(Q7_24(-7.5) / Q7_24(2.5) == Q7_24(-3));
  LONGS_EQUAL(5592405, (Q7_24(1) / Q7_24(3)).raw());  // 2^24/3 = 5592405.33
  LONGS_EQUAL(11184811, (Q7_24(2) / Q7_24(3)).raw());  // 11184810.67
  LONGS_EQUAL(-11184811, (Q7_24(-2) / Q7_24(3)).raw());
  LONGS_EQUAL(-11184811, (Q7_24(2) / Q7_24(-3)).raw());
  // Halfway quotients: away from zero, not to even.
  LONGS_EQUAL(1, (Q31_0(1) / Q31_0(2)).raw());
  LONGS_EQUAL(2, (Q31_0(3) / Q31_0(2)).raw());
  LONGS_EQUAL(3, (Q31_0(5) / Q31_0(2)).raw());
  LONGS_EQUAL(-3, (Q31_0(-5) / Q31_0(2)).raw());
  LONGS_EQUAL(-3, (Q31_0(5) / Q31_0(-2)).raw());
  LONGS_EQUAL(3, (Q31_0(-5) / Q31_0(-2)).raw());
  LONGS_EQUAL(1, (Q7_24::resolution() / Q7_24(2)).raw());
  LONGS_EQUAL(-1, (-Q7_24::resolution() / Q7_24(2)).raw());
  // Saturation.
  CHECK(Q7_24(100) / Q7_24(0.5) == Q7_24::highest());
  CHECK(Q7_24(-100) / Q7_24(0.5) == Q7_24::lowest());
  CHECK(Q7_24(100) / Q7_24(-0.5) == Q7_24::lowest());
  CHECK(Q7_24(1) / Q7_24::resolution() == Q7_24::highest());
  CHECK(Q7_24::highest() / Q7_24::resolution() == Q7_24::highest());
  CHECK(Q7_24::lowest() / Q7_24::resolution() == Q7_24::lowest());
  // Division by zero: saturates by the sign of the dividend; 0/0 = 0.
  CHECK(Q7_24(3) / Q7_24(0) == Q7_24::highest());
  CHECK(Q7_24(-3) / Q7_24(0) == Q7_24::lowest());
  CHECK(Q7_24::resolution() / Q7_24(0) == Q7_24::highest());
  CHECK(Q7_24(0) / Q7_24(0) == Q7_24(0));
  CHECK(Q0_31(-0.25) / Q0_31(0) == Q0_31::lowest());
  CHECK(fixed_div<Q7_24>(Q1_30(0.5), Q1_30(0)) == Q7_24::highest());
  CHECK(fixed_div<Q7_24>(Q1_30(-0.5), Q1_30(0)) == Q7_24::lowest());
  CHECK(fixed_div<Q7_24>(Q1_30(0), Q1_30(0)) == Q7_24(0));
  CHECK(Q7_24(0) / Q7_24(5) == Q7_24(0));
}

TEST(FixedPoint, SameFormatOperatorsMatchTheExactReference) {
  check_same_format_against_reference<Q7_24>(11);
  check_same_format_against_reference<Q0_31>(12);
  check_same_format_against_reference<Q1_30>(13);
  check_same_format_against_reference<Q15_16>(14);
  check_same_format_against_reference<Q31_0>(15);
  check_same_format_against_reference<Fixed<20, 11>>(16);
  check_same_format_against_reference<Fixed<-4, 35>>(17);
  check_same_format_against_reference<Qm12_43>(18);
  check_same_format_against_reference<Qm30_61>(19);
}

TEST(FixedPoint, FormatsWithNegativeIntegerBits) {
  // Q−12.43: range ±2^−12, resolution 2^−43.
  DOUBLES_EQUAL(std::ldexp(1.0, -43), Qm12_43::resolution_value(), 0.0);
  LONGS_EQUAL(1 << 20, Qm12_43(std::ldexp(1.0, -23)).raw());
  LONGS_EQUAL(1, Qm12_43(std::ldexp(1.0, -44)).raw());  // half a step: away from zero
  LONGS_EQUAL(-1, Qm12_43(-std::ldexp(1.0, -44)).raw());
  CHECK(Qm12_43(std::ldexp(1.0, -12)) == Qm12_43::highest());
  CHECK(Qm12_43(1) == Qm12_43::highest());
  CHECK(Qm12_43(-1) == Qm12_43::lowest());
  CHECK(Qm12_43(0) == Qm12_43());
  DOUBLES_EQUAL(std::ldexp(1.0, -61), Qm30_61::resolution().to_double(), 0.0);
  CHECK(Qm30_61(Qm30_61::highest().to_double()) == Qm30_61::highest());
  // Products round once (shift 43), quotients whose widened dividend would pass 2^62 saturate by sign.
  LONGS_EQUAL(1 << 17, (Qm12_43(std::ldexp(1.0, -13)) * Qm12_43(std::ldexp(1.0, -13))).raw());
  CHECK(Qm12_43(std::ldexp(1.0, -20)) / Qm12_43(std::ldexp(1.0, -30)) == Qm12_43::highest());
  CHECK(Qm12_43(-std::ldexp(1.0, -20)) / Qm12_43(std::ldexp(1.0, -30)) == Qm12_43::lowest());
  CHECK(Qm12_43(std::ldexp(1.0, -20)) / Qm12_43(-std::ldexp(1.0, -30)) == Qm12_43::lowest());
  CHECK(Qm12_43::highest() / Qm12_43::highest() == Qm12_43::highest());  // 1 is beyond 2^−12
  CHECK(Qm12_43(std::ldexp(1.0, -20)) / Qm12_43(0) == Qm12_43::highest());
  CHECK(Qm12_43(-std::ldexp(1.0, -20)) / Qm12_43(0) == Qm12_43::lowest());
  // A small dividend is still divided exactly: (2^−40)/(3 · 2^−14) = 2^−26/3 → raw 2^17/3 = 43690.67.
  LONGS_EQUAL(43691, (Qm12_43(std::ldexp(1.0, -40)) / Qm12_43(3.0 * std::ldexp(1.0, -14))).raw());
  // Mixed formats in and out of them.
  check_mixed_against_reference<Qm12_43, Q0_31, Q0_31>(41);   // shift 19
  check_mixed_against_reference<Q7_24, Qm12_43, Q15_16>(42);  // shift 35
  check_mixed_against_reference<Qm30_61, Qm12_43, Qm12_43>(43);  // shift 25
  check_mixed_against_reference<Q31_0, Qm30_61, Qm30_61>(44);  // shift 122: always 0
  check_mixed_div_against_reference<Qm12_43, Qm12_43, Q7_24>(45);  // widen 24
  check_mixed_div_against_reference<Q1_30, Qm12_43, Q15_16>(46);   // widen 3
}

TEST(FixedPoint, MixedFormatProductAndConversionRoundOnce) {
  check_mixed_against_reference<Q7_24, Q1_30, Q15_16>(21);   // shift 22
  check_mixed_against_reference<Q1_30, Q7_24, Q0_31>(22);    // shift 25
  check_mixed_against_reference<Q31_0, Q0_31, Q0_31>(23);    // shift 62: the largest
  check_mixed_against_reference<Q0_31, Q31_0, Q31_0>(24);    // shift −31: left shift with saturation
  check_mixed_against_reference<Q7_24, Q31_0, Q15_16>(25);   // shift −8
  check_mixed_against_reference<Q15_16, Q7_24, Q7_24>(26);   // shift 32
  check_mixed_against_reference<Q7_24, Q7_24, Q7_24>(27);    // same format as operator*
  check_mixed_against_reference<Fixed<4, 27>, Q1_30, Q7_24>(28);
  // The product does not depend on operand order, and negation commutes with the rounding.
  SplitMix64 rng{29};
  for (int i = 0; i < kRandomCases; ++i) {
    const Q1_30 a = Q1_30::from_raw(rng.raw());
    const Q15_16 b = Q15_16::from_raw(rng.raw());
    CHECK(fixed_mul<Q7_24>(a, b) == fixed_mul<Q7_24>(b, a));
    CHECK(fixed_mul<Q7_24>(-a, b) == -fixed_mul<Q7_24>(a, b));
    CHECK(fixed_convert<Q7_24>(-a) == -fixed_convert<Q7_24>(a));
  }
}

TEST(FixedPoint, MixedFormatQuotientRoundsOnce) {
  check_mixed_div_against_reference<Q7_24, Q7_24, Q7_24>(31);   // widen 24
  check_mixed_div_against_reference<Q7_24, Q1_30, Q1_30>(32);   // widen 24
  check_mixed_div_against_reference<Q7_24, Q1_30, Q7_24>(33);   // widen 18
  check_mixed_div_against_reference<Q0_31, Q0_31, Q0_31>(34);   // widen 31: the largest
  check_mixed_div_against_reference<Q31_0, Q7_24, Q7_24>(35);   // widen 0
  check_mixed_div_against_reference<Q15_16, Q0_31, Q15_16>(36); // widen 1
  check_mixed_div_against_reference<Fixed<4, 27>, Q1_30, Q7_24>(37);   // widen 21
}

TEST(FixedPoint, MixedFormatConversionRoundsOrSaturates) {
  // Dropping bits: Q0.31 raw 1 is half a Q1.30 step.
  LONGS_EQUAL(1, fixed_convert<Q1_30>(Q0_31::from_raw(1)).raw());
  LONGS_EQUAL(-1, fixed_convert<Q1_30>(Q0_31::from_raw(-1)).raw());
  LONGS_EQUAL(2, fixed_convert<Q1_30>(Q0_31::from_raw(3)).raw());
  LONGS_EQUAL(-2, fixed_convert<Q1_30>(Q0_31::from_raw(-3)).raw());
  LONGS_EQUAL(2, fixed_convert<Q1_30>(Q0_31::from_raw(4)).raw());
  LONGS_EQUAL(1, fixed_convert<Q31_0>(Q0_31(0.5)).raw());
  LONGS_EQUAL(0, fixed_convert<Q31_0>(Q0_31(0.4999)).raw());
  // Adding bits: exact, saturating beyond the target's range.
  CHECK(fixed_convert<Q7_24>(Q15_16(-100.75)) == Q7_24(-100.75));
  CHECK(fixed_convert<Q7_24>(Q15_16(200)) == Q7_24::highest());
  CHECK(fixed_convert<Q7_24>(Q15_16(-200)) == Q7_24::lowest());
  CHECK(fixed_convert<Q0_31>(Q31_0(1)) == Q0_31::highest());
  CHECK(fixed_convert<Q0_31>(Q31_0(-1)) == Q0_31::lowest());
  CHECK(fixed_convert<Q0_31>(Q31_0(0)) == Q0_31(0));
  // Highest of the wider-range format into the narrower one.
  CHECK(fixed_convert<Q1_30>(Q7_24::highest()) == Q1_30::highest());
  CHECK(fixed_convert<Q7_24>(Q1_30::highest()) == Q7_24(2));  // 2 − 2^−30 rounds to 2
}

TEST(FixedPoint, AbsAndComparisons) {
  CHECK(abs(Q7_24(-3.5)) == Q7_24(3.5));
  CHECK(abs(Q7_24(3.5)) == Q7_24(3.5));
  CHECK(abs(Q7_24::lowest()) == Q7_24::highest());
  CHECK(Q7_24(-1) < Q7_24(1));
  CHECK(Q7_24(1) <= Q7_24(1));
  CHECK(Q7_24(2) > Q7_24(1));
  CHECK(Q7_24(2) >= Q7_24(2));
  CHECK(Q7_24(2) != Q7_24(1));
  CHECK(Q7_24::lowest() < -Q7_24::resolution());
  CHECK(Q7_24() == Q7_24(0));
}

}  // namespace unity_test_fixed_point
