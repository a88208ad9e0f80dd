// Standard normal distribution functions for the collapse statistics (private to sim). Φ goes through std::erfc so
// both tails keep full relative accuracy (1 − Φ(z) is never formed by subtraction); ln Φ and the inverse Mills ratio
// φ/Φ switch to their asymptotic series far in the lower tail, where Φ would underflow.
#pragma once

#include <cmath>

namespace rockwatch::sim::study::detail {

inline constexpr double kInvSqrt2 = 0.70710678118654752440;
inline constexpr double kInvSqrt2Pi = 0.39894228040143267794;
inline constexpr double kLogSqrt2Pi = 0.91893853320467274178;

// Below this z, Φ(z) ≈ 1e-300: ln Φ and φ/Φ use the asymptotic series (truncation error ≈ 945/z¹⁰ < 3e-13).
inline constexpr double kLowerTailZ = -37.0;

inline double normal_pdf(double z) { return kInvSqrt2Pi * std::exp(-0.5 * z * z); }

inline double normal_cdf(double z) { return 0.5 * std::erfc(-z * kInvSqrt2); }

// 1 − 1/z² + 3/z⁴ − 15/z⁶ + 105/z⁸: Φ(z) ≈ φ(z)/(−z) · series(z) for z → −∞.
inline double lower_tail_series(double z) {
  const double u = 1.0 / (z * z);
  return 1.0 + u * (-1.0 + u * (3.0 + u * (-15.0 + u * 105.0)));
}

// ln Φ(z), accurate in both tails.
inline double log_normal_cdf(double z) {
  if (z >= 0.0) return std::log1p(-0.5 * std::erfc(z * kInvSqrt2));
  if (z > kLowerTailZ) return std::log(normal_cdf(z));
  return -0.5 * z * z - std::log(-z) - kLogSqrt2Pi + std::log(lower_tail_series(z));
}

// Inverse Mills ratio φ(z)/Φ(z) (= d ln Φ/dz), accurate in both tails.
inline double mills_ratio(double z) {
  if (z > kLowerTailZ) return normal_pdf(z) / normal_cdf(z);
  return -z / lower_tail_series(z);
}

}  // namespace rockwatch::sim::study::detail
