// Fixed<I, F> as an Eigen scalar (Eigen's "Using custom scalar types" guide): NumTraits plus the free functions
// Eigen finds by argument-dependent lookup. Fixed-size matrices of one Q format then support sums, differences,
// coefficient-wise operations, matrix products, .dot() and .sum() with Fixed's own rounding and saturation.
//
// What the arithmetic means inside Eigen expressions:
// - A matrix product or .dot() rounds every scalar product once (same-format operator*) and adds with
//   saturation, so an n-term inner product is within n half-resolutions of the exact sum of the exact products.
// - Saturation is sticky only per operation: a saturated partial sum that later terms pull back is not an
//   error flag. Check .saturated() on results where the range matters, and keep inputs within range.
// - Not supported: mixing formats in one expression (use fixed_mul/fixed_convert between them), anything that
//   needs a square root or floating point (norm(), normalized(), decompositions), printing. .mean() works but
//   divides (a 64-bit library division on Cortex-M4).
//
// Include this header before instantiating any Eigen type with a Fixed scalar (sensor_axes.hpp does).
#pragma once

#include <Eigen/Core>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point64.hpp"

namespace rockwatch::core {

// The real-scalar functions Eigen's custom-scalar guide asks for. Scaling and overflow: exact (real, imag,
// conj); abs2 is the same-format product a·a: one rounding, saturates at highest().
template <int I, int F>
constexpr Fixed<I, F> real(Fixed<I, F> a) { return a; }
template <int I, int F>
constexpr Fixed<I, F> imag(Fixed<I, F>) { return Fixed<I, F>(); }
template <int I, int F>
constexpr Fixed<I, F> conj(Fixed<I, F> a) { return a; }
template <int I, int F>
constexpr Fixed<I, F> abs2(Fixed<I, F> a) { return a * a; }

// The same for the 64-bit Fixed64 (the observer's covariance, wall_observer.hpp). Scaling and overflow: as above;
// abs2 is one rounding of the exact 128-bit product, saturating at highest().
template <int I, int F>
constexpr Fixed64<I, F> real(Fixed64<I, F> a) { return a; }
template <int I, int F>
constexpr Fixed64<I, F> imag(Fixed64<I, F>) { return Fixed64<I, F>(); }
template <int I, int F>
constexpr Fixed64<I, F> conj(Fixed64<I, F> a) { return a; }
template <int I, int F>
constexpr Fixed64<I, F> abs2(Fixed64<I, F> a) { return a * a; }

}  // namespace rockwatch::core

namespace Eigen {

template <int I, int F>
struct NumTraits<rockwatch::core::Fixed<I, F>> {
  using Scalar = rockwatch::core::Fixed<I, F>;
  using Real = Scalar;
  using NonInteger = Scalar;  // division stays in the format (rounded), so the type is its own non-integer
  using Literal = Scalar;
  using Nested = Scalar;

  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    // The fixed-size storage default-constructs every coefficient anyway (raw 0); Eigen only consults this for
    // heap storage, which core never uses.
    RequireInitialization = 0,
    // Costs in Eigen's unit (about one simple instruction), used to choose evaluation strategies:
    ReadCost = 1,
    AddCost = 3,  // 64-bit add and two compares for the saturation
    MulCost = 6   // 32×32→64 multiply, rounding shift with saturation checks
  };

  // One resolution step, 2^−F: the smallest difference the format can hold.
  static constexpr Scalar epsilon() { return Scalar::resolution(); }
  // Tolerance of Eigen's isApprox/isZero: 128 resolution steps (Q7.24: 7.6e-6), at most 1. The error of a
  // short fixed-point computation is a few half-steps in absolute terms; these tests are relative, so this is
  // only a loose default for values well above the resolution.
  static constexpr Scalar dummy_precision() { return Scalar::from_raw(std::int32_t{1} << (F < 7 ? F : 7)); }
  static constexpr Scalar highest() { return Scalar::highest(); }
  static constexpr Scalar lowest() { return Scalar::lowest(); }
  // Decimal places that survive a round trip through the format: floor(F·log10 2).
  static constexpr int digits10() { return (F * 30103) / 100000; }
  // Binary digits of the value (std::numeric_limits<int32_t>::digits).
  static constexpr int digits() { return 31; }
};

template <int I, int F>
struct NumTraits<rockwatch::core::Fixed64<I, F>> {
  using Scalar = rockwatch::core::Fixed64<I, F>;
  using Real = Scalar;
  using NonInteger = Scalar;
  using Literal = Scalar;
  using Nested = Scalar;

  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 0,
    ReadCost = 2,
    AddCost = 4,   // 64-bit add with saturation checks (two words on a 32-bit target)
    MulCost = 12   // 64×64→128 product (four UMULL on Cortex-M4) and a rounding shift
  };

  static constexpr Scalar epsilon() { return Scalar::from_raw(1); }
  static constexpr Scalar dummy_precision() { return Scalar::from_raw(std::int64_t{1} << (F < 7 ? F : 7)); }
  static constexpr Scalar highest() { return Scalar::highest(); }
  static constexpr Scalar lowest() { return Scalar::lowest(); }
  static constexpr int digits10() { return (F * 30103) / 100000; }
  static constexpr int digits() { return 63; }
};

}  // namespace Eigen
