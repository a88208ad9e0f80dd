// Static non-linear kinematic analysis of the two-block wall (SPEC §5, the design paper's §3): collapse multiplier
// K, equivalent-SDOF instability displacement X, secant period T at x_eq,max = λX, and the allowable PGA for which
// the spectral displacement at T equals x_eq,max.
//
// Only the total height h = h1 + h2 enters the static chain (the mechanism's hinge sits at mid-height whatever
// the split); h1 and h2 are accepted so that a wall described for `simulate` can be checked unchanged, and are
// validated when given.
//
// Initialisation-time code: always double, header-only, no heap, no exceptions, no I/O.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "rockwatch/core/design_spectrum.hpp"

namespace rockwatch::core {

// Codes that prescribe the instability factor λ (x_eq,max = λ·X). Stable values; new codes are appended.
enum class InstabilityCode : std::uint8_t {
  ntc2008 = 0,    // Italian NTC 2008: λ = 0.4
  nzsee2016 = 1,  // New Zealand NZSEE 2016: λ = 0.6
};

constexpr double code_lambda(InstabilityCode c) { return c == InstabilityCode::ntc2008 ? 0.4 : 0.6; }

inline const char* code_name(InstabilityCode c) { return c == InstabilityCode::ntc2008 ? "ntc2008" : "nzsee2016"; }

// As the codes are cited in the paper and in reports.
inline const char* code_title(InstabilityCode c) { return c == InstabilityCode::ntc2008 ? "NTC 2008" : "NZSEE 2016"; }

inline bool parse_code_name(const char* text, InstabilityCode& out) {
  if (std::strcmp(text, "ntc2008") == 0) out = InstabilityCode::ntc2008;
  else if (std::strcmp(text, "nzsee2016") == 0) out = InstabilityCode::nzsee2016;
  else return false;
  return true;
}

struct StaticInputs {
  double b_m = 0.10;          // wall thickness b [m]
  double h1_m = 1.75;         // bottom block height [m]; only h1 + h2 is used
  double h2_m = 1.75;         // top block height [m]; only h1 + h2 is used
  bool blocks_given = true;   // false when only the total height is known (h1 = h2 = h/2 then stand in for it)
  double fp_npm = 0.0;        // overburden on the top [N per m of wall]
  double a = 0.0;             // overburden eccentricity, fraction of b from the top hinge [-]
  double psi_rad = 0.0;       // out-of-plumb angle ψ [rad] (the SPEC's sign: ψ > 0 lowers K)
  double rho_kgpm3 = 1800.0;  // masonry density [kg/m³]; with Fp = 0 the result does not depend on it
  double g_mps2 = 9.81;       // gravity [m/s²]
  double lambda = 0.4;        // instability factor: x_eq,max = λ·X [-]
  SpectrumShape spectrum = spectrum_npr9998_2015();

  constexpr double h_m() const { return h1_m + h2_m; }
};

// The paper's wall (b 0.1, h1 = h2 = 1.75, ρ 1800, Fp 0) with the instability factor of `code`.
inline StaticInputs paper_static_inputs(InstabilityCode code = InstabilityCode::ntc2008) {
  StaticInputs in;
  in.lambda = code_lambda(code);
  return in;
}

// A wall known only by its total height: the static chain needs nothing else.
inline void set_total_height(StaticInputs& in, double h_m) {
  in.h1_m = 0.5 * h_m;
  in.h2_m = 0.5 * h_m;
  in.blocks_given = false;
}

// Error codes are stable: new codes are appended, never renumbered.
enum class StaticError : std::uint8_t {
  ok = 0,
  not_finite = 1,
  b_not_positive = 2,
  h_not_above_b = 3,
  h1_not_above_b = 4,
  h2_not_above_b = 5,
  fp_negative = 6,
  a_out_of_range = 7,
  rho_not_positive = 8,
  g_not_positive = 9,
  lambda_out_of_range = 10,
  psi_too_large = 11,       // ψ leaves K ≤ 0 or X ≤ 0: the wall is statically unstable without shaking
  spectrum_invalid = 12,
  result_not_finite = 13,   // extreme inputs overflow the chain
};

struct StaticCheck {
  StaticError code = StaticError::ok;
  // The input at fault: "b", "h", "h1", "h2", "fp", "a", "psi", "rho", "g", "lambda", "spectrum" ("" for overflow).
  const char* field = "";
  const char* message = "";  // what was expected
  constexpr bool ok() const { return code == StaticError::ok; }
};

struct StaticResult {
  // Fp ≠ 0 or ψ ≠ 0 (a enters only through Fp): K, X, T come from the virtual-work derivation — label them so.
  bool general_case = false;
  double h_m = 0.0;            // total height h1 + h2 [m]
  double weight_npm = 0.0;     // W = ρ g b h [N per m of wall]
  double f = 0.0;              // overburden ratio Fp / W [-]
  double k = 0.0;              // collapse multiplier: rocking starts at K·g [-]
  double x_m = 0.0;            // equivalent-SDOF instability displacement X [m]
  double period_s = 0.0;       // secant period T at x_eq,max [s]
  double x_eq_max_m = 0.0;     // allowed displacement demand λX [m]
  double shape = 0.0;          // spectrum shape at T, Se(T)/a_g [-]
  double allowable_pga_mps2 = 0.0;
  double allowable_pga_g = 0.0;
  double se_mps2 = 0.0;        // Se(T) at the allowable PGA [m/s²]
  double sd_m = 0.0;           // Sd(T) = Se(T)(T/2π)² at the allowable PGA: equals x_eq,max [m]
};

namespace detail {

inline constexpr double kTwoPi = 6.283185307179586476925286766559;

// The general-case formulas of SPEC §5. With Fp = 0 and ψ = 0 every extra factor is exactly 1 or 0, so the
// result is bit-identical to the simple case's K = 4b/h, X = b/2, T = 2πλ√(h/(8g(1−λ²))): one code path.
inline StaticResult static_chain(const StaticInputs& in) {
  StaticResult r;
  const double b = in.b_m, h = in.h_m(), g = in.g_mps2, lambda = in.lambda;
  r.general_case = in.fp_npm != 0.0 || in.psi_rad != 0.0;
  r.h_m = h;
  r.weight_npm = in.rho_kgpm3 * g * b * h;
  r.f = in.fp_npm == 0.0 ? 0.0 : in.fp_npm / r.weight_npm;
  const double lever = 1.0 + (2.0 - in.a) * r.f;  // the overburden's share of the restoring moment
  r.k = 4.0 * b / h * lever - in.psi_rad;
  r.x_m = (b * lever - in.psi_rad * h / 4.0) / (2.0 * (1.0 + 2.0 * r.f));
  r.period_s = kTwoPi * lambda * std::sqrt(h / (8.0 * g * (1.0 + 2.0 * r.f) * (1.0 - lambda * lambda)));
  r.x_eq_max_m = lambda * r.x_m;
  r.shape = spectrum_shape(in.spectrum, r.period_s);
  const double omega = kTwoPi / r.period_s;
  r.allowable_pga_mps2 = r.x_eq_max_m * omega * omega / r.shape;
  r.allowable_pga_g = r.allowable_pga_mps2 / g;
  r.se_mps2 = r.allowable_pga_mps2 * r.shape;
  const double t_over_2pi = r.period_s / kTwoPi;
  r.sd_m = r.se_mps2 * t_over_2pi * t_over_2pi;
  return r;
}

}  // namespace detail

// Validates `in` and, when valid, fills `out`. On failure `out` is left unspecified.
inline StaticCheck run_static_check(const StaticInputs& in, StaticResult& out) {
  const double values[] = {in.b_m, in.h1_m, in.h2_m, in.fp_npm, in.a, in.psi_rad, in.rho_kgpm3, in.g_mps2, in.lambda};
  const char* names[] = {"b", "h1", "h2", "fp", "a", "psi", "rho", "g", "lambda"};
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(values[i])) {
      const bool total_only = !in.blocks_given && (i == 1 || i == 2);
      return {StaticError::not_finite, total_only ? "h" : names[i], "must be a finite number"};
    }
  }
  if (!std::isfinite(in.h_m())) return {StaticError::not_finite, "h", "must be a finite number"};
  if (!(in.b_m > 0.0)) return {StaticError::b_not_positive, "b", "must be > 0 m"};
  if (in.blocks_given) {
    if (!(in.h1_m > in.b_m)) return {StaticError::h1_not_above_b, "h1", "must be greater than b"};
    if (!(in.h2_m > in.b_m)) return {StaticError::h2_not_above_b, "h2", "must be greater than b"};
  }
  if (!(in.h_m() > in.b_m)) return {StaticError::h_not_above_b, "h", "must be greater than b"};
  if (!(in.fp_npm >= 0.0)) return {StaticError::fp_negative, "fp", "must be >= 0 N/m"};
  if (!(in.a >= 0.0 && in.a <= 1.0)) return {StaticError::a_out_of_range, "a", "must be in [0, 1]"};
  if (!(in.rho_kgpm3 > 0.0)) return {StaticError::rho_not_positive, "rho", "must be > 0 kg/m3"};
  if (!(in.g_mps2 > 0.0)) return {StaticError::g_not_positive, "g", "must be > 0 m/s2"};
  if (!(in.lambda > 0.0 && in.lambda < 1.0)) {
    return {StaticError::lambda_out_of_range, "lambda", "must be in (0, 1), exclusive"};
  }
  if (!spectrum_valid(in.spectrum)) {
    return {StaticError::spectrum_invalid, "spectrum", "needs p >= 1 and 0 < TB < TC < TD, all finite"};
  }
  const StaticResult r = detail::static_chain(in);
  if (std::isfinite(r.k) && std::isfinite(r.x_m) && (!(r.k > 0.0) || !(r.x_m > 0.0))) {
    return {StaticError::psi_too_large, "psi", "must leave K > 0 and X > 0 (psi < 4b(1 + (2 - a)f)/h)"};
  }
  // f may be 0; every other output is a positive size. Underflow to 0 is as useless as overflow to inf.
  const double positive_outputs[] = {r.weight_npm, r.k, r.x_m, r.period_s, r.x_eq_max_m, r.shape,
                                     r.allowable_pga_mps2, r.allowable_pga_g, r.se_mps2, r.sd_m};
  bool computable = std::isfinite(r.f);
  for (const double v : positive_outputs) computable = computable && std::isfinite(v) && v > 0.0;
  if (!computable) return {StaticError::result_not_finite, "", "too extreme: a result overflows or underflows"};
  out = r;
  return {};
}

inline StaticCheck validate_static_inputs(const StaticInputs& in) {
  StaticResult scratch;
  return run_static_check(in, scratch);
}

}  // namespace rockwatch::core
