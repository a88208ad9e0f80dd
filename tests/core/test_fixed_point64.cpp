// Fixed64<I, F>: the portable 128-bit helpers against the compiler's 128-bit type, conversions, same-format
// arithmetic and the mixed-format operations (also with the 32-bit Fixed), against exact references computed here
// with unsigned __int128 (exact rational result, rounded half away from zero, clamped to the symmetric range).
// The random cases come from a fixed-seed SplitMix64 (as in test_fixed_point.cpp), so every run checks the same
// values.
#include <cmath>
#include <cstdint>
#include <limits>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point64.hpp"

#include <CppUTest/TestHarness.h>

#if !defined(__SIZEOF_INT128__)
#error "the exact references of this test need the compiler's 128-bit integers (a host test)"
#endif

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_fixed_point64 {

using namespace rockwatch::core;

namespace {

__extension__ typedef unsigned __int128 u128;  // __extension__ keeps -Wpedantic quiet
__extension__ typedef __int128 i128;

using Q1_62 = Fixed64<1, 62>;
using Q7_56 = Fixed64<7, 56>;
using Q0_63 = Fixed64<0, 63>;
using Q3_60 = Fixed64<3, 60>;
using Q31_32 = Fixed64<31, 32>;
using Q63_0 = Fixed64<63, 0>;
// Negative integer bits: more than 63 fraction bits (no operator/, whose widening would pass 63 bits).
using Qm12_75 = Fixed64<-12, 75>;
using Qm60_123 = Fixed64<-60, 123>;
// The 32-bit formats mixed in.
using Q7_24 = Fixed<7, 24>;
using Q1_30 = Fixed<1, 30>;

// LONGS_EQUAL compares as long: 64-bit raws need a 64-bit long (LP64 hosts).
static_assert(sizeof(long) >= sizeof(std::int64_t), "the checks compare 64-bit raws as long");

constexpr int kRandomCases = 4000;
constexpr int kRandomWords = 20000;
constexpr std::int64_t kMax64 = INT64_MAX;

// The largest raw of a format: 2^63 − 1 (Fixed64) or 2^31 − 1 (Fixed). Results clamp to ±this.
template <typename Q>
constexpr std::int64_t kRawLimit = std::numeric_limits<decltype(Q().raw())>::max();

// Words where the 32-bit halves carry into each other or the division's shifted-out top bit matters.
constexpr std::uint64_t kEdgeWords[] = {
    0u, 1u, 2u, 3u, 0x7fffffffu, 0xffffffffu, 0x100000000u, 0x100000001u, 0xffffffff00000000u, 0x00000001ffffffffu,
    0x7fffffffffffffffu, 0x8000000000000000u, 0x8000000000000001u, 0xfffffffffffffffeu, 0xffffffffffffffffu};

constexpr std::int64_t kEdgeMagnitudes[] = {0, 1, 2, 3,
                                            std::int64_t{1} << 31, (std::int64_t{1} << 32) - 1,
                                            std::int64_t{1} << 32, (std::int64_t{1} << 32) + 1,
                                            std::int64_t{1} << 61, (std::int64_t{1} << 62) - 1,
                                            std::int64_t{1} << 62, (std::int64_t{1} << 62) + 1,
                                            kMax64 - 1, kMax64};

// SplitMix64 (Steele, Lea, Flood 2014): tiny, full-period, identical everywhere.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // A 64-bit word with 0..64 significant bits, or (one in eight) an edge value.
  std::uint64_t word() {
    if (next() % 8u == 0) return kEdgeWords[next() % (sizeof kEdgeWords / sizeof kEdgeWords[0])];
    const auto bits = static_cast<int>(next() % 65u);
    return bits == 64 ? next() : next() & ((std::uint64_t{1} << bits) - 1u);
  }
  // A Fixed64 raw of random sign whose magnitude has 0..63 significant bits, or an edge value (0, 1, 2^32 ± 1,
  // 2^62, the ends, INT64_MIN) so small values, values near 1 and values near the range ends all appear.
  std::int64_t raw64() {
    const std::uint64_t pick = next() % 64u;
    if (pick == 0) return INT64_MIN;
    std::int64_t magnitude = 0;
    if (pick < 9) {
      magnitude = kEdgeMagnitudes[next() % (sizeof kEdgeMagnitudes / sizeof kEdgeMagnitudes[0])];
    } else {
      const auto bits = static_cast<int>(next() % 64u);
      magnitude = static_cast<std::int64_t>(next() & ((std::uint64_t{1} << bits) - 1u));
    }
    return (next() & 1u) != 0 ? -magnitude : magnitude;
  }
  // A Fixed raw (as in test_fixed_point.cpp): 0..31 significant bits, random sign.
  std::int32_t raw32() {
    const auto bits = static_cast<int>(next() % 32u);
    const auto v = static_cast<std::int32_t>(next() & ((std::uint64_t{1} << bits) - 1u));
    return (next() & 1u) != 0 ? -v : v;
  }
};

template <typename Q>
Q random_value(SplitMix64& rng) {
  if constexpr (kRawLimit<Q> == INT32_MAX) {
    return Q::from_raw(rng.raw32());
  } else {
    return Q::from_raw(rng.raw64());
  }
}

std::uint64_t magnitude_of(std::int64_t v) {
  return v < 0 ? std::uint64_t(0) - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
}

// ±m, clamped to ±limit.
std::int64_t signed_clamped(bool negative, u128 m, std::int64_t limit) {
  const auto v = static_cast<std::int64_t>(m > static_cast<u128>(limit) ? static_cast<u128>(limit) : m);
  return negative ? -v : v;
}

// The integer nearest to m · 2^−shift, halfway up (the magnitude of a ties-away result), for any shift. Growing
// (shift < 0) stops once past `cap`, which is enough to clamp.
u128 round_scaled(u128 m, int shift, std::int64_t cap) {
  if (shift <= 0) {
    for (int i = 0; i < -shift && m <= static_cast<u128>(cap); ++i) m *= 2u;  // m ≤ 2^63 − 1 before doubling
    return m;
  }
  if (shift >= 128) return 0;  // m < 2^126 (a product of two magnitudes ≤ 2^63 − 1): below one quarter
  const u128 q = m >> shift;
  const u128 r = m - (q << shift);
  return r >= (u128{1} << (shift - 1)) ? q + 1u : q;
}

// round(a · b · 2^−shift) on raws, clamped to ±limit.
std::int64_t reference_mul_raw(std::int64_t a, std::int64_t b, int shift, std::int64_t limit) {
  const u128 product = static_cast<u128>(magnitude_of(a)) * magnitude_of(b);
  return signed_clamped((a < 0) != (b < 0), round_scaled(product, shift, limit), limit);
}

// round(n · 2^widen / d) on raws, clamped; d = 0 gives ±limit by the sign of n, 0/0 = 0.
std::int64_t reference_div_raw(std::int64_t n, std::int64_t d, int widen, std::int64_t limit) {
  if (d == 0) return n == 0 ? 0 : (n > 0 ? limit : -limit);
  const u128 dividend = static_cast<u128>(magnitude_of(n)) << widen;  // < 2^126 for widen ≤ 63
  const u128 divisor = magnitude_of(d);
  u128 q = dividend / divisor;
  const u128 r = dividend % divisor;
  if (2u * r >= divisor) ++q;
  return signed_clamped((n < 0) != (d < 0), q, limit);
}

std::int64_t reference_convert_raw(std::int64_t v, int shift, std::int64_t limit) {
  return signed_clamped(v < 0, round_scaled(magnitude_of(v), shift, limit), limit);
}

template <typename Out, typename A, typename B>
std::int64_t reference_mul(A a, B b) {
  return reference_mul_raw(a.raw(), b.raw(), A::kFracBits + B::kFracBits - Out::kFracBits, kRawLimit<Out>);
}
template <typename Out, typename A, typename B>
std::int64_t reference_div(A a, B b) {
  return reference_div_raw(a.raw(), b.raw(), Out::kFracBits + B::kFracBits - A::kFracBits, kRawLimit<Out>);
}
template <typename Out, typename A>
std::int64_t reference_convert(A a) {
  return reference_convert_raw(a.raw(), A::kFracBits - Out::kFracBits, kRawLimit<Out>);
}

// The raw nearest to v · 2^F (std::round: halfway away from zero; v · 2^F is exact in double), clamped; NaN → 0.
template <typename Q>
std::int64_t reference_from_double(double v) {
  if (std::isnan(v)) return 0;
  const double r = std::round(std::ldexp(v, Q::kFracBits));
  if (r >= 0x1p63) return kMax64;
  if (r <= -0x1p63) return -kMax64;
  return static_cast<std::int64_t>(r);
}

// v · 2^F, clamped.
template <typename Q>
std::int64_t reference_from_integer(std::int64_t v) {
  return reference_convert_raw(v, -Q::kFracBits, kMax64);
}

// One raw result; on a mismatch the message names the operation and the operand raws.
void expect_raw(const char* what, std::int64_t expected, std::int64_t actual, std::int64_t a, std::int64_t b) {
  if (expected == actual) return;
  const SimpleString text = StringFromFormat("%s with raws a = %lld, b = %lld", what, static_cast<long long>(a),
                                             static_cast<long long>(b));
  LONGS_EQUAL_TEXT(expected, actual, text.asCharString());
}

void expect_word(const char* what, std::uint64_t expected, std::uint64_t actual, std::uint64_t x, std::uint64_t y) {
  if (expected == actual) return;
  const SimpleString text = StringFromFormat("%s with 0x%016llx, 0x%016llx", what, static_cast<unsigned long long>(x),
                                             static_cast<unsigned long long>(y));
  UNSIGNED_LONGS_EQUAL_TEXT(expected, actual, text.asCharString());
}

std::int64_t clamp_sum(i128 v) { return v > kMax64 ? kMax64 : (v < -kMax64 ? -kMax64 : static_cast<std::int64_t>(v)); }

// Same-format operators against the reference, on random operands; / where the format allows it.
template <typename Q>
void check_same_format_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const Q a = random_value<Q>(rng);
    const Q b = random_value<Q>(rng);
    expect_raw("a + b", clamp_sum(i128{a.raw()} + b.raw()), (a + b).raw(), a.raw(), b.raw());
    expect_raw("a - b", clamp_sum(i128{a.raw()} - b.raw()), (a - b).raw(), a.raw(), b.raw());
    expect_raw("-a", -a.raw(), (-a).raw(), a.raw(), 0);
    expect_raw("a * b", reference_mul<Q>(a, b), (a * b).raw(), a.raw(), b.raw());
    expect_raw("wide_mul<Q>(a, b)", (a * b).raw(), wide_mul<Q>(a, b).raw(), a.raw(), b.raw());
    if constexpr (Q::kFracBits <= 63) {
      expect_raw("a / b", reference_div<Q>(a, b), (a / b).raw(), a.raw(), b.raw());
      expect_raw("wide_div<Q>(a, b)", (a / b).raw(), wide_div<Q>(a, b).raw(), a.raw(), b.raw());
    }
  }
}

template <typename Out, typename A, typename B>
void check_mixed_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const A a = random_value<A>(rng);
    const B b = random_value<B>(rng);
    expect_raw("wide_mul", reference_mul<Out>(a, b), wide_mul<Out>(a, b).raw(), a.raw(), b.raw());
    expect_raw("wide_mul swapped", reference_mul<Out>(a, b), wide_mul<Out>(b, a).raw(), a.raw(), b.raw());
    expect_raw("wide_convert", reference_convert<Out>(a), wide_convert<Out>(a).raw(), a.raw(), 0);
    expect_raw("wide_convert(-a)", -wide_convert<Out>(a).raw(), wide_convert<Out>(-a).raw(), a.raw(), 0);
  }
}

template <typename Out, typename A, typename B>
void check_mixed_div_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const A a = random_value<A>(rng);
    const B b = random_value<B>(rng);
    expect_raw("wide_div", reference_div<Out>(a, b), wide_div<Out>(a, b).raw(), a.raw(), b.raw());
  }
}

template <typename Q>
void check_double_conversion_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    // A 53-bit mantissa placed from 2^−58 to 2^66 raw steps; every fourth one exactly halfway between two steps.
    const bool halfway = i % 4 == 0;
    const std::uint64_t mantissa = halfway ? (rng.next() >> 12) | 1u : rng.next() >> 11;
    const int exponent = halfway ? -Q::kFracBits - 1 : -Q::kFracBits - 58 + static_cast<int>(rng.next() % 72u);
    const double magnitude = std::ldexp(static_cast<double>(mantissa), exponent);
    const double v = (rng.next() & 1u) != 0 ? -magnitude : magnitude;
    expect_raw("Q(double)", reference_from_double<Q>(v), Q(v).raw(), static_cast<std::int64_t>(mantissa), exponent);
  }
}

template <typename Q>
void check_integer_conversion_against_reference(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const std::int64_t v = rng.raw64();
    expect_raw("Q(int64)", reference_from_integer<Q>(v), Q(v).raw(), v, 0);
    const auto small = static_cast<std::int32_t>(v % 1000);
    expect_raw("Q(int32)", reference_from_integer<Q>(small), Q(small).raw(), small, 0);
  }
}

template <typename Q>
void check_to_double(std::uint64_t seed) {
  SplitMix64 rng{seed};
  for (int i = 0; i < kRandomCases; ++i) {
    const Q a = Q::from_raw(rng.raw64());
    const double d = a.to_double();
    DOUBLES_EQUAL(std::ldexp(static_cast<double>(a.raw()), -Q::kFracBits), d, 0.0);
    // Back: exact for raws of up to 53 bits; otherwise the raw rounded to the double's 53 bits (or saturated).
    expect_raw("Q(to_double)", reference_from_double<Q>(d), Q(d).raw(), a.raw(), 0);
    if (magnitude_of(a.raw()) < (std::uint64_t{1} << 53)) CHECK(Q(d) == a);
  }
}

// The portable long division, usable in constant expressions.
constexpr std::uint64_t portable_quotient(std::uint64_t hi, std::uint64_t lo, std::uint64_t d) {
  std::uint64_t rem = 0;
  return fixed64_detail::udiv_portable(fixed64_detail::U128{hi, lo}, d, rem);
}
constexpr std::uint64_t portable_remainder(std::uint64_t hi, std::uint64_t lo, std::uint64_t d) {
  std::uint64_t rem = 0;
  fixed64_detail::udiv_portable(fixed64_detail::U128{hi, lo}, d, rem);
  return rem;
}

// Usable in constant expressions: tables and constants can be built at compile time.
static_assert(fixed64_detail::umul_portable(UINT64_MAX, UINT64_MAX).hi == UINT64_MAX - 1 &&
                  fixed64_detail::umul_portable(UINT64_MAX, UINT64_MAX).lo == 1,
              "portable 128-bit product");
static_assert(fixed64_detail::umul_portable(0x100000001u, 0xffffffffu).hi == 0 &&
                  fixed64_detail::umul_portable(0x100000001u, 0xffffffffu).lo == 0xffffffffffffffffu,
              "portable product, carries between the halves");
static_assert(portable_quotient(UINT64_MAX - 1, UINT64_MAX, UINT64_MAX) == UINT64_MAX &&
                  portable_remainder(UINT64_MAX - 1, UINT64_MAX, UINT64_MAX) == UINT64_MAX - 1,
              "portable long division, n.hi = d − 1");
static_assert(portable_quotient(0, 7, 2) == 3 && portable_remainder(0, 7, 2) == 1, "portable long division");
constexpr std::uint64_t normalised_quotient(std::uint64_t hi, std::uint64_t lo, std::uint64_t d) {
  std::uint64_t rem = 0;
  return fixed64_detail::udiv_normalised(fixed64_detail::U128{hi, lo}, d, rem);
}
static_assert(normalised_quotient(UINT64_MAX - 1, UINT64_MAX, UINT64_MAX) == UINT64_MAX &&
                  normalised_quotient(0, 7, 2) == 3 && normalised_quotient(0x80000000u, 0, 0x80000001u) != 0,
              "normalised long division");
static_assert(Q1_62(1.5).raw() == std::int64_t{3} << 61, "exact conversion");
static_assert(Q7_56(-0.5) + Q7_56(2) == Q7_56(1.5), "addition");
static_assert((Q1_62(0.5) * Q1_62(-0.5)).raw() == -(std::int64_t{1} << 60), "multiplication");
static_assert((Q7_56(1) / Q7_56(4)).raw() == std::int64_t{1} << 54, "division");
static_assert((Q63_0(5) / Q63_0(2)).raw() == 3 && (Q63_0(-5) / Q63_0(2)).raw() == -3, "ties away from zero");
static_assert(Q0_63(1.0) == Q0_63::highest() && Q7_56(100) + Q7_56(100) == Q7_56::highest(), "saturation");
static_assert(Q1_62(1) / Q1_62(0) == Q1_62::highest() && Q1_62(0) / Q1_62(0) == Q1_62(0), "division by zero");
static_assert(Q1_62::from_raw(INT64_MIN) == Q1_62::lowest() && abs(Q1_62(-1.25)) == Q1_62(1.25), "from_raw, abs");
static_assert(wide_mul<Q1_30>(Q7_24(0.5), Q1_62(0.5)) == Q1_30(0.25), "mixed-format product");
static_assert(wide_div<Q7_56>(Q1_30(0.75), Q7_24(0.25)) == Q7_56(3), "mixed-format quotient");
static_assert(wide_convert<Q7_24>(Q1_62(-1.25)) == Q7_24(-1.25) && wide_convert<Q7_24>(Q7_56(200)) == Q7_24::highest(),
              "conversion into the 32-bit format");

}  // namespace

TEST_GROUP(FixedPoint64){};

TEST(FixedPoint64, PortableProductEqualsTheNative128BitProduct) {
  const auto check = [](std::uint64_t a, std::uint64_t b) {
    const u128 native = static_cast<u128>(a) * b;
    const fixed64_detail::U128 portable = fixed64_detail::umul_portable(a, b);
    expect_word("umul_portable hi", static_cast<std::uint64_t>(native >> 64), portable.hi, a, b);
    expect_word("umul_portable lo", static_cast<std::uint64_t>(native), portable.lo, a, b);
    const fixed64_detail::U128 used = fixed64_detail::umul(a, b);
    expect_word("umul hi", portable.hi, used.hi, a, b);
    expect_word("umul lo", portable.lo, used.lo, a, b);
  };
  for (const std::uint64_t a : kEdgeWords)
    for (const std::uint64_t b : kEdgeWords) check(a, b);
  SplitMix64 rng{1};
  for (int i = 0; i < kRandomWords; ++i) {
    const std::uint64_t a = rng.word();
    check(a, rng.word());
  }
}

TEST(FixedPoint64, PortableDivisionEqualsTheNative128BitDivision) {
  const auto check = [](std::uint64_t hi, std::uint64_t lo, std::uint64_t d) {
    const u128 n = (static_cast<u128>(hi) << 64) | lo;  // hi < d: the quotient fits 64 bits
    std::uint64_t rem = 0;
    const std::uint64_t q = fixed64_detail::udiv_portable(fixed64_detail::U128{hi, lo}, d, rem);
    expect_word("udiv_portable quotient", static_cast<std::uint64_t>(n / d), q, hi, d);
    expect_word("udiv_portable remainder", static_cast<std::uint64_t>(n % d), rem, lo, d);
    std::uint64_t used_rem = 0;
    expect_word("udiv quotient", q, fixed64_detail::udiv(fixed64_detail::U128{hi, lo}, d, used_rem), hi, d);
    expect_word("udiv remainder", rem, used_rem, lo, d);
    // The division a 32-bit target uses (Cortex-M4): normalised 32-bit digits, 64/32 steps in 16-bit halves.
    std::uint64_t normalised_rem = 0;
    expect_word("udiv_normalised quotient", q,
                fixed64_detail::udiv_normalised(fixed64_detail::U128{hi, lo}, d, normalised_rem), hi, d);
    expect_word("udiv_normalised remainder", rem, normalised_rem, lo, d);
  };
  for (const std::uint64_t d : kEdgeWords) {
    if (d == 0) continue;
    for (const std::uint64_t lo : kEdgeWords) {
      check(0, lo, d);
      check(d - 1, lo, d);  // the largest quotients
      check(d / 2, lo, d);
      check(1 % d, lo, d);
    }
  }
  SplitMix64 rng{2};
  for (int i = 0; i < kRandomWords; ++i) {
    std::uint64_t d = rng.word();
    if (d == 0) d = 1;
    const std::uint64_t pick = rng.next() % 4u;
    const std::uint64_t hi = pick == 0 ? d - 1 : (pick == 1 ? 0 : rng.word() % d);
    check(hi, rng.word(), d);
  }
}

// The 64/32 step of the normalised division, alone: every width of divisor, the quotient at both ends.
TEST(FixedPoint64, DivluEqualsThe64BitDivision) {
  SplitMix64 rng{3};
  for (int i = 0; i < 200000; ++i) {
    const auto width = static_cast<int>(rng.next() % 32u) + 1;
    auto v = static_cast<std::uint32_t>(rng.next() & ((std::uint64_t{1} << width) - 1u));
    if (v == 0) v = 1;
    const std::uint64_t pick = rng.next() % 4u;
    const auto u1 = static_cast<std::uint32_t>(pick == 0 ? v - 1u : (pick == 1 ? 0u : rng.next() % v));
    const auto u0 = static_cast<std::uint32_t>(pick == 3 ? 0xffffffffu : rng.next());
    const std::uint64_t n = (std::uint64_t{u1} << 32) | u0;
    std::uint32_t r = 0;
    const std::uint32_t q = fixed64_detail::divlu(u1, u0, v, r);
    if (q != n / v || r != n % v) {
      FAIL(("divlu(" + std::to_string(u1) + ", " + std::to_string(u0) + ", " + std::to_string(v) + ")").c_str());
    }
  }
}

TEST(FixedPoint64, ConversionFromDoubleRoundsHalfwayCasesAwayFromZero) {
  LONGS_EQUAL(1, Q63_0(0.5).raw());
  LONGS_EQUAL(-1, Q63_0(-0.5).raw());
  LONGS_EQUAL(2, Q63_0(1.5).raw());
  LONGS_EQUAL(-2, Q63_0(-1.5).raw());
  LONGS_EQUAL(3, Q63_0(2.5).raw());  // away from zero, not to even
  LONGS_EQUAL(-3, Q63_0(-2.5).raw());
  const double below_half = std::nextafter(0.5, 0.0);
  LONGS_EQUAL(0, Q63_0(below_half).raw());
  LONGS_EQUAL(0, Q63_0(-below_half).raw());
  LONGS_EQUAL(1, Q63_0(std::nextafter(0.5, 1.0)).raw());
  LONGS_EQUAL(std::int64_t{1} << 62, Q63_0(0x1p62).raw());
  // Halfway between two Q1.62 steps, both signs, at several magnitudes.
  for (const std::int64_t k : {std::int64_t{0}, std::int64_t{1}, std::int64_t{7}, std::int64_t{1} << 20,
                               (std::int64_t{1} << 52) - 1}) {
    const double half_step_above = std::ldexp(static_cast<double>(k) + 0.5, -62);
    LONGS_EQUAL(k + 1, Q1_62(half_step_above).raw());
    LONGS_EQUAL(-(k + 1), Q1_62(-half_step_above).raw());
  }
  for (const std::int64_t k : {std::int64_t{0}, std::int64_t{1}, std::int64_t{7}, std::int64_t{1} << 20}) {
    LONGS_EQUAL(k, Q1_62(std::ldexp(static_cast<double>(k) + 0.49, -62)).raw());
    LONGS_EQUAL(-k, Q1_62(-std::ldexp(static_cast<double>(k) + 0.49, -62)).raw());
  }
  LONGS_EQUAL(std::int64_t{1} << 62, Q0_63(0.5).raw());
  LONGS_EQUAL(1, Q0_63(0x1p-64).raw());  // half a step
  LONGS_EQUAL(-1, Q0_63(-0x1p-64).raw());
  LONGS_EQUAL(0, Q0_63(std::ldexp(0.99, -64)).raw());
  LONGS_EQUAL(std::int64_t{1} << 62, Qm12_75(0x1p-13).raw());
  LONGS_EQUAL(1, Qm12_75(0x1p-76).raw());
  LONGS_EQUAL(-1, Qm12_75(-0x1p-76).raw());
  LONGS_EQUAL(3, Qm60_123(std::ldexp(2.5, -123)).raw());
  LONGS_EQUAL(-3, Qm60_123(std::ldexp(-2.5, -123)).raw());
  check_double_conversion_against_reference<Q1_62>(101);
  check_double_conversion_against_reference<Q7_56>(102);
  check_double_conversion_against_reference<Q0_63>(103);
  check_double_conversion_against_reference<Q63_0>(104);
  check_double_conversion_against_reference<Q31_32>(105);
  check_double_conversion_against_reference<Qm12_75>(106);
  check_double_conversion_against_reference<Qm60_123>(107);
}

TEST(FixedPoint64, ConversionFromDoubleSaturatesAndMapsNanToZero) {
  CHECK(Q7_56(128.0) == Q7_56::highest());
  CHECK(Q7_56(1e300) == Q7_56::highest());
  CHECK(Q7_56(std::numeric_limits<double>::infinity()) == Q7_56::highest());
  CHECK(Q7_56(-128.0) == Q7_56::lowest());
  CHECK(Q7_56(-1e300) == Q7_56::lowest());
  CHECK(Q7_56(-std::numeric_limits<double>::infinity()) == Q7_56::lowest());
  LONGS_EQUAL(0, Q7_56(std::numeric_limits<double>::quiet_NaN()).raw());
  LONGS_EQUAL(0, Q7_56(-std::numeric_limits<double>::quiet_NaN()).raw());
  LONGS_EQUAL(0, Qm12_75(std::numeric_limits<double>::quiet_NaN()).raw());
  // The last doubles before the ends (2^63 − 2^10 raw), and the ends themselves.
  LONGS_EQUAL(kMax64 - 1023, Q63_0(std::nextafter(0x1p63, 0.0)).raw());
  LONGS_EQUAL(-(kMax64 - 1023), Q63_0(-std::nextafter(0x1p63, 0.0)).raw());
  CHECK(Q63_0(0x1p63) == Q63_0::highest());
  CHECK(Q63_0(-0x1p63) == Q63_0::lowest());
  LONGS_EQUAL(kMax64 - 1023, Q1_62(std::nextafter(2.0, 0.0)).raw());
  CHECK(Q1_62(2.0) == Q1_62::highest());
  CHECK(Q1_62(-2.0) == Q1_62::lowest());
  CHECK(Q0_63(1.0) == Q0_63::highest());
  CHECK(Q0_63(-1.0) == Q0_63::lowest());  // −1 itself is INT64_MIN raw, outside the symmetric range
  CHECK(Qm12_75(0x1p-12) == Qm12_75::highest());
  CHECK(Qm12_75(-1.0) == Qm12_75::lowest());
  CHECK(Qm60_123(1.0) == Qm60_123::highest());
  CHECK(Q7_56(-128.0).saturated() && Q7_56(128.0).saturated() && !Q7_56(127.0).saturated());
}

TEST(FixedPoint64, ConversionFromIntIsExactOrSaturates) {
  LONGS_EQUAL(std::int64_t{127} << 56, Q7_56(127).raw());
  LONGS_EQUAL(-(std::int64_t{127} << 56), Q7_56(-127).raw());
  CHECK(Q7_56(128) == Q7_56::highest());
  CHECK(Q7_56(-128) == Q7_56::lowest());
  LONGS_EQUAL(std::int64_t{1} << 62, Q1_62(1).raw());
  LONGS_EQUAL(-(std::int64_t{1} << 62), Q1_62(-1).raw());
  CHECK(Q1_62(2) == Q1_62::highest());
  CHECK(Q1_62(-2) == Q1_62::lowest());
  CHECK(Q0_63(1) == Q0_63::highest());
  CHECK(Q0_63(-1) == Q0_63::lowest());
  LONGS_EQUAL(0, Q0_63(0).raw());
  CHECK(Qm12_75(1) == Qm12_75::highest());
  CHECK(Qm12_75(-1) == Qm12_75::lowest());
  LONGS_EQUAL(0, Qm12_75(0).raw());
  LONGS_EQUAL(kMax64, Q63_0(INT64_MAX).raw());
  CHECK(Q63_0(INT64_MIN) == Q63_0::lowest());
  CHECK(Q1_62(INT64_MIN) == Q1_62::lowest());
  CHECK(Q63_0(UINT64_MAX) == Q63_0::highest());  // unsigned beyond int64
  CHECK(Q63_0(std::uint64_t{1} << 63) == Q63_0::highest());
  LONGS_EQUAL(-5, Q63_0(static_cast<short>(-5)).raw());
  LONGS_EQUAL(std::int64_t{200} << 32, Q31_32(static_cast<unsigned char>(200)).raw());
  check_integer_conversion_against_reference<Q1_62>(111);
  check_integer_conversion_against_reference<Q7_56>(112);
  check_integer_conversion_against_reference<Q63_0>(113);
  check_integer_conversion_against_reference<Q31_32>(114);
  check_integer_conversion_against_reference<Qm12_75>(115);
}

TEST(FixedPoint64, ConversionToDoubleMatchesTheRawAndRoundTrips) {
  check_to_double<Q1_62>(121);
  check_to_double<Q7_56>(122);
  check_to_double<Q0_63>(123);
  check_to_double<Q63_0>(124);
  check_to_double<Qm12_75>(125);
  check_to_double<Qm60_123>(126);
  DOUBLES_EQUAL(0x1p-62, Q1_62::from_raw(1).to_double(), 0.0);
  DOUBLES_EQUAL(0x1p-75, Qm12_75::from_raw(1).to_double(), 0.0);
  DOUBLES_EQUAL(2.0, Q1_62::highest().to_double(), 0.0);  // 2 − 2^−62 rounds to 2 in a double
  DOUBLES_EQUAL(-1.0, Q0_63::lowest().to_double(), 0.0);
  DOUBLES_EQUAL(-1.125, Q1_62(-1.125).to_double(), 0.0);
}

TEST(FixedPoint64, FromRawMapsInt64MinToLowest) {
  LONGS_EQUAL(-kMax64, Q1_62::from_raw(INT64_MIN).raw());
  LONGS_EQUAL(-kMax64, Qm12_75::from_raw(INT64_MIN).raw());
  LONGS_EQUAL(kMax64, (-Q1_62::from_raw(INT64_MIN)).raw());
  LONGS_EQUAL(kMax64, abs(Q1_62::from_raw(INT64_MIN)).raw());
  LONGS_EQUAL(-kMax64 + 1, Q1_62::from_raw(-kMax64 + 1).raw());
  CHECK(Q1_62::from_raw(INT64_MIN).saturated());
  CHECK(Q1_62::from_raw(INT64_MIN) * Q1_62(1) == Q1_62::lowest());
  CHECK(Q1_62::from_raw(INT64_MIN) / Q1_62(-1) == Q1_62::highest());
}

TEST(FixedPoint64, AdditionAndSubtractionAreExactAndSaturateAtBothEnds) {
  const Q1_62 step = Q1_62::from_raw(1);
  CHECK(Q1_62(0.25) + Q1_62(-1.5) == Q1_62(-1.25));
  CHECK(Q1_62(0.25) - Q1_62(-1.5) == Q1_62(1.75));
  CHECK(Q1_62::highest() + step == Q1_62::highest());
  CHECK(Q1_62::lowest() - step == Q1_62::lowest());
  CHECK(Q1_62::highest() + Q1_62::highest() == Q1_62::highest());
  CHECK(Q1_62::lowest() + Q1_62::lowest() == Q1_62::lowest());
  CHECK(Q1_62::highest() - Q1_62::lowest() == Q1_62::highest());
  CHECK(Q1_62::lowest() - Q1_62::highest() == Q1_62::lowest());
  CHECK(Q1_62::highest() + Q1_62::lowest() == Q1_62(0));
  // One past the low end without int64 overflow (INT64_MIN raw): still the symmetric lowest.
  CHECK(Q1_62::lowest() + (-step) == Q1_62::lowest());
  CHECK(Q1_62::lowest() - step == Q1_62::lowest());
  LONGS_EQUAL(-kMax64 + 1, (Q1_62::lowest() + step).raw());
  CHECK(Q1_62(1.5) + Q1_62(1.5) - Q1_62(1.5) == Q1_62::highest() - Q1_62(1.5));  // saturation is not undone
  CHECK(-Q1_62::highest() == Q1_62::lowest());
  CHECK(-Q1_62::lowest() == Q1_62::highest());
  CHECK(-Q1_62(0) == Q1_62(0));
}

TEST(FixedPoint64, MultiplicationRoundsOnceHalfwayAwayFromZero) {
  CHECK(Q1_62(1.5) * Q1_62(-0.75) == Q1_62(-1.125));
  CHECK(Q7_56(-3.5) * Q7_56(-2.25) == Q7_56(7.875));
  CHECK(Q1_62(0) * Q1_62::highest() == Q1_62(0));
  // Half a step: ties away from zero, with every sign combination.
  const Q1_62 half(0.5);
  const Q1_62 step = Q1_62::from_raw(1);
  LONGS_EQUAL(1, (half * step).raw());
  LONGS_EQUAL(-1, (-half * step).raw());
  LONGS_EQUAL(-1, (half * -step).raw());
  LONGS_EQUAL(1, (-half * -step).raw());
  LONGS_EQUAL(2, (Q1_62(1.5) * step).raw());  // 1.5 steps → 2
  LONGS_EQUAL(-2, (Q1_62(-1.5) * step).raw());
  LONGS_EQUAL(3, (Q1_62(2.5 / 4) * Q1_62::from_raw(4)).raw());  // 2.5 steps → 3 (not to even)
  LONGS_EQUAL(0, (Q1_62(0.4999999) * step).raw());
  LONGS_EQUAL(0, (Q1_62(-0.4999999) * step).raw());
  // The tie decided by the low bits of the 126-bit product only: 0.5 + 2^−62 steps rounds up, 0.5 − 2^−62 down.
  LONGS_EQUAL(1, (Q1_62::from_raw((std::int64_t{1} << 61) + 1) * step).raw());
  LONGS_EQUAL(0, (Q1_62::from_raw((std::int64_t{1} << 61) - 1) * step).raw());
  LONGS_EQUAL(-1, (Q1_62::from_raw(-(std::int64_t{1} << 61)) * step).raw());
  LONGS_EQUAL(0, (Q1_62::from_raw(-(std::int64_t{1} << 61) + 1) * step).raw());
  LONGS_EQUAL(1, (Q0_63(0.5) * Q0_63::from_raw(1)).raw());
  LONGS_EQUAL(-1, (Q0_63(-0.5) * Q0_63::from_raw(1)).raw());
  // Q−12.75: raw products of 2^74 are half a step (shift 75).
  const Qm12_75 r37 = Qm12_75::from_raw(std::int64_t{1} << 37);
  LONGS_EQUAL(1, (r37 * r37).raw());
  LONGS_EQUAL(-1, (-r37 * r37).raw());
  LONGS_EQUAL(3, (Qm12_75::from_raw(std::int64_t{5} << 37) * r37).raw());  // 2.5 → 3
  LONGS_EQUAL(-3, (Qm12_75::from_raw(std::int64_t{5} << 37) * -r37).raw());
  LONGS_EQUAL(std::int64_t{1} << 49, (Qm12_75(0x1p-13) * Qm12_75(0x1p-13)).raw());  // 2^−26
  LONGS_EQUAL(std::int64_t{1} << 51, (Qm12_75::highest() * Qm12_75::highest()).raw());
  LONGS_EQUAL(kMax64 - 1, (Q0_63::highest() * Q0_63::highest()).raw());  // (1 − 2^−63)² rounds below 1
  // Saturation at both ends.
  CHECK(Q7_56(12) * Q7_56(11) == Q7_56::highest());
  CHECK(Q7_56(-12) * Q7_56(11) == Q7_56::lowest());
  CHECK(Q7_56(12) * Q7_56(-11) == Q7_56::lowest());
  CHECK(Q7_56(-12) * Q7_56(-11) == Q7_56::highest());
  CHECK(Q1_62::highest() * Q1_62::highest() == Q1_62::highest());
  CHECK(Q1_62::lowest() * Q1_62::highest() == Q1_62::lowest());
  CHECK(Q1_62::lowest() * Q1_62::lowest() == Q1_62::highest());
  CHECK(Q63_0(std::int64_t{1} << 32) * Q63_0(std::int64_t{1} << 31) == Q63_0::highest());  // exactly 2^63
  CHECK(Q63_0(-(std::int64_t{1} << 32)) * Q63_0(std::int64_t{1} << 31) == Q63_0::lowest());
  LONGS_EQUAL(9223372030926249001, (Q63_0(3037000499) * Q63_0(3037000499)).raw());  // the largest square
  CHECK(Q63_0(3037000500) * Q63_0(3037000500) == Q63_0::highest());
  CHECK(Q63_0::highest() * Q63_0::highest() == Q63_0::highest());
}

TEST(FixedPoint64, DivisionRoundsOnceAndSaturatesIncludingDivisionByZero) {
  CHECK(Q1_62(0.25) / Q1_62(-0.5) == Q1_62(-0.5));
  CHECK(Q7_56(-7.5) / Q7_56(2.5) == Q7_56(-3));
  CHECK(Q1_62(0.75) / Q1_62(0.5) == Q1_62(1.5));
  LONGS_EQUAL(1537228672809129301, (Q1_62(0.25) / Q1_62(0.75)).raw());  // 2^62/3 = …301.33
  LONGS_EQUAL(-1537228672809129301, (Q1_62(-0.25) / Q1_62(0.75)).raw());
  LONGS_EQUAL(24019198012642645, (Q7_56(1) / Q7_56(3)).raw());  // 2^56/3 = …645.33
  LONGS_EQUAL(48038396025285291, (Q7_56(2) / Q7_56(3)).raw());  // …290.67
  LONGS_EQUAL(-48038396025285291, (Q7_56(-2) / Q7_56(3)).raw());
  LONGS_EQUAL(-48038396025285291, (Q7_56(2) / Q7_56(-3)).raw());
  LONGS_EQUAL(3074457345618258603, (Q0_63::from_raw(1) / Q0_63::from_raw(3)).raw());  // 2^63/3 = …602.67
  LONGS_EQUAL(std::int64_t{1} << 62, (Q0_63::from_raw(1) / Q0_63::from_raw(2)).raw());
  // Halfway quotients: away from zero, not to even.
  LONGS_EQUAL(1, (Q63_0(1) / Q63_0(2)).raw());
  LONGS_EQUAL(2, (Q63_0(3) / Q63_0(2)).raw());
  LONGS_EQUAL(3, (Q63_0(5) / Q63_0(2)).raw());
  LONGS_EQUAL(-3, (Q63_0(-5) / Q63_0(2)).raw());
  LONGS_EQUAL(-3, (Q63_0(5) / Q63_0(-2)).raw());
  LONGS_EQUAL(3, (Q63_0(-5) / Q63_0(-2)).raw());
  LONGS_EQUAL(std::int64_t{1} << 62, (Q63_0::highest() / Q63_0(2)).raw());  // 2^62 − 0.5
  LONGS_EQUAL(-(std::int64_t{1} << 62), (Q63_0::lowest() / Q63_0(2)).raw());
  LONGS_EQUAL(1, (Q7_56::from_raw(1) / Q7_56(2)).raw());  // exactly half a step
  LONGS_EQUAL(-1, (Q7_56::from_raw(-1) / Q7_56(2)).raw());
  LONGS_EQUAL(3, (Q7_56::from_raw(5) / Q7_56(2)).raw());  // 2.5 → 3
  LONGS_EQUAL(-3, (Q7_56::from_raw(5) / Q7_56(-2)).raw());
  LONGS_EQUAL(1, (Q1_62::from_raw(1) / Q1_62::highest()).raw());  // just over half a step
  LONGS_EQUAL(-1, (Q1_62::from_raw(1) / Q1_62::lowest()).raw());
  // Saturation.
  CHECK(Q7_56(100) / Q7_56(0.5) == Q7_56::highest());
  CHECK(Q7_56(-100) / Q7_56(0.5) == Q7_56::lowest());
  CHECK(Q7_56(100) / Q7_56(-0.5) == Q7_56::lowest());
  CHECK(Q1_62(1) / Q1_62(0.5) == Q1_62::highest());  // exactly 2: just out of range
  CHECK(Q1_62(-1) / Q1_62(0.5) == Q1_62::lowest());
  CHECK(Q1_62(1) / Q1_62::from_raw(1) == Q1_62::highest());  // quotient ≥ 2^64
  CHECK(Q1_62::lowest() / Q1_62::from_raw(1) == Q1_62::lowest());
  CHECK(Q0_63::highest() / Q0_63::highest() == Q0_63::highest());  // 1 is beyond the range
  CHECK(Q0_63::lowest() / Q0_63::highest() == Q0_63::lowest());
  CHECK(Q0_63::highest() / Q0_63::from_raw(1) == Q0_63::highest());
  // Division by zero: saturates by the sign of the dividend; 0/0 = 0.
  CHECK(Q1_62(1) / Q1_62(0) == Q1_62::highest());
  CHECK(Q1_62(-1) / Q1_62(0) == Q1_62::lowest());
  CHECK(Q1_62::from_raw(1) / Q1_62(0) == Q1_62::highest());
  CHECK(Q1_62::from_raw(-1) / Q1_62(0) == Q1_62::lowest());
  CHECK(Q1_62(0) / Q1_62(0) == Q1_62(0));
  CHECK(Q0_63(-0.25) / Q0_63(0) == Q0_63::lowest());
  CHECK(Q63_0(-5) / Q63_0(0) == Q63_0::lowest());
  CHECK(Q63_0(0) / Q63_0(0) == Q63_0(0));
  CHECK(Q1_62(0) / Q1_62(-0.5) == Q1_62(0));
}

TEST(FixedPoint64, SameFormatOperatorsMatchTheExactReference) {
  check_same_format_against_reference<Q1_62>(11);
  check_same_format_against_reference<Q7_56>(12);
  check_same_format_against_reference<Q0_63>(13);
  check_same_format_against_reference<Q3_60>(14);
  check_same_format_against_reference<Q31_32>(15);
  check_same_format_against_reference<Q63_0>(16);
  check_same_format_against_reference<Qm12_75>(17);   // no operator/ (75 fraction bits)
  check_same_format_against_reference<Qm60_123>(18);  // shift 123
}

TEST(FixedPoint64, WideOperationsMatchTheExactReference) {
  check_mixed_against_reference<Q7_24, Q1_62, Q7_56>(21);      // shift 94, into 32 bits
  check_mixed_against_reference<Q1_62, Q7_24, Q1_30>(22);      // shift −8: two 32-bit operands, exact
  check_mixed_against_reference<Q1_30, Q1_62, Q1_30>(23);      // shift 62
  check_mixed_against_reference<Q7_56, Q7_24, Q7_56>(24);      // shift 24
  check_mixed_against_reference<Q1_62, Qm12_75, Q7_56>(25);    // shift 69 (the engine's H²/4 · a)
  check_mixed_against_reference<Qm12_75, Q0_63, Q0_63>(26);    // shift 51
  check_mixed_against_reference<Q1_30, Qm12_75, Qm12_75>(27);  // shift 120
  check_mixed_against_reference<Q7_24, Qm12_75, Qm12_75>(28);  // shift 126
  check_mixed_against_reference<Q63_0, Qm60_123, Qm60_123>(29);  // shift 246: always 0
  check_mixed_against_reference<Qm12_75, Q63_0, Q7_24>(30);    // shift −51
  check_mixed_against_reference<Qm60_123, Q63_0, Q1_30>(31);   // shift −93
  check_mixed_against_reference<Q1_30, Q7_24, Q7_24>(32);      // 32-bit in and out, shift 18
  check_mixed_div_against_reference<Q1_62, Q1_62, Q1_62>(41);    // widen 62
  check_mixed_div_against_reference<Q7_24, Q1_62, Q7_56>(42);    // widen 18, into 32 bits
  check_mixed_div_against_reference<Q1_30, Q7_24, Q1_30>(43);    // widen 36: 32-bit operands
  check_mixed_div_against_reference<Q7_56, Q7_24, Q1_30>(44);    // widen 62
  check_mixed_div_against_reference<Q1_62, Qm12_75, Q1_62>(45);  // widen 49
  check_mixed_div_against_reference<Qm12_75, Qm12_75, Q7_56>(46);  // widen 56
  check_mixed_div_against_reference<Q1_30, Q0_63, Q1_62>(47);    // widen 29
  check_mixed_div_against_reference<Q63_0, Q7_56, Q7_56>(48);    // widen 0
  check_mixed_div_against_reference<Q0_63, Q0_63, Q0_63>(49);    // widen 63: the largest
  check_mixed_div_against_reference<Qm60_123, Qm60_123, Q63_0>(50);  // widen 0
}

TEST(FixedPoint64, WideOperationsRoundOnce) {
  // a · b = 2^99 − δ raw with δ ≈ 2^49: half a Q7.24 step less about 2^−51 of a step. Rounding the product to Q1.62 first
  // would give exactly half a step (2^37 raw) and then 1; the single rounding gives 0.
  const Q1_62 a = Q1_62::from_raw(1125899906854969);  // 2^50 + 12345
  const Q1_62 b = Q1_62::from_raw(562949953415139);   // ⌊(2^99 − 1)/a⌋
  LONGS_EQUAL(std::int64_t{1} << 37, (a * b).raw());
  LONGS_EQUAL(1, wide_convert<Q7_24>(a * b).raw());
  LONGS_EQUAL(0, wide_mul<Q7_24>(a, b).raw());
  LONGS_EQUAL(0, wide_mul<Q7_24>(-a, b).raw());
  // Mixed 32/64-bit products and quotients with exact results.
  CHECK(wide_mul<Q1_62>(Q7_24(-1.5), Q1_30(0.75)) == Q1_62(-1.125));
  CHECK(wide_mul<Q7_24>(Q1_62(0.5), Q7_56(-6.25)) == Q7_24(-3.125));
  CHECK(wide_div<Q1_62>(Q1_30(0.75), Q7_24(2)) == Q1_62(0.375));
  CHECK(wide_div<Q7_24>(Q1_62(-1.5), Q7_56(0.25)) == Q7_24(-6));
  LONGS_EQUAL(1537228672809129301, wide_div<Q1_62>(Q1_62(1), Q7_56(3)).raw());  // 2^62/3 rounded once
  LONGS_EQUAL(357913941, wide_div<Q1_30>(Q1_62(1), Q7_56(3)).raw());  // 2^30/3 = …941.33
  LONGS_EQUAL(715827883, wide_div<Q1_30>(Q1_62(-1), Q7_56(-1.5)).raw());  // 2^31/3 = …882.67
  // Ties: Q1.62 raw 2^37 is half a Q7.24 step.
  LONGS_EQUAL(1, wide_convert<Q7_24>(Q1_62::from_raw(std::int64_t{1} << 37)).raw());
  LONGS_EQUAL(-1, wide_convert<Q7_24>(Q1_62::from_raw(-(std::int64_t{1} << 37))).raw());
  LONGS_EQUAL(0, wide_convert<Q7_24>(Q1_62::from_raw((std::int64_t{1} << 37) - 1)).raw());
  LONGS_EQUAL(3, wide_convert<Q7_24>(Q1_62::from_raw(std::int64_t{5} << 37)).raw());  // 2.5 → 3
  // Into more fraction bits: exact.
  LONGS_EQUAL(-(std::int64_t{INT32_MAX} << 32), wide_convert<Q1_62>(Q1_30::lowest()).raw());
  LONGS_EQUAL(std::int64_t{123456789} << 32, wide_convert<Q7_56>(Q7_24::from_raw(123456789)).raw());
  CHECK(wide_convert<Q0_63>(Q63_0(1)) == Q0_63::highest());
  CHECK(wide_convert<Qm12_75>(Q1_62(-0.5)) == Qm12_75::lowest());
}

TEST(FixedPoint64, WideOperationsSaturateIntoThe32BitFormat) {
  CHECK(wide_convert<Q7_24>(Q7_56::highest()) == Q7_24::highest());  // 128 − 2^−56 rounds to 128
  CHECK(wide_convert<Q7_24>(Q7_56::lowest()) == Q7_24::lowest());
  CHECK(wide_convert<Q1_30>(Q7_56(5)) == Q1_30::highest());
  CHECK(wide_convert<Q1_30>(Q7_56(-5)) == Q1_30::lowest());
  CHECK(wide_convert<Q1_30>(Q63_0::highest()) == Q1_30::highest());
  LONGS_EQUAL(INT32_MAX, wide_convert<Q1_30>(Q1_62(2.0 - 0x1p-30)).raw());  // the largest value, exactly
  LONGS_EQUAL(INT32_MAX, wide_convert<Q1_30>(Q1_62(2.0 - 0x1p-31)).raw());  // rounds up to 2: clamped
  CHECK(wide_mul<Q1_30>(Q1_62(1.5), Q7_24(2)) == Q1_30::highest());
  CHECK(wide_mul<Q1_30>(Q1_62(-1.5), Q7_24(2)) == Q1_30::lowest());
  CHECK(wide_mul<Q1_30>(Q1_62(1.5), Q7_24(-2)) == Q1_30::lowest());
  CHECK(wide_mul<Q7_24>(Q63_0::highest(), Q63_0::highest()) == Q7_24::highest());
  CHECK(wide_mul<Q7_24>(Q63_0::lowest(), Q63_0::highest()) == Q7_24::lowest());
  CHECK(wide_div<Q7_24>(Q1_62(1), Q7_56(0.0078125)) == Q7_24::highest());  // exactly 128
  CHECK(wide_div<Q7_24>(Q1_62(-1), Q7_56(0.0078125)) == Q7_24::lowest());
  CHECK(wide_div<Q7_24>(Q1_62(1), Q7_56(0)) == Q7_24::highest());
  CHECK(wide_div<Q7_24>(Q1_62(-1), Q7_56(0)) == Q7_24::lowest());
  CHECK(wide_div<Q7_24>(Q1_62(0), Q7_56(0)) == Q7_24(0));
  CHECK(wide_div<Q1_30>(Q7_24(0), Q1_30(0)) == Q1_30(0));
  CHECK(wide_div<Q1_30>(Q7_24(-0.5), Q1_30(0)) == Q1_30::lowest());
}

TEST(FixedPoint64, AbsAndComparisons) {
  CHECK(abs(Q1_62(-1.5)) == Q1_62(1.5));
  CHECK(abs(Q1_62(1.5)) == Q1_62(1.5));
  CHECK(abs(Q1_62::lowest()) == Q1_62::highest());
  CHECK(Q1_62(-1) < Q1_62(1));
  CHECK(Q1_62(1) <= Q1_62(1));
  CHECK(Q1_62(1.5) > Q1_62(1));
  CHECK(Q1_62(1.5) >= Q1_62(1.5));
  CHECK(Q1_62(1.5) != Q1_62(1));
  CHECK(Q1_62::lowest() < -Q1_62::from_raw(1));
  CHECK(Q1_62() == Q1_62(0));
}

}  // namespace unity_test_fixed_point64
