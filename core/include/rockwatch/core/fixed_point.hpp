// Signed fixed-point numbers Q<IntBits>.<FracBits> on int32 with int64 intermediates (CMSIS-DSP naming: the
// format is in the type). Value = raw · 2^−FracBits; IntBits + FracBits = 31 (the sign takes the last bit).
// IntBits may be negative for small quantities (Q−12.43 holds |v| < 2^−12 with 2^−43 resolution), as in the
// engine's H²/4 [s²].
//
// Rounding: every operation that drops bits rounds to nearest, ties away from zero (so results are symmetric
// under negation: round(−v) = −round(v)).
// Saturation: results outside the range clamp to ±(2^31 − 1) raw. The range is symmetric, so negation and abs
// never overflow; INT32_MIN is never produced (from_raw maps it to the lowest value). No operation has undefined
// behaviour for any input: every shift is of a non-negative magnitude, every product fits int64, and division by
// zero saturates by the sign of the dividend (0/0 = 0).
//
// Mixed formats: fixed_mul<Out>(a, b), fixed_div<Out>(a, b) and fixed_convert<Out>(a) produce the result directly
// in the format Out with a single rounding. The engine keeps each quantity in its own format (see
// fixed_rocking_stepper.hpp); the same-format operators exist for generic code and Eigen (fixed_point_eigen.hpp).
#pragma once

#include <cstdint>
#include <type_traits>

namespace rockwatch::core {

namespace fixed_detail {

inline constexpr std::int64_t kRawMax = INT32_MAX;
inline constexpr std::int64_t kRawMin = -static_cast<std::int64_t>(INT32_MAX);

constexpr std::int32_t saturate(std::int64_t v) {
  return static_cast<std::int32_t>(v > kRawMax ? kRawMax : (v < kRawMin ? kRawMin : v));
}

// v·2^frac_bits rounded to nearest, ties away from zero, saturated at ±limit; NaN gives 0. From the double's bits
// (no floating-point operation: the M4 has no double unit, and the soft-double division, product and compares this
// replaces cost ~300 instructions a conversion): bit for bit the value of the floating-point form it replaces,
// trunc(v·2^F) rounded on its remainder, saturating when |v·2^F| ≥ limit. frac_bits in [0, 123].
// Scaling and overflow: the double is m·2^e with m < 2^53; m·2^(e+F) is formed only when it is below 2^63.
constexpr std::int64_t double_to_raw(double v, int frac_bits, std::int64_t limit) {
  const auto bits = __builtin_bit_cast(std::uint64_t, v);
  const bool negative = (bits >> 63) != 0;
  const int biased = static_cast<int>((bits >> 52) & 0x7FF);
  const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
  if (biased == 0x7FF) {  // NaN: 0; ±Inf: saturated
    if (fraction != 0) return 0;
    return negative ? -limit : limit;
  }
  if (biased == 0) return 0;  // zero or subnormal: below 2^−1022·2^123, rounds to 0
  const std::uint64_t m = fraction | (std::uint64_t{1} << 52);
  const int sh = biased - 1075 + frac_bits;  // v·2^F = m·2^sh
  std::uint64_t magnitude = 0;
  if (sh >= 11) {
    magnitude = std::uint64_t(limit);  // ≥ 2^63 ≥ limit
  } else if (sh >= 0) {
    magnitude = m << sh;
  } else if (sh >= -53) {
    const int n = -sh;
    magnitude = (m + (std::uint64_t{1} << (n - 1))) >> n;
  }
  if (magnitude > std::uint64_t(limit)) magnitude = std::uint64_t(limit);
  const auto r = static_cast<std::int64_t>(magnitude);
  return negative ? -r : r;
}

// raw·2^−frac_bits as a double: the integer converted (rounded to nearest, as double(raw)), then its exponent
// lowered by frac_bits, exact (|raw| ≥ 1 has an exponent ≥ 0, frac_bits ≤ 123: no underflow). Bit for bit
// double(raw) · 2^−F, without the soft-double product or division. frac_bits in [0, 123].
constexpr double raw_to_double(std::int64_t raw, int frac_bits) {
  if (raw == 0) return 0.0;
  const auto bits = __builtin_bit_cast(std::uint64_t, static_cast<double>(raw));
  return __builtin_bit_cast(double, bits - (static_cast<std::uint64_t>(frac_bits) << 52));
}

// v · 2^−shift rounded to nearest, ties away from zero; shift ≤ 0 multiplies with saturation.
// Scaling and overflow: |v| < 2^63 on entry; for shift > 0 the magnitude only shrinks; for shift < 0 the
// result saturates when it would exceed the int32 range (checked before shifting, so no int64 overflow).
constexpr std::int32_t round_shift(std::int64_t v, int shift) {
  if (shift <= 0) {
    const int up = -shift;
    if (up >= 32) return v == 0 ? 0 : saturate(v > 0 ? kRawMax + 1 : kRawMin - 1);
    const std::int64_t limit = kRawMax >> up;
    if (v > limit) return saturate(kRawMax + 1);
    if (v < -limit) return saturate(kRawMin - 1);
    return saturate(v * (std::int64_t{1} << up));
  }
  if (shift >= 64) return 0;  // |v| < 2^63: below one half (shift 63 can still round to ±1)
  const bool negative = v < 0;
  const std::uint64_t magnitude = negative ? std::uint64_t(0) - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
  const std::uint64_t rounded = (magnitude + (std::uint64_t{1} << (shift - 1))) >> shift;
  const std::int64_t r = rounded > std::uint64_t(kRawMax) ? kRawMax + 1 : static_cast<std::int64_t>(rounded);
  return saturate(negative ? -r : r);
}

// n / d rounded to nearest, ties away from zero; d = 0 saturates by the sign of n (0/0 = 0).
// Scaling and overflow: |n| < 2^63, |d| < 2^63; the quotient saturates to the int32 range.
constexpr std::int32_t round_divide(std::int64_t n, std::int64_t d) {
  if (d == 0) return n == 0 ? 0 : saturate(n > 0 ? kRawMax + 1 : kRawMin - 1);
  const bool negative = (n < 0) != (d < 0);
  const std::uint64_t un = n < 0 ? std::uint64_t(0) - static_cast<std::uint64_t>(n) : static_cast<std::uint64_t>(n);
  const std::uint64_t ud = d < 0 ? std::uint64_t(0) - static_cast<std::uint64_t>(d) : static_cast<std::uint64_t>(d);
  const std::uint64_t q = un / ud;
  const std::uint64_t rem = un - q * ud;
  const std::uint64_t rounded = q + (rem >= ud - rem ? 1u : 0u);  // rem ≥ d/2 without overflow
  const std::int64_t r = rounded > std::uint64_t(kRawMax) ? kRawMax + 1 : static_cast<std::int64_t>(rounded);
  return saturate(negative ? -r : r);
}

}  // namespace fixed_detail

template <int IntBits, int FracBits>
class Fixed {
  static_assert(IntBits >= -30 && IntBits <= 31 && IntBits + FracBits == 31, "Q format must use 31 value bits");

 public:
  static constexpr int kIntBits = IntBits;
  static constexpr int kFracBits = FracBits;

  constexpr Fixed() = default;
  // From an integer value. Scaling and overflow: saturates when |v| ≥ 2^IntBits.
  // Any integer type (Eigen constructs scalars from Index). Scaling and overflow: saturates when |v| ≥ 2^IntBits.
  template <typename Int, typename std::enable_if<std::is_integral<Int>::value, int>::type = 0>
  constexpr explicit Fixed(Int v) : raw_(from_integer_raw(v)) {}
  // From a double, rounded to nearest (ties away); saturates outside the range; NaN gives 0.
  // Initialisation-time conversion: the per-sample code never touches floating point.
  constexpr explicit Fixed(double v) : raw_(from_double_raw(v)) {}

  static constexpr Fixed from_raw(std::int32_t raw) {
    Fixed f;
    f.raw_ = raw < -INT32_MAX ? -INT32_MAX : raw;
    return f;
  }
  constexpr std::int32_t raw() const { return raw_; }
  constexpr double to_double() const { return fixed_detail::raw_to_double(raw_, FracBits); }

  static constexpr Fixed highest() { return from_raw(INT32_MAX); }
  static constexpr Fixed lowest() { return from_raw(-INT32_MAX); }
  static constexpr Fixed resolution() { return from_raw(1); }  // 2^−FracBits
  static constexpr double resolution_value() { return 1.0 / double(std::int64_t{1} << FracBits); }
  // At either end of the range: the value saturated (or is exactly the extreme).
  constexpr bool saturated() const { return raw_ == INT32_MAX || raw_ == -INT32_MAX; }

  // Scaling and overflow (+, −): exact, saturates on overflow.
  friend constexpr Fixed operator+(Fixed a, Fixed b) {
    return from_raw(fixed_detail::saturate(std::int64_t{a.raw_} + b.raw_));
  }
  friend constexpr Fixed operator-(Fixed a, Fixed b) {
    return from_raw(fixed_detail::saturate(std::int64_t{a.raw_} - b.raw_));
  }
  // Scaling and overflow: exact; the symmetric range makes it never overflow.
  constexpr Fixed operator-() const { return from_raw(-raw_); }
  // Scaling and overflow: 62-bit product, one rounding by 2^−FracBits, saturates.
  friend constexpr Fixed operator*(Fixed a, Fixed b) {
    return from_raw(fixed_detail::round_shift(std::int64_t{a.raw_} * b.raw_, FracBits));
  }
  // Scaling and overflow: dividend widened by 2^FracBits, one rounding, saturates; b = 0 saturates. With more
  // than 31 fraction bits a dividend |a.raw|·2^FracBits ≥ 2^62 would overflow int64; its quotient exceeds
  // 2^62/|b.raw| > 2^31 anyway, so it saturates by the signs without dividing. Otherwise the dividend is < 2^62.
  friend constexpr Fixed operator/(Fixed a, Fixed b) {
    if constexpr (FracBits > 31) {
      constexpr std::int32_t kLimit = std::int32_t{1} << (62 - FracBits);
      if (a.raw_ >= kLimit || a.raw_ <= -kLimit) return (a.raw_ < 0) != (b.raw_ < 0) ? lowest() : highest();
    }
    return from_raw(fixed_detail::round_divide(std::int64_t{a.raw_} * (std::int64_t{1} << FracBits), b.raw_));
  }
  constexpr Fixed& operator+=(Fixed b) { return *this = *this + b; }
  constexpr Fixed& operator-=(Fixed b) { return *this = *this - b; }
  constexpr Fixed& operator*=(Fixed b) { return *this = *this * b; }
  constexpr Fixed& operator/=(Fixed b) { return *this = *this / b; }

  friend constexpr bool operator==(Fixed a, Fixed b) { return a.raw_ == b.raw_; }
  friend constexpr bool operator!=(Fixed a, Fixed b) { return a.raw_ != b.raw_; }
  friend constexpr bool operator<(Fixed a, Fixed b) { return a.raw_ < b.raw_; }
  friend constexpr bool operator<=(Fixed a, Fixed b) { return a.raw_ <= b.raw_; }
  friend constexpr bool operator>(Fixed a, Fixed b) { return a.raw_ > b.raw_; }
  friend constexpr bool operator>=(Fixed a, Fixed b) { return a.raw_ >= b.raw_; }

 private:
  template <typename Int>
  static constexpr std::int32_t from_integer_raw(Int v) {
    // Clamp first so that the widening to int64 and the shift are exact for every integer type.
    constexpr std::int64_t limit = fixed_detail::kRawMax;
    if (v > Int(0) && static_cast<std::uint64_t>(v) > static_cast<std::uint64_t>(limit)) return INT32_MAX;
    if (v < Int(0) && static_cast<std::int64_t>(v) < -limit) return -INT32_MAX;
    return fixed_detail::round_shift(static_cast<std::int64_t>(v), -FracBits);
  }

  static constexpr std::int32_t from_double_raw(double v) {
    // Rounded to nearest, ties away; saturating at ±(2^31 − 1) (fixed_detail::double_to_raw: from the bits).
    return static_cast<std::int32_t>(fixed_detail::double_to_raw(v, FracBits, fixed_detail::kRawMax));
  }


  std::int32_t raw_ = 0;
};

template <typename T>
struct is_fixed : std::false_type {};
template <int I, int F>
struct is_fixed<Fixed<I, F>> : std::true_type {};

// a · b in the format Out. Scaling and overflow: the 62-bit product is shifted by F_a + F_b − F_out with one
// rounding; saturates when the result does not fit Out.
template <typename Out, int Ia, int Fa, int Ib, int Fb>
constexpr Out fixed_mul(Fixed<Ia, Fa> a, Fixed<Ib, Fb> b) {
  return Out::from_raw(fixed_detail::round_shift(std::int64_t{a.raw()} * b.raw(), Fa + Fb - Out::kFracBits));
}

// a / b in the format Out. Scaling and overflow: the dividend is widened by 2^(F_out + F_b − F_a), which must be
// in [0, 31] (checked at compile time) so it stays below 2^62; one rounding; saturates; b = 0 saturates by sign.
template <typename Out, int Ia, int Fa, int Ib, int Fb>
constexpr Out fixed_div(Fixed<Ia, Fa> a, Fixed<Ib, Fb> b) {
  constexpr int widen = Out::kFracBits + Fb - Fa;
  static_assert(widen >= 0 && widen <= 31, "fixed_div: choose formats whose quotient needs a widening of 0..31 bits");
  return Out::from_raw(fixed_detail::round_divide(std::int64_t{a.raw()} * (std::int64_t{1} << widen), b.raw()));
}

// a in the format Out. Scaling and overflow: fewer fraction bits round once; more fraction bits are exact but
// saturate when the value exceeds Out's range.
template <typename Out, int I, int F>
constexpr Out fixed_convert(Fixed<I, F> a) {
  return Out::from_raw(fixed_detail::round_shift(a.raw(), F - Out::kFracBits));
}

// |a|. Scaling and overflow: exact (symmetric range).
template <int I, int F>
constexpr Fixed<I, F> abs(Fixed<I, F> a) {
  return a.raw() < 0 ? -a : a;
}

}  // namespace rockwatch::core
