// Coefficient of restitution r at the impact at x = 0 (SPEC §3). r is a kinetic-energy ratio: ẋ⁺ = √r ẋ⁻.
#pragma once

#include <cstdint>

#include "rockwatch/core/wall.hpp"

namespace rockwatch::core {

enum class RestitutionKind : std::uint8_t {
  ana = 0,      // paper eq. 17 (a velocity ratio used as an energy ratio; kept to reproduce the paper)
  exp = 1,      // 0.9 · r_ana, paper eq. 18, the default
  impulse = 2,  // rigorous impulse analysis including the top restraint: r = e²
  value = 3,    // a number in [0, 1] given by the user
};

struct Restitution {
  RestitutionKind kind = RestitutionKind::exp;
  double value = 0.0;  // used only when kind == value [-]
};

inline double r_ana(const WallParameters& w) {
  const double b2 = w.b_m * w.b_m, base = w.h1_m * w.h2_m + 2.0 * w.h1_m * w.h1_m;
  return (base - 3.0 * b2) / (base + 3.0 * b2);
}

inline double r_exp(const WallParameters& w) { return 0.9 * r_ana(w); }

// Velocity ratio e = (Jt − Vt)/(Jt + Vt) of the rigorous impulse analysis (SPEC §3).
inline double impulse_velocity_ratio(const WallParameters& w) {
  const WallProperties p = wall_properties(w);
  const double h1 = w.h1_m, h2 = w.h2_m, b = w.b_m;
  const double jt = p.j1_kgm / (h1 * h1) + p.j2_kgm / (h2 * h2) + (p.m1_kgpm + p.m2_kgpm) / 4.0;
  const double lever = b / h1 + b / (2.0 * h2);
  const double vt = p.m1_kgpm * b * b / (4.0 * h1 * h1) + p.m2_kgpm * lever * lever;
  return (jt - vt) / (jt + vt);
}

inline double r_impulse(const WallParameters& w) {
  const double e = impulse_velocity_ratio(w);
  return e * e;
}

// Energy ratio r for the chosen option; a user value is returned as given (validate with restitution_valid).
inline double restitution_energy_ratio(const WallParameters& w, const Restitution& r) {
  switch (r.kind) {
    case RestitutionKind::ana: return r_ana(w);
    case RestitutionKind::exp: return r_exp(w);
    case RestitutionKind::impulse: return r_impulse(w);
    case RestitutionKind::value: return r.value;
  }
  return r_exp(w);
}

inline bool restitution_valid(const Restitution& r) {
  return r.kind != RestitutionKind::value || (r.value >= 0.0 && r.value <= 1.0);
}

inline const char* restitution_name(RestitutionKind k) {
  switch (k) {
    case RestitutionKind::ana: return "ana";
    case RestitutionKind::exp: return "exp";
    case RestitutionKind::impulse: return "impulse";
    case RestitutionKind::value: return "value";
  }
  return "?";
}

}  // namespace rockwatch::core
