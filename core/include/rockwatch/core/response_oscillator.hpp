// Damped single-degree-of-freedom oscillator for response spectra, exact for ground acceleration that is linear
// between samples (the project's input convention, SPEC §4): the Nigam–Jennings (1969) recurrence.
//
//   ü + 2ζω u̇ + ω² u = −a_g(t)        u: displacement relative to the ground [m]
//
//   [u; u̇]_{k+1} = A [u; u̇]_k + B [a_g,k; a_g,k+1]
//
// A and B depend only on (ω, ζ, Δt) and are computed once by init(); a step is eight multiply-adds. Because the
// recurrence is the exact solution for piecewise-linear input, its accuracy does not depend on T/Δt: a period far
// below the sample interval needs neither sub-stepping nor a PGA substitute (the stiff oscillator follows
// u ≈ −a_g/ω², so ω²·max|u| tends to the peak sample, i.e. the PGA).
//
// Peaks are taken at the samples. Between samples |u| can be slightly larger (by O((ωΔt)²) relative near a peak);
// spectra conventionally report the sampled peak. Header-only, no heap, no exceptions, no I/O.
#pragma once

#include <cmath>
#include <cstdint>

namespace rockwatch::core {

inline constexpr double kDefaultDampingRatio = 0.05;  // 5 % of critical, the design-spectrum convention

// Stable codes; new ones are appended.
enum class OscillatorStatus : std::uint8_t {
  ok = 0,
  period_not_positive = 1,   // period ≤ 0 or not finite
  damping_out_of_range = 2,  // ζ outside [0, 1) or not finite (the recurrence is the underdamped solution)
  dt_not_positive = 3,       // Δt ≤ 0 or not finite
  not_computable = 4,        // valid inputs whose coefficients overflow (e.g. T = 1e-300 s)
};

inline const char* oscillator_status_text(OscillatorStatus s) {
  switch (s) {
    case OscillatorStatus::ok: return "ok";
    case OscillatorStatus::period_not_positive: return "period must be a finite value > 0 s";
    case OscillatorStatus::damping_out_of_range: return "damping ratio must be in [0, 1)";
    case OscillatorStatus::dt_not_positive: return "sample interval must be a finite value > 0 s";
    case OscillatorStatus::not_computable: return "period and sample interval give coefficients that overflow";
  }
  return "?";
}

// One step of the recurrence: u' = a11 u + a12 v + b11 a0 + b12 a1, v' = a21 u + a22 v + b21 a0 + b22 a1.
struct OscillatorCoefficients {
  double a11 = 0.0, a12 = 0.0, a21 = 0.0, a22 = 0.0;  // free response (state transition)
  double b11 = 0.0, b12 = 0.0, b21 = 0.0, b22 = 0.0;  // forced response to a_g at the start / end of the step
};

namespace detail {

// Below this ωΔt the closed form loses digits: B is O(Δt²) while its terms are O(1/ω²) and O(ζ/(ω³Δt)), a
// cancellation of up to ~max(1, 2ζ/(ωΔt))/(ωΔt)² (2e5 for T = 4 s at 200 Hz and ζ = 5 %). There the same exact
// expressions are summed as power series in the dimensionless step, where no cancellation occurs. Near the switch
// both agree to a few 1e-14 (tested).
inline constexpr double kSeriesBelowOmegaDt = 0.5;

// The transition over a dimensionless step θ = ωΔt for the scaled state z = [ω u; u̇]:
//   dz/ds = K z + [0; −1] a/ω,  K = [[0, 1], [−1, −2ζ]],  s = ω t.
// exp(Kθ) = Σ (Kθ)^n/n!; the response to a_g linear in the step needs Σ (Kθ)^n/(n+1)! (its start value) and
// Σ (Kθ)^n/(n+2)! (its slope). With ‖Kθ‖ ≤ 1.5 for θ ≤ 0.5, 30 terms are below double rounding.
inline OscillatorCoefficients series_coefficients(double omega, double zeta, double dt) {
  const double theta = omega * dt;
  // X = Kθ; P = X^n / n! carried from term to term.
  const double x11 = 0.0, x12 = theta, x21 = -theta, x22 = -2.0 * zeta * theta;
  double p11 = 1.0, p12 = 0.0, p21 = 0.0, p22 = 1.0;
  double e11 = 0.0, e12 = 0.0, e21 = 0.0, e22 = 0.0;  // exp(X)
  // Only the second column of the φ sums is needed (the input enters the velocity equation).
  double f0_1 = 0.0, f0_2 = 0.0;  // Σ X^n/(n+1)! · [0; 1] − Σ X^n/(n+2)! · [0; 1]: weight of a_g at the step start
  double f1_1 = 0.0, f1_2 = 0.0;  // Σ X^n/(n+2)! · [0; 1]: weight of a_g at the step end
  constexpr int kTerms = 30;
  for (int n = 0; n < kTerms; ++n) {
    const double dn = static_cast<double>(n);
    e11 += p11;
    e12 += p12;
    e21 += p21;
    e22 += p22;
    // X^n/(n+1)! − X^n/(n+2)! = (X^n/n!)·1/(n+2), and X^n/(n+2)! = (X^n/n!)·1/((n+1)(n+2)): no subtraction.
    const double w_start = 1.0 / (dn + 2.0);
    const double w_end = w_start / (dn + 1.0);
    f0_1 += p12 * w_start;
    f0_2 += p22 * w_start;
    f1_1 += p12 * w_end;
    f1_2 += p22 * w_end;
    // P ← P·X/(n+1)
    const double inv = 1.0 / (dn + 1.0);
    const double q11 = (p11 * x11 + p12 * x21) * inv, q12 = (p11 * x12 + p12 * x22) * inv;
    const double q21 = (p21 * x11 + p22 * x21) * inv, q22 = (p21 * x12 + p22 * x22) * inv;
    p11 = q11;
    p12 = q12;
    p21 = q21;
    p22 = q22;
  }
  // Back to (u, u̇): u = z1/ω. The forcing term is θ·φ·[0; −1]·a/ω in z.
  OscillatorCoefficients c;
  c.a11 = e11;
  c.a12 = e12 / omega;
  c.a21 = e21 * omega;
  c.a22 = e22;
  const double scale = theta / omega;  // = Δt
  c.b11 = -(f0_1 * scale) / omega;
  c.b12 = -(f1_1 * scale) / omega;
  c.b21 = -f0_2 * scale;
  c.b22 = -f1_2 * scale;
  return c;
}

// Nigam & Jennings (1969), "Calculation of response spectra from strong-motion earthquake records", BSSA 59(2).
inline OscillatorCoefficients closed_form_coefficients(double omega, double zeta, double dt) {
  const double root = std::sqrt(1.0 - zeta * zeta);
  const double omega_d = omega * root;
  const double e = std::exp(-zeta * omega * dt);
  const double s = std::sin(omega_d * dt);
  const double c = std::cos(omega_d * dt);
  const double z_r = zeta / root;
  OscillatorCoefficients k;
  k.a11 = e * (z_r * s + c);
  k.a12 = e * s / omega_d;
  k.a21 = -omega / root * e * s;
  k.a22 = e * (c - z_r * s);

  const double w2 = omega * omega;
  const double t1 = (2.0 * zeta * zeta - 1.0) / (w2 * dt);
  const double t2 = 2.0 * zeta / (w2 * omega * dt);
  k.b11 = e * ((t1 + zeta / omega) * s / omega_d + (t2 + 1.0 / w2) * c) - t2;
  k.b12 = -e * (t1 * s / omega_d + t2 * c) - 1.0 / w2 + t2;
  k.b21 = e * ((t1 + zeta / omega) * (c - z_r * s) - (t2 + 1.0 / w2) * (omega_d * s + zeta * omega * c)) +
          1.0 / (w2 * dt);
  k.b22 = -e * (t1 * (c - z_r * s) - t2 * (omega_d * s + zeta * omega * c)) - 1.0 / (w2 * dt);
  return k;
}

inline bool all_finite(const OscillatorCoefficients& c) {
  return std::isfinite(c.a11) && std::isfinite(c.a12) && std::isfinite(c.a21) && std::isfinite(c.a22) &&
         std::isfinite(c.b11) && std::isfinite(c.b12) && std::isfinite(c.b21) && std::isfinite(c.b22);
}

}  // namespace detail

// Caller-owned state: init() once per (period, damping, Δt), reset() at the first sample, step() per sample.
class ResponseOscillator {
 public:
  static constexpr double kTwoPi = 6.283185307179586476925286766559;

  // Validates and computes A, B. On failure the oscillator is left uninitialised (step() does nothing).
  OscillatorStatus init(double period_s, double damping, double dt_s) {
    ready_ = false;
    if (!(std::isfinite(period_s) && period_s > 0.0)) return OscillatorStatus::period_not_positive;
    if (!(std::isfinite(damping) && damping >= 0.0 && damping < 1.0)) return OscillatorStatus::damping_out_of_range;
    if (!(std::isfinite(dt_s) && dt_s > 0.0)) return OscillatorStatus::dt_not_positive;
    const double omega = kTwoPi / period_s;
    if (!std::isfinite(omega * omega)) return OscillatorStatus::not_computable;
    const OscillatorCoefficients c = omega * dt_s < detail::kSeriesBelowOmegaDt
                                         ? detail::series_coefficients(omega, damping, dt_s)
                                         : detail::closed_form_coefficients(omega, damping, dt_s);
    if (!detail::all_finite(c)) return OscillatorStatus::not_computable;
    k_ = c;
    period_s_ = period_s;
    damping_ = damping;
    dt_s_ = dt_s;
    omega_rad_s_ = omega;
    two_zeta_omega_ = 2.0 * damping * omega;
    omega_sq_ = omega * omega;
    ready_ = true;
    reset(0.0);
    return OscillatorStatus::ok;
  }

  // At rest (u = u̇ = 0) at a sample where the ground acceleration is ag_first; peaks cleared.
  void reset(double ag_first_mps2) {
    u_m_ = 0.0;
    v_mps_ = 0.0;
    ag_prev_mps2_ = ag_first_mps2;
    max_abs_u_m_ = 0.0;
    max_abs_acc_mps2_ = 0.0;  // at rest the absolute acceleration ü + a_g = −2ζωu̇ − ω²u is 0
  }

  // Advances one sample interval to the next input sample.
  void step(double ag_next_mps2) {
    if (!ready_) return;
    // The input terms first: they do not depend on the previous step, so the serial chain from one step to the
    // next is one multiply and two adds.
    const double u = (k_.b11 * ag_prev_mps2_ + k_.b12 * ag_next_mps2) + (k_.a11 * u_m_ + k_.a12 * v_mps_);
    const double v = (k_.b21 * ag_prev_mps2_ + k_.b22 * ag_next_mps2) + (k_.a21 * u_m_ + k_.a22 * v_mps_);
    u_m_ = u;
    v_mps_ = v;
    ag_prev_mps2_ = ag_next_mps2;
    // Plain comparisons, not std::fmax: its NaN rules cost a call or a branch per step, and the input is finite.
    const double abs_u = std::fabs(u);
    max_abs_u_m_ = abs_u > max_abs_u_m_ ? abs_u : max_abs_u_m_;
    // From the equation of motion, ü + a_g = −(2ζω u̇ + ω² u): no acceleration state is needed.
    const double abs_acc = std::fabs(two_zeta_omega_ * v + omega_sq_ * u);
    max_abs_acc_mps2_ = abs_acc > max_abs_acc_mps2_ ? abs_acc : max_abs_acc_mps2_;
  }

  bool ready() const { return ready_; }
  double period_s() const { return period_s_; }
  double damping() const { return damping_; }
  double dt_s() const { return dt_s_; }
  double omega_rad_s() const { return omega_rad_s_; }
  const OscillatorCoefficients& coefficients() const { return k_; }

  double displacement_m() const { return u_m_; }   // u, relative to the ground
  double velocity_mps() const { return v_mps_; }   // u̇, relative
  // Absolute acceleration ü + a_g at the current sample.
  double absolute_acceleration_mps2() const { return -(two_zeta_omega_ * v_mps_ + omega_sq_ * u_m_); }

  double sd_m() const { return max_abs_u_m_; }                   // spectral displacement max|u|
  double psv_mps() const { return omega_rad_s_ * max_abs_u_m_; }  // pseudo-spectral velocity ω·Sd
  double psa_mps2() const { return omega_sq_ * max_abs_u_m_; }    // pseudo-spectral acceleration ω²·Sd
  double max_abs_acceleration_mps2() const { return max_abs_acc_mps2_; }  // max |ü + a_g|

 private:
  OscillatorCoefficients k_{};
  double period_s_ = 0.0, damping_ = 0.0, dt_s_ = 0.0;
  double omega_rad_s_ = 0.0, two_zeta_omega_ = 0.0, omega_sq_ = 0.0;
  double u_m_ = 0.0, v_mps_ = 0.0, ag_prev_mps2_ = 0.0;
  double max_abs_u_m_ = 0.0, max_abs_acc_mps2_ = 0.0;
  bool ready_ = false;
};

}  // namespace rockwatch::core
