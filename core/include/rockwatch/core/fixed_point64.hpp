// Signed 64-bit fixed-point numbers Q<IntBits>.<FracBits> (IntBits + FracBits = 63) with exact 128-bit
// intermediates: the engine's state and arithmetic. Same rules as the 32-bit Fixed (fixed_point.hpp): round to
// nearest, ties away from zero; saturation at ±(2⁶³ − 1) raw (symmetric, so negation never overflows); no
// undefined behaviour for any input; division by zero saturates by the sign of the dividend (0/0 = 0).
//
// Why 64 bits: the rocking response near the collapse boundary is chaotic, and while the wall chatters on its
// hinge at micrometre amplitudes a 32-bit displacement (9.3e-10 m) is a 1e-3 relative error that grows into
// different verdicts (docs/FIXED_POINT.md). Q1.62 resolves 2.2e-19 m.
//
// 128-bit arithmetic is done on magnitudes as two uint64 words, so results are identical on every target. The
// product uses the compiler's 128-bit type where it has one (x86-64, AArch64) and four 32×32→64 products
// otherwise (Cortex-M4: UMULL); the quotient uses the 128-bit type's division, or otherwise a normalised long
// division in 32-bit digits whose digit estimates are 64/32 divisions done in 16-bit halves with the target's 32/32
// divide (Cortex-M4: UDIV; Knuth's algorithm D, Hacker's Delight's divlu) — exact, so the same bits as the 128-bit
// type's division. udiv_portable, a restoring long division of 64 steps, is the plain reference the tests hold both to.
//
// Mixed formats, also with the 32-bit Fixed: wide_mul<Out>(a, b), wide_div<Out>(a, b), wide_convert<Out>(a), one
// rounding each, saturating to Out.
#pragma once

#include <cstdint>
#include <type_traits>

#include "rockwatch/core/fixed_point.hpp"

namespace rockwatch::core {

namespace fixed64_detail {

// The 64-bit products and conversions run in every step many times with shifts that are constants of the formats
// involved; inlined, each specialises to a few instructions (the shift folded in). An attribute, not a semantic change.
#if defined(__GNUC__)
#define ROCKWATCH_FIXED64_INLINE [[gnu::always_inline]]
#else
#define ROCKWATCH_FIXED64_INLINE
#endif

inline constexpr std::int64_t kRawMax = INT64_MAX;
inline constexpr std::int64_t kRawMin = -INT64_MAX;

struct U128 {
  std::uint64_t hi = 0, lo = 0;
};

#if defined(__SIZEOF_INT128__)
__extension__ typedef unsigned __int128 native_u128;  // a GCC/Clang extension: __extension__ keeps -Wpedantic quiet
#endif

ROCKWATCH_FIXED64_INLINE constexpr std::uint64_t magnitude(std::int64_t v) {
  return v < 0 ? std::uint64_t(0) - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
}

// a · b as 128 bits from four 32×32→64 products: what a 32-bit target does (Cortex-M4: UMULL).
ROCKWATCH_FIXED64_INLINE constexpr U128 umul_portable(std::uint64_t a, std::uint64_t b) {
  const std::uint64_t a_lo = a & 0xffffffffu, a_hi = a >> 32, b_lo = b & 0xffffffffu, b_hi = b >> 32;
  const std::uint64_t ll = a_lo * b_lo, lh = a_lo * b_hi, hl = a_hi * b_lo, hh = a_hi * b_hi;
  const std::uint64_t mid = (ll >> 32) + (lh & 0xffffffffu) + (hl & 0xffffffffu);
  return U128{hh + (lh >> 32) + (hl >> 32) + (mid >> 32), (mid << 32) | (ll & 0xffffffffu)};
}

// n / d for n.hi < d by restoring long division, 64 steps whatever the operands (constant work). rem gets n mod d.
constexpr std::uint64_t udiv_portable(U128 n, std::uint64_t d, std::uint64_t& rem) {
  std::uint64_t q = 0;
  rem = n.hi;
  for (int bit = 63; bit >= 0; --bit) {
    const bool carry = (rem >> 63) != 0;
    rem = (rem << 1) | ((n.lo >> bit) & 1u);
    if (carry || rem >= d) {
      rem -= d;
      q |= std::uint64_t{1} << bit;
    }
  }
  return q;
}

// Leading zero bits of a non-zero word.
constexpr int clz64(std::uint64_t v) {
  int n = 0;
  if ((v >> 32) == 0) { n += 32; v <<= 32; }
  if ((v >> 48) == 0) { n += 16; v <<= 16; }
  if ((v >> 56) == 0) { n += 8; v <<= 8; }
  if ((v >> 60) == 0) { n += 4; v <<= 4; }
  if ((v >> 62) == 0) { n += 2; v <<= 2; }
  if ((v >> 63) == 0) n += 1;
  return n;
}

// (u1·2³² + u0) / v for u1 < v (the quotient fits 32 bits), with 32-bit operations only: the divisor normalised, two
// quotient halves of 16 bits each estimated by a 32/16 division and corrected (Hacker's Delight, divlu). r gets the
// remainder. Products and sums wrap modulo 2³² where the algorithm relies on it.
constexpr std::uint32_t divlu(std::uint32_t u1, std::uint32_t u0, std::uint32_t v, std::uint32_t& r) {
  constexpr std::uint32_t b = 65536u;
  const int s = clz64(v) - 32;
  v <<= s;
  const std::uint32_t vn1 = v >> 16, vn0 = v & 0xffffu;
  const std::uint32_t un32 = s == 0 ? u1 : (u1 << s) | (u0 >> (32 - s));
  const std::uint32_t un10 = u0 << s;
  const std::uint32_t un1 = un10 >> 16, un0 = un10 & 0xffffu;
  std::uint32_t q1 = un32 / vn1;
  std::uint32_t rhat = un32 - q1 * vn1;
  while (q1 >= b || q1 * vn0 > b * rhat + un1) {
    --q1;
    rhat += vn1;
    if (rhat >= b) break;
  }
  const std::uint32_t un21 = un32 * b + un1 - q1 * v;
  std::uint32_t q0 = un21 / vn1;
  rhat = un21 - q0 * vn1;
  while (q0 >= b || q0 * vn0 > b * rhat + un0) {
    --q0;
    rhat += vn1;
    if (rhat >= b) break;
  }
  r = (un21 * b + un0 - q0 * v) >> s;
  return q1 * b + q0;
}

// One 32-bit quotient digit of num / v, num < v·2³² (num of 96 bits), v normalised (top bit set, v ≥ 2⁶³): the
// estimate from the top digits (≤ 2 too large, Knuth's theorem B), refined with the divisor's second digit, then
// corrected against the whole product. rem gets num − q·v (< v).
constexpr std::uint32_t quotient_digit(U128 num, std::uint64_t v, std::uint64_t& rem) {
  const auto n2 = static_cast<std::uint32_t>(num.hi), n1 = static_cast<std::uint32_t>(num.lo >> 32),
             n0 = static_cast<std::uint32_t>(num.lo);
  const auto v1 = static_cast<std::uint32_t>(v >> 32), v0 = static_cast<std::uint32_t>(v);
  std::uint32_t qhat = 0xffffffffu;
  if (n2 < v1) {
    std::uint32_t rhat = 0;
    qhat = divlu(n2, n1, v1, rhat);
    while (std::uint64_t{qhat} * v0 > ((std::uint64_t{rhat} << 32) | n0)) {
      --qhat;
      const std::uint64_t next = std::uint64_t{rhat} + v1;
      if ((next >> 32) != 0) break;
      rhat = static_cast<std::uint32_t>(next);
    }
  }
  U128 p = umul_portable(qhat, v);
  while (p.hi > num.hi || (p.hi == num.hi && p.lo > num.lo)) {  // at most twice
    --qhat;
    p = U128{p.hi - (p.lo < v ? 1u : 0u), p.lo - v};
  }
  rem = num.lo - p.lo;  // num − p < v: the low word alone
  return qhat;
}

// n / d for n.hi < d by normalised long division in 32-bit digits (Knuth's algorithm D): a divisor of one digit takes
// two 64/32 steps, a wider one two quotient digits. Exact: the same quotient and remainder as udiv_portable.
constexpr std::uint64_t udiv_normalised(U128 n, std::uint64_t d, std::uint64_t& rem) {
  if ((d >> 32) == 0) {
    const auto v = static_cast<std::uint32_t>(d);
    std::uint32_t r = 0;
    const std::uint32_t q1 = divlu(static_cast<std::uint32_t>(n.hi), static_cast<std::uint32_t>(n.lo >> 32), v, r);
    const std::uint32_t q0 = divlu(r, static_cast<std::uint32_t>(n.lo), v, r);
    rem = r;
    return (std::uint64_t{q1} << 32) | q0;
  }
  const int s = clz64(d);  // < 32
  const std::uint64_t v = d << s;
  const std::uint64_t nh = s == 0 ? n.hi : (n.hi << s) | (n.lo >> (64 - s));
  const std::uint64_t nl = n.lo << s;
  std::uint64_t r = 0;
  const std::uint32_t q1 = quotient_digit(U128{nh >> 32, (nh << 32) | (nl >> 32)}, v, r);
  const std::uint32_t q0 = quotient_digit(U128{r >> 32, (r << 32) | (nl & 0xffffffffu)}, v, r);
  rem = r >> s;
  return (std::uint64_t{q1} << 32) | q0;
}

ROCKWATCH_FIXED64_INLINE constexpr U128 umul(std::uint64_t a, std::uint64_t b) {
#if defined(__SIZEOF_INT128__)
  const native_u128 p = static_cast<native_u128>(a) * b;
  return U128{static_cast<std::uint64_t>(p >> 64), static_cast<std::uint64_t>(p)};
#else
  return umul_portable(a, b);
#endif
}

// n / d for n.hi < d (the quotient fits 64 bits); both paths are exact, so they give the same bits.
constexpr std::uint64_t udiv(U128 n, std::uint64_t d, std::uint64_t& rem) {
#if defined(__SIZEOF_INT128__)
  const native_u128 wide = (static_cast<native_u128>(n.hi) << 64) | n.lo;
  rem = static_cast<std::uint64_t>(wide % d);
  return static_cast<std::uint64_t>(wide / d);
#else
  return udiv_normalised(n, d, rem);
#endif
}

constexpr U128 add(U128 a, std::uint64_t b) {
  U128 r{a.hi, a.lo + b};
  if (r.lo < a.lo) ++r.hi;
  return r;
}

// a >> s for 0 < s < 128.
ROCKWATCH_FIXED64_INLINE constexpr U128 shr(U128 a, int s) {
  if (s >= 64) return U128{0, a.hi >> (s - 64)};
  return U128{a.hi >> s, (a.lo >> s) | (a.hi << (64 - s))};
}

// Magnitude m · 2^−shift rounded to nearest (ties away); shift ≤ 0 multiplies. `overflow` is set when the result
// does not fit 63 bits.
ROCKWATCH_FIXED64_INLINE constexpr std::uint64_t round_shift_magnitude(U128 m, int shift, bool& overflow) {
  if (shift > 0) {
    if (shift >= 128) return 0;
    const int s = shift;
    const U128 half = s > 64 ? U128{std::uint64_t{1} << (s - 65), 0} : U128{0, std::uint64_t{1} << (s - 1)};
    U128 sum{m.hi + half.hi, m.lo + half.lo};
    if (sum.lo < m.lo) ++sum.hi;
    m = shr(sum, s);
  } else if (shift < 0) {
    const int up = -shift;
    if (up >= 64 || m.hi != 0 || (m.lo >> (63 - up)) != 0) {
      overflow = overflow || m.hi != 0 || m.lo != 0;
      return 0;
    }
    m = U128{0, m.lo << up};
  }
  if (m.hi != 0 || m.lo > std::uint64_t(kRawMax)) {
    overflow = true;
    return 0;
  }
  return m.lo;
}

ROCKWATCH_FIXED64_INLINE constexpr std::int64_t finish(bool negative, std::uint64_t m, bool overflow) {
  if (overflow) return negative ? kRawMin : kRawMax;
  const auto v = static_cast<std::int64_t>(m);
  return negative ? -v : v;
}

// round(a · b · 2^−shift), saturated to ±(2⁶³ − 1).
ROCKWATCH_FIXED64_INLINE constexpr std::int64_t mul_round(std::int64_t a, std::int64_t b, int shift) {
  bool overflow = false;
  const std::uint64_t m = round_shift_magnitude(umul(magnitude(a), magnitude(b)), shift, overflow);
  return finish((a < 0) != (b < 0), m, overflow);
}

// round(v · 2^−shift), saturated.
ROCKWATCH_FIXED64_INLINE constexpr std::int64_t convert_round(std::int64_t v, int shift) {
  bool overflow = false;
  const std::uint64_t m = round_shift_magnitude(U128{0, magnitude(v)}, shift, overflow);
  return finish(v < 0, m, overflow);
}

// round(n · 2^widen / d) for 0 ≤ widen ≤ 63, saturated; d = 0 saturates by the sign of n (0/0 = 0).
constexpr std::int64_t div_round(std::int64_t n, std::int64_t d, int widen) {
  if (d == 0) return n == 0 ? 0 : (n > 0 ? kRawMax : kRawMin);
  const bool negative = (n < 0) != (d < 0);
  const std::uint64_t ud = magnitude(d);
  const U128 num = umul(magnitude(n), std::uint64_t{1} << widen);
  if (num.hi >= ud) return negative ? kRawMin : kRawMax;  // quotient ≥ 2⁶⁴
  std::uint64_t rem = 0;
  const std::uint64_t q = udiv(num, ud, rem);
  const bool round_up = rem >= ud - rem;  // rem ≥ d/2 without overflow
  const std::uint64_t rounded = q + (round_up ? 1u : 0u);
  const bool overflow = rounded > std::uint64_t(kRawMax) || rounded < q;
  return finish(negative, rounded, overflow);
}

}  // namespace fixed64_detail

template <int IntBits, int FracBits>
class Fixed64 {
  static_assert(IntBits >= -60 && IntBits <= 63 && IntBits + FracBits == 63, "Q format must use 63 value bits");

 public:
  static constexpr int kIntBits = IntBits;
  static constexpr int kFracBits = FracBits;
  using raw_type = std::int64_t;

  constexpr Fixed64() = default;
  // From an integer. Scaling and overflow: saturates when |v| ≥ 2^IntBits.
  template <typename Int, typename std::enable_if<std::is_integral<Int>::value, int>::type = 0>
  constexpr explicit Fixed64(Int v) : raw_(fixed64_detail::convert_round(clamp_integer(v), -FracBits)) {}
  // From a double, rounded to nearest (ties away), saturating; NaN gives 0. Initialisation and host code only.
  constexpr explicit Fixed64(double v) : raw_(from_double_raw(v)) {}

  static constexpr Fixed64 from_raw(std::int64_t raw) {
    Fixed64 f;
    f.raw_ = raw < -INT64_MAX ? -INT64_MAX : raw;
    return f;
  }
  constexpr std::int64_t raw() const { return raw_; }
  constexpr double to_double() const { return fixed_detail::raw_to_double(raw_, FracBits); }

  static constexpr Fixed64 highest() { return from_raw(INT64_MAX); }
  static constexpr Fixed64 lowest() { return from_raw(-INT64_MAX); }
  constexpr bool saturated() const { return raw_ == INT64_MAX || raw_ == -INT64_MAX; }

  // Scaling and overflow (+, −): exact, saturating.
  friend constexpr Fixed64 operator+(Fixed64 a, Fixed64 b) {
    std::int64_t r = 0;
    if (__builtin_add_overflow(a.raw_, b.raw_, &r)) return b.raw_ > 0 ? highest() : lowest();
    return from_raw(r);
  }
  friend constexpr Fixed64 operator-(Fixed64 a, Fixed64 b) {
    std::int64_t r = 0;
    if (__builtin_sub_overflow(a.raw_, b.raw_, &r)) return b.raw_ < 0 ? highest() : lowest();
    return from_raw(r);
  }
  // Exact (symmetric range).
  constexpr Fixed64 operator-() const { return from_raw(-raw_); }
  // Scaling and overflow: exact 126-bit product, one rounding by 2^−FracBits, saturating.
  friend constexpr Fixed64 operator*(Fixed64 a, Fixed64 b) {
    return from_raw(fixed64_detail::mul_round(a.raw_, b.raw_, FracBits));
  }
  // Scaling and overflow: dividend widened by 2^FracBits exactly in 128 bits, one rounding, saturating.
  friend constexpr Fixed64 operator/(Fixed64 a, Fixed64 b) {
    static_assert(FracBits >= 0 && FracBits <= 63, "operator/ needs 0..63 fraction bits");
    return from_raw(fixed64_detail::div_round(a.raw_, b.raw_, FracBits));
  }
  // Compound forms (Eigen's += / −= / scalar *= /=): the same roundings and saturation as above.
  constexpr Fixed64& operator+=(Fixed64 b) { return *this = *this + b; }
  constexpr Fixed64& operator-=(Fixed64 b) { return *this = *this - b; }
  constexpr Fixed64& operator*=(Fixed64 b) { return *this = *this * b; }
  constexpr Fixed64& operator/=(Fixed64 b) { return *this = *this / b; }
  friend constexpr bool operator==(Fixed64 a, Fixed64 b) { return a.raw_ == b.raw_; }
  friend constexpr bool operator!=(Fixed64 a, Fixed64 b) { return a.raw_ != b.raw_; }
  friend constexpr bool operator<(Fixed64 a, Fixed64 b) { return a.raw_ < b.raw_; }
  friend constexpr bool operator<=(Fixed64 a, Fixed64 b) { return a.raw_ <= b.raw_; }
  friend constexpr bool operator>(Fixed64 a, Fixed64 b) { return a.raw_ > b.raw_; }
  friend constexpr bool operator>=(Fixed64 a, Fixed64 b) { return a.raw_ >= b.raw_; }

 private:
  template <typename Int>
  static constexpr std::int64_t clamp_integer(Int v) {
    if (v > Int(0) && static_cast<std::uint64_t>(v) > std::uint64_t(INT64_MAX)) return INT64_MAX;
    return static_cast<std::int64_t>(v);
  }
  static constexpr std::int64_t from_double_raw(double v) {
    // Rounded to nearest, ties away; saturating at ±(2^63 − 1) (fixed_detail::double_to_raw: from the bits).
    return fixed_detail::double_to_raw(v, FracBits, INT64_MAX);
  }


  std::int64_t raw_ = 0;
};

namespace fixed64_detail {
template <typename T>
struct format;
template <int I, int F>
struct format<Fixed<I, F>> {
  static constexpr int frac = F;
  static constexpr std::int64_t raw(Fixed<I, F> v) { return v.raw(); }
  static constexpr Fixed<I, F> from(std::int64_t r) {
    return Fixed<I, F>::from_raw(static_cast<std::int32_t>(r > INT32_MAX ? INT32_MAX : (r < -INT32_MAX ? -INT32_MAX : r)));
  }
};
template <int I, int F>
struct format<Fixed64<I, F>> {
  static constexpr int frac = F;
  static constexpr std::int64_t raw(Fixed64<I, F> v) { return v.raw(); }
  static constexpr Fixed64<I, F> from(std::int64_t r) { return Fixed64<I, F>::from_raw(r); }
};
}  // namespace fixed64_detail

// a · b in the format Out (any of Fixed, Fixed64). Scaling and overflow: exact product of the raw values (< 2^126),
// shifted by F_a + F_b − F_out with one rounding; saturates to Out.
template <typename Out, typename A, typename B>
constexpr Out wide_mul(A a, B b) {
  using namespace fixed64_detail;
  return format<Out>::from(
      mul_round(format<A>::raw(a), format<B>::raw(b), format<A>::frac + format<B>::frac - format<Out>::frac));
}

// a / b in the format Out. Scaling and overflow: the dividend is widened exactly by 2^(F_out + F_b − F_a), which
// must be in [0, 63] (compile-time check); one rounding; saturates; b = 0 saturates by sign.
template <typename Out, typename A, typename B>
constexpr Out wide_div(A a, B b) {
  using namespace fixed64_detail;
  constexpr int widen = format<Out>::frac + format<B>::frac - format<A>::frac;
  static_assert(widen >= 0 && widen <= 63, "wide_div: choose formats whose quotient needs a widening of 0..63 bits");
  return format<Out>::from(div_round(format<A>::raw(a), format<B>::raw(b), widen));
}

// a in the format Out. Scaling and overflow: fewer fraction bits round once; more are exact; saturates to Out.
template <typename Out, typename A>
constexpr Out wide_convert(A a) {
  using namespace fixed64_detail;
  return format<Out>::from(convert_round(format<A>::raw(a), format<A>::frac - format<Out>::frac));
}

// |a|. Exact (symmetric range).
template <int I, int F>
constexpr Fixed64<I, F> abs(Fixed64<I, F> a) {
  return a.raw() < 0 ? -a : a;
}

}  // namespace rockwatch::core
