// Constant-time fixed-point natural logarithm and inverse hyperbolic tangent, for the alarm's predicted time to
// instability t = atanh(z)/ω evaluated on the monitor without floating point.
//
// Method (both functions share one kernel, fixed_math_detail::log_q40):
//   1. Normalise with count-leading-zeros (one CLZ instruction on Cortex-M4 and x86): u = m · 2^k with the
//      mantissa m in [1/√2, √2), chosen branch-free by one comparison against √2.
//   2. ln m = 2·atanh(s), s = (m − 1)/(m + 1) = t/(2 + t) with t = m − 1, so |s| ≤ 3 − 2√2 < 0.1716.
//      The division is a reciprocal by Newton–Raphson: a minimax linear first guess (relative error ≤ 0.0150)
//      and three iterations (errors 2.2e-4, 5e-8, then below the Q.31 rounding), so no divide instruction and
//      no data-dependent loop.
//   3. 2·atanh(s) = 2(s + s³/3 + s⁵/5 + s⁷/7 + s⁹/9): the first omitted term is 2s¹¹/11 < 7e-10.
//   4. ln u = ln m + k·ln 2 in Q.40 (int64), rounded once into the output format.
// Every operand of a product is an int32 in Q.31, so each product is one 32×32→64 multiply (SMULL on
// Cortex-M4); the only 64-bit multiply is k·ln 2.
//
// Accuracy: the kernel's error is at most 2.1e-9 (measured over every third Q.30 mantissa in [1, 2) against
// long double; stated bound 5e-9), so the result is the exact value rounded once into Out plus that: for
// Out = Q7.24 at most 3.1e-8 from std::log over (2^−30, 2^7) and from std::atanh over [0, 1 − 2^−20] (the
// alarm's target is 2e-7); tests/core/test_fixed_math.cpp checks half a step of Out + 5e-9.
//
// Constant time: the same instructions run for every valid input (about 95 Thumb-2 instructions per kernel
// at -Os, no calls); the only branches reject invalid input (u ≤ 0, |z| ≥ 1) and pick the saturated result.
// For t = atanh(z)/ω multiply by 1/ω prepared at initialisation (fixed_mul) rather than dividing: Fixed's
// division is a 64-bit division, a library call on Cortex-M4 (__aeabi_uldivmod) whose time depends on the data.
#pragma once

#include <cstdint>

#include "rockwatch/core/fixed_point.hpp"

namespace rockwatch::core {

namespace fixed_math_detail {

// Q.31 constants: value · 2^31 rounded to nearest.
inline constexpr std::int32_t kOneThirdQ31 = 715827883;   // 1/3
inline constexpr std::int32_t kOneFifthQ31 = 429496730;   // 1/5
inline constexpr std::int32_t kOneSeventhQ31 = 306783378;  // 1/7
inline constexpr std::int32_t kOneNinthQ31 = 238609294;   // 1/9
// Newton–Raphson first guess for 1/(2 + t), t ∈ [1/√2 − 1, √2 − 1]: e0 = kRecipA − kRecipB·t, the minimax
// linear approximation of 1/D on D ∈ [1 + 1/√2, 1 + √2] in relative error (equal error 0.01494 at both ends
// and in between): kRecipB = 8/(P(P + 4)), kRecipA = kRecipB·(P − 2), P = 2 + 3/√2.
inline constexpr std::int32_t kRecipAQ31 = 1088837564;  // 0.50702950...
inline constexpr std::int32_t kRecipBQ31 = 513282950;   // 0.23901600...
// √2 in Q.30, rounded up: a mantissa at or above it is halved.
inline constexpr std::uint32_t kSqrt2Q30 = 1518500250u;
// ln 2 · 2^40 rounded to nearest (error < 5e-13 per unit of k; |k| ≤ 61).
inline constexpr std::int64_t kLn2Q40 = 762123384786;
inline constexpr int kLogFracBits = 40;

// a · b in Q.31, rounded to nearest (ties up: internal, the bias is far below the kernel's error).
// Scaling and overflow: |a|, |b| < 2^31, so the product is below 2^62 in magnitude; the offset 2^62 makes it
// non-negative before the shift (no shift of a negative number), and the result fits int32 whenever |a·b| < 1,
// which holds for every operand pair the kernel forms (|values| < 0.6).
constexpr std::int32_t mul_q31(std::int32_t a, std::int32_t b) {
  constexpr std::int64_t kOffset = std::int64_t{1} << 62;
  const std::int64_t biased = std::int64_t{a} * b + kOffset + (std::int64_t{1} << 30);
  return static_cast<std::int32_t>((biased >> 31) - (std::int64_t{1} << 31));
}

// ln(raw · 2^−frac_bits) in Q.40 for raw > 0.
// Scaling and overflow: the mantissa t = m − 1 is exact in Q.31 (|t| < 0.415); s, s², the series and the
// reciprocal stay in Q.31 below 0.6; the result |ln u| ≤ 61·ln 2 < 43 (frac_bits ≤ 61) needs 46 bits of the int64.
// Error: below 5e-9, measured 2.1e-9 (rounding of 14 Q.31 products; series truncation < 7e-10; ln 2 < 2e-11).
constexpr std::int64_t log_q40(std::uint32_t raw, int frac_bits) {
  // 1. u = x·2^(p−30), x in [2^30, 2^31) the Q.30 mantissa m ∈ [1, 2); p the bit position of the leading one.
  const int leading_zeros = __builtin_clz(raw);  // raw > 0: defined; 1..31 for an int32 value
  const int p = 31 - leading_zeros;
  const std::uint32_t x = raw << (leading_zeros - 1);
  // Fold m ≥ √2 to m/2 ∈ [1/√2, 1) so |s| is smallest; as Q.31 that is the same bits x.
  const int halve = x >= kSqrt2Q30 ? 1 : 0;
  // t = m − 1 in Q.31: 2x − 2^31 (m in Q.30) or x − 2^31 (m/2 in Q.31); exact.
  const auto t = static_cast<std::int32_t>((std::int64_t{x} << (1 - halve)) - (std::int64_t{1} << 31));

  // 2. e ≈ 1/(2 + t) ∈ [0.414, 0.586]: linear guess, then e ← e + e·(1 − (2 + t)·e) three times.
  std::int32_t e = kRecipAQ31 - mul_q31(kRecipBQ31, t);
  for (int i = 0; i < 3; ++i) {  // a fixed count, whatever the data
    const std::int64_t residual = (std::int64_t{1} << 31) - 2 * std::int64_t{e} - mul_q31(t, e);
    e += mul_q31(e, static_cast<std::int32_t>(residual));  // |residual| < 0.0150 in Q.31
  }
  const std::int32_t s = mul_q31(t, e);  // (m − 1)/(m + 1), |s| < 0.1716

  // 3. ln m / 2 = atanh(s) = s + s·w·(1/3 + w(1/5 + w(1/7 + w/9))), w = s².
  const std::int32_t w = mul_q31(s, s);
  std::int32_t poly = kOneSeventhQ31 + mul_q31(w, kOneNinthQ31);
  poly = kOneFifthQ31 + mul_q31(w, poly);
  poly = kOneThirdQ31 + mul_q31(w, poly);
  const std::int32_t half_ln_m = s + mul_q31(mul_q31(s, w), poly);

  // 4. ln u = 2·half_ln_m + k·ln 2, k = p + halve − frac_bits ∈ [−61, 31]. Q.31·2 → Q.40 is a factor 2^10.
  const int k = p + halve - frac_bits;
  return std::int64_t{half_ln_m} * (std::int64_t{1} << (kLogFracBits - 31 + 1)) + k * kLn2Q40;
}

}  // namespace fixed_math_detail

// ln(u) in the format Out, for u > 0; u ≤ 0 (no logarithm) gives Out::lowest().
// Scaling and overflow: any Q format in; |ln u| < 21.5 for inputs with at most 31 fraction bits (< 43 with up
// to 61), so Out needs 5 integer bits (6), else the result saturates; one rounding (to nearest, ties away) from
// the Q.40 kernel value.
// Accuracy: within Out's half resolution + 5e-9 of ln u (Q7.24: 3.5e-8). Cost: one CLZ, 14 32×32→64 multiplies.
template <typename Out, int I, int F>
constexpr Out fixed_log(Fixed<I, F> u) {
  static_assert(is_fixed<Out>::value, "fixed_log: Out must be a Fixed format");
  if (u.raw() <= 0) return Out::lowest();
  const std::int64_t ln_q40 = fixed_math_detail::log_q40(static_cast<std::uint32_t>(u.raw()), F);
  return Out::from_raw(fixed_detail::round_shift(ln_q40, fixed_math_detail::kLogFracBits - Out::kFracBits));
}

// atanh(z) in the format Out, for |z| < 1; |z| ≥ 1 (the wall is past the point the prediction describes)
// saturates to ±Out::highest() by the sign of z.
// atanh z = ½(ln(1 + z) − ln(1 − z)): 1 ± z are exact in Q1.30 and positive, so z near ±1 keeps its full
// precision (1 − z = 2^−30 is still exact) and atanh(−z) = −atanh(z) exactly.
// Scaling and overflow: |atanh z| ≤ ½·ln(2^31 − 1) < 10.8 for |z| ≤ 1 − 2^−30, so Out needs 4 integer bits;
// otherwise the result saturates. One rounding from the Q.41 difference of the two kernel values.
// Accuracy: within Out's half resolution + 5e-9 of atanh z (Q7.24: 3.5e-8). Cost: two log kernels (2 CLZ,
// 28 32×32→64 multiplies).
template <typename Out>
constexpr Out fixed_atanh(Fixed<1, 30> z) {
  static_assert(is_fixed<Out>::value, "fixed_atanh: Out must be a Fixed format");
  constexpr std::int32_t kOne = std::int32_t{1} << 30;
  if (z.raw() >= kOne) return Out::highest();
  if (z.raw() <= -kOne) return Out::lowest();
  const std::int64_t ln_plus = fixed_math_detail::log_q40(static_cast<std::uint32_t>(kOne + z.raw()), 30);
  const std::int64_t ln_minus = fixed_math_detail::log_q40(static_cast<std::uint32_t>(kOne - z.raw()), 30);
  // The difference is 2·atanh z in Q.40, i.e. atanh z in Q.41.
  constexpr int kShift = fixed_math_detail::kLogFracBits + 1 - Out::kFracBits;
  return Out::from_raw(fixed_detail::round_shift(ln_plus - ln_minus, kShift));
}

}  // namespace rockwatch::core
