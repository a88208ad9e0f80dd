// The alarm's physical conditions evaluated on the fixed-point engine's state: the definitions of
// instability_indicators.hpp (their one home, with the prediction cap), in fixed point and with constant work.
//   y = s·x − x_inst,s,  ẏ = s·ẋ,  ρ = E/E_barrier = 1 + (ẏ/(ω x_i))² − (y/x_i)²  (linear model, SPEC §2),
//   IMMINENT by energy when moving, ẏ > 0 and ρ ≥ margin from |x| ≥ energy_min_x·x_inst (or ρ ≥ 1 and the
//   prediction ≤ the horizon); predicted time to x_inst under zero input
//   t = atanh(ω|y|/ẏ)/ω (0 once |x| ≥ x_inst; none below the barrier or moving inward), capped at
//   kInstabilityPredictionCap_s (instability_indicators.hpp).
//
// Why not that template instantiated on a fixed type: bit-identity of both engines with their references
// (`rockwatch simulate --arith double|fixed`, the golden files) forbids moving either one to the other's
// arithmetic, and the two are arranged differently on purpose:
//   - formats: the engine's 64-bit state is narrowed to Q1.30/Q3.28 first; ρ is formed from the scaled quantities
//     w = y/x_i and u = ẏ/(ω x_i) as 1 + u² − w² (Q7.24, bounded factors: see the scaling note below) where the
//     double form is 1 + (ẏ² − ω²y²)/(ω²x_i²), with other constants (1/x_i, 1/(ω x_i), 1/ω against x_i, ω, ω²,
//     1/(ω² x_i²)); the two round differently, so neither can take the other's form without changing its bits;
//   - constant work: z = −w/u and fixed_atanh are computed every sample and the result selected afterwards; the
//     double template computes atanh only when a prediction exists (instantiated on a fixed type it would give
//     data-dependent work);
//   - saturation: arithmetic_saturated is the stepper's report flag here, always false in floating point; the
//     prediction is also 0 once the stepper collapsed (in double, collapse implies |x| ≥ x_i anyway).
// What is shared: the definitions, AlarmConditions and the alarm behind them, kInstabilityPredictionCap_s, and the
// composition stepper → indicators → alarm (stepper_alarm_chain.hpp).
#pragma once

#include <cmath>
#include <cstdint>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/fixed_math.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/instability_indicators.hpp"

namespace rockwatch::core {

using RatioQ7_24 = Fixed<7, 24>;  // dimensionless ratios, |v| < 128, 6.0e-8
using TimeQ7_24 = Fixed<7, 24>;   // predicted times [s], < 128 s, 6.0e-8 s
using RateQ7_24 = Fixed<7, 24>;   // ω [1/s] and 1/(ω x_i) [s/m], 1/x_i [1/m]

struct FixedInstabilityConstants {
  LengthQ1_30 x_inst_m[2];       // per side (index side_index) [m]
  LengthQ1_30 x_warning_m[2];    // λ_w·x_inst [m]
  LengthQ1_30 x_energy_min_m[2];  // energy_min_x·x_inst: the energy margin's rule applies from here [m]
  RateQ7_24 inv_x_inst_pm[2];    // 1/x_inst [1/m]
  RateQ7_24 inv_omega_x_inst_spm[2];  // 1/(ω x_inst) [s/m]
  RateQ7_24 inv_omega_s[2];      // 1/ω [s]
  RatioQ7_24 energy_margin;      // IMMINENT when ρ ≥ margin [-]
  TimeQ7_24 horizon_s;           // ... or ρ ≥ 1 and the predicted time to x_inst ≤ this [s] (0 = off)
  TimeQ7_24 t_max_s;             // prediction cap [s]
};

// Initialisation time. ω_s² = −p4(s)/p1 of the linear model with ü = v̈ = 0 (the rate the wall leaves x_inst).
// Returns false when a constant does not fit its format (x_inst below 8 mm or above 1.9 m).
inline bool make_fixed_instability_constants(const StepperSetup<double>& s, const AlarmSettings& a,
                                             FixedInstabilityConstants& out) {
  bool ok = true;
  for (int i = 0; i < 2; ++i) {
    const double k = -(s.model.c4_fp[i] + s.model.c4_g * s.g_mps2) / s.model.c1;
    const double xi = s.x_inst_m[i];
    ok = ok && k > 0.0 && xi > 0.008 && xi < 1.9;
    const double omega = k > 0.0 ? std::sqrt(k) : 1.0;
    out.x_inst_m[i] = LengthQ1_30(xi);
    out.x_warning_m[i] = LengthQ1_30(a.lambda_warning * xi);
    out.x_energy_min_m[i] = LengthQ1_30(a.energy_min_x * xi);
    out.inv_x_inst_pm[i] = RateQ7_24(1.0 / xi);
    out.inv_omega_x_inst_spm[i] = RateQ7_24(1.0 / (omega * xi));
    out.inv_omega_s[i] = RateQ7_24(1.0 / omega);
    ok = ok && 1.0 / (omega * xi) < 100.0 && 1.0 / omega < 100.0;
  }
  out.energy_margin = RatioQ7_24(a.energy_margin);
  out.horizon_s = TimeQ7_24(a.imminent_horizon_s);
  out.t_max_s = TimeQ7_24(kInstabilityPredictionCap_s);
  return ok;
}

struct FixedInstabilityIndicators {
  AlarmConditions conditions;
  bool t_valid = false;             // a prediction exists
  TimeQ7_24 t_to_instability_s{};   // [s], when t_valid
  RatioQ7_24 energy_ratio{};        // E / E_barrier [-] (saturates at 128)
};

// Scaling and overflow: y/x_i and ẏ/(ω x_i) are below 128 for |x| < 2 m and |ẋ| < 8 m/s with the constants'
// limits above; their squares saturate at 128, which only ever means "far above the barrier"; z = ω|y|/ẏ is
// used only when ≤ 1 (ρ ≥ 1 and ẏ > 0), so the atanh argument is in [0, 1].
inline FixedInstabilityIndicators evaluate_instability(const FixedInstabilityConstants& c,
                                                       const FixedRockingStepper& stepper,
                                                       const FixedStepReport& report) {
  FixedInstabilityIndicators out;
  const Side side = stepper.side();
  const int i = side_index(side);
  const bool pos = side == Side::positive;
  // The engine's 64-bit state in the 32-bit formats: the indicators need ~1e-8 relative, not the engine's 1e-19.
  const LengthQ1_30 x = wide_convert<LengthQ1_30>(stepper.x_m());
  const SpeedQ3_28 xd = wide_convert<SpeedQ3_28>(stepper.xd_mps());
  const LengthQ1_30 sx = pos ? x : -x;
  const SpeedQ3_28 syd = pos ? xd : -xd;
  const LengthQ1_30 y = sx - c.x_inst_m[i];
  const RatioQ7_24 w = fixed_mul<RatioQ7_24>(y, c.inv_x_inst_pm[i]);             // y/x_i
  const RatioQ7_24 u = fixed_mul<RatioQ7_24>(syd, c.inv_omega_x_inst_spm[i]);   // ẏ/(ω x_i)
  out.energy_ratio = RatioQ7_24(1) + u * u - w * w;
  const LengthQ1_30 ax = abs(x);
  const bool moving = stepper.moving();
  AlarmConditions& k = out.conditions;
  k.moving = moving;
  k.over_warning_displacement = ax >= c.x_warning_m[i];
  k.over_instability_displacement = ax >= c.x_inst_m[i];
  k.over_collapse_displacement = stepper.collapsed();
  const bool outward = syd > SpeedQ3_28{};
  k.energy_over_barrier_outward =
      moving && outward && out.energy_ratio >= c.energy_margin && ax >= c.x_energy_min_m[i];
  k.input_invalid = report.input_invalid;
  k.arithmetic_saturated = report.saturated;

  // z = ω|y|/ẏ = −w/u; always formed (constant work), used only when it is a valid prediction.
  const bool predictable = outward && out.energy_ratio >= RatioQ7_24(1) && y < LengthQ1_30{};
  const FractionQ1_30 z = fixed_div<FractionQ1_30>(-w, predictable ? u : RatioQ7_24(1));
  TimeQ7_24 t = fixed_mul<TimeQ7_24>(fixed_atanh<TimeQ7_24>(z), c.inv_omega_s[i]);
  if (t > c.t_max_s) t = c.t_max_s;
  if (k.over_instability_displacement || k.over_collapse_displacement) {
    out.t_valid = true;
    out.t_to_instability_s = TimeQ7_24{};
  } else if (predictable) {
    out.t_valid = true;
    out.t_to_instability_s = t;
    // About to pass x_inst in free motion (instability_indicators.hpp; horizon 0 = off).
    if (moving && c.horizon_s > TimeQ7_24{} && t <= c.horizon_s) k.energy_over_barrier_outward = true;
  }
  return out;
}

}  // namespace rockwatch::core
