// Wall parameters (SPEC §1), their validation and the derived masses and inertias.
// Everything is per metre of wall length (L = 1 m): masses in kg/m, inertias in kg·m²/m, Fp in N/m.
// Initialisation-time code: always double, whatever scalar the stepper later runs on.
#pragma once

#include <cmath>
#include <cstdint>

namespace rockwatch::core {

struct WallParameters {
  double b_m = 0.10;           // wall thickness b [m]
  double h1_m = 1.75;          // bottom block height h1, ground hinge to mid-height hinge [m]
  double h2_m = 1.75;          // top block height h2, mid-height hinge to top restraint [m]
  double rho_kgpm3 = 1800.0;   // masonry density ρ [kg/m³]
  double fp_npm = 0.0;         // overburden Fp on the top of the wall [N per m of wall]
  double a = 0.0;              // overburden eccentricity while x < 0, as a fraction of b from the top hinge [-]
  double a_prime = 0.0;        // overburden eccentricity while x > 0, fraction of b [-]
  double g_mps2 = 9.81;        // gravity [m/s²]
};

// The design paper's wall (Table 2): b = 0.10, h1 = h2 = 1.75, ρ = 1800, a = a' = 0, Fp = 0.
constexpr WallParameters paper_wall() { return WallParameters{}; }

// Error codes are stable: new codes are appended, never renumbered.
enum class WallError : std::uint8_t {
  ok = 0,
  not_finite = 1,
  b_not_positive = 2,
  h1_not_above_b = 3,
  h2_not_above_b = 4,
  rho_not_positive = 5,
  fp_negative = 6,
  a_out_of_range = 7,
  a_prime_out_of_range = 8,
  g_not_positive = 9,
};

struct WallCheck {
  WallError code = WallError::ok;
  const char* field = "";     // the option/field at fault, e.g. "h1"
  const char* message = "";   // what was expected, e.g. "must be greater than b"
  constexpr bool ok() const { return code == WallError::ok; }
};

inline WallCheck validate_wall(const WallParameters& w) {
  const double values[] = {w.b_m, w.h1_m, w.h2_m, w.rho_kgpm3, w.fp_npm, w.a, w.a_prime, w.g_mps2};
  const char* names[] = {"b", "h1", "h2", "rho", "fp", "a", "a_prime", "g"};
  for (int i = 0; i < 8; ++i) {
    if (!std::isfinite(values[i])) return {WallError::not_finite, names[i], "must be a finite number"};
  }
  if (!(w.b_m > 0.0)) return {WallError::b_not_positive, "b", "must be > 0 m"};
  if (!(w.h1_m > w.b_m)) return {WallError::h1_not_above_b, "h1", "must be greater than b"};
  if (!(w.h2_m > w.b_m)) return {WallError::h2_not_above_b, "h2", "must be greater than b"};
  if (!(w.rho_kgpm3 > 0.0)) return {WallError::rho_not_positive, "rho", "must be > 0 kg/m3"};
  if (!(w.fp_npm >= 0.0)) return {WallError::fp_negative, "fp", "must be >= 0 N/m"};
  if (!(w.a >= 0.0 && w.a <= 1.0)) return {WallError::a_out_of_range, "a", "must be in [0, 1]"};
  if (!(w.a_prime >= 0.0 && w.a_prime <= 1.0)) return {WallError::a_prime_out_of_range, "a_prime", "must be in [0, 1]"};
  if (!(w.g_mps2 > 0.0)) return {WallError::g_not_positive, "g", "must be > 0 m/s2"};
  return {};
}

// Masses and centroidal inertias of the two blocks (SPEC §1).
struct WallProperties {
  double m1_kgpm = 0.0;    // bottom block mass ρ b h1 [kg/m]
  double m2_kgpm = 0.0;    // top block mass ρ b h2 [kg/m]
  double j1_kgm = 0.0;     // bottom block inertia m1 (b² + h1²)/12 [kg·m²/m]
  double j2_kgm = 0.0;     // top block inertia m2 (b² + h2²)/12 [kg·m²/m]
  double d_minus = 1.0;    // overburden lever factor while x < 0: 1 − a [-]
  double d_plus = 1.0;     // overburden lever factor while x > 0: 1 − a' [-]
};

inline WallProperties wall_properties(const WallParameters& w) {
  WallProperties p;
  p.m1_kgpm = w.rho_kgpm3 * w.b_m * w.h1_m;
  p.m2_kgpm = w.rho_kgpm3 * w.b_m * w.h2_m;
  p.j1_kgm = p.m1_kgpm * (w.b_m * w.b_m + w.h1_m * w.h1_m) / 12.0;
  p.j2_kgm = p.m2_kgpm * (w.b_m * w.b_m + w.h2_m * w.h2_m) / 12.0;
  p.d_minus = 1.0 - w.a;
  p.d_plus = 1.0 - w.a_prime;
  return p;
}

// Side of the wall: +1 while x > 0, −1 while x < 0; at x = 0 the side the wall is entering. Never 0.
enum class Side : std::int8_t { negative = -1, positive = 1 };

constexpr double sign_of(Side s) { return s == Side::positive ? 1.0 : -1.0; }
constexpr Side opposite(Side s) { return s == Side::positive ? Side::negative : Side::positive; }

}  // namespace rockwatch::core
