// Ensemble forecast of collapse (SPEC §10): the ground model's fit and the members.
#include "rockwatch/sim/ensemble_forecast.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rockwatch/sim/synthesis/random_stream.hpp"

namespace rockwatch::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxBlocks = 8;
constexpr double kOmegaMin_rps = 2.0 * kPi * 0.2;  // ω_g range [rad/s]: 0.2 Hz ...
constexpr double kInitialFilterClamp = 4.0;        // |y(0)| ≤ 4 (the record's ü now over σ_now)

bool in(double v, double lo, double hi) { return v >= lo && v <= hi; }

// The discretised ground filter, state s = (y, v, z, w), each step at h by symplectic Euler:
//   Kanai–Tajimi stage  v' = a v + b y + c ξ,  y' = y + h v'        (a = 1 − 2ζ_g ω_g h, b = −ω_g² h)
//   Clough–Penzien high-pass (when ω_f > 0)
//                       w' = w + h (y' − 2ζ_g ω_f w − ω_f² z),  z' = z + h w',  output u = y' − 2ζ_g ω_f w' − ω_f² z'
//   (without it, u = y'), ξ of unit variance, c chosen so that the stationary variance of u is exactly 1 (the discrete
//   Lyapunov equation, by doubling). The filter is linear, so its matrices are read off the step itself.
struct GroundFilter {
  static constexpr int n = 4;
  double h = 0.0, a = 0.0, b = 0.0, c = 1.0;
  double hp_k = 0.0, hp_w2 = 0.0;  // 2ζ ω_f, ω_f² (0: no high-pass)
  bool highpass = false;
  double gain[n] = {};             // E[s | u = 1]
  int dim = 2;                     // states used (4 with the high-pass)
  double Am[n][n] = {}, Gm[n] = {}, Cm[n] = {};  // s' = Am s + Gm ξ, u = Cm s
  double P_stat[n][n] = {};        // stationary covariance of s (with the unit-variance gain c)
  double var_w = 0.0;              // stationary variance of w = ∫u (the ground velocity per unit σ) [s²]
  double chol[n][n] = {};          // Cholesky factor of the covariance of s given u

  void step(double* s, double xi) const {
    s[1] = a * s[1] + b * s[0] + c * xi;
    s[0] += h * s[1];
    if (highpass) {
      s[3] += h * (s[0] - hp_k * s[3] - hp_w2 * s[2]);
      s[2] += h * s[3];
    }
  }
  double output(const double* s) const { return highpass ? s[0] - hp_k * s[3] - hp_w2 * s[2] : s[0]; }

  GroundFilter(double omega, double zeta, double omega_f, double h_s) : h(h_s) {
    a = 1.0 - 2.0 * zeta * omega * h;
    b = -omega * omega * h;
    highpass = omega_f > 0.0;
    hp_k = 2.0 * zeta * omega_f;
    hp_w2 = omega_f * omega_f;
    const int m = highpass ? 4 : 2;
    double A[n][n] = {}, P[n][n] = {}, C[n] = {};
    for (int i = 0; i < m; ++i) {
      double e[n] = {};
      e[i] = 1.0;
      C[i] = output(e);  // the output of a state (no step)
    }
    // A: the step of each unit state (no noise); G: the step of the zero state with ξ = 1. u' = C·s'.
    for (int i = 0; i < m; ++i) {
      double e[n] = {};
      e[i] = 1.0;
      step(e, 0.0);
      for (int r = 0; r < m; ++r) A[r][i] = e[r];
    }
    double G[n] = {};
    step(G, 1.0);
    for (int r = 0; r < m; ++r)
      for (int q = 0; q < m; ++q) P[r][q] = G[r] * G[q];
    for (int it = 0; it < 64; ++it) {  // Smith's doubling: P ← P + A P Aᵀ, A ← A²
      double AP[n][n] = {}, A2[n][n] = {};
      double norm = 0.0;
      for (int r = 0; r < m; ++r)
        for (int q = 0; q < m; ++q)
          for (int k = 0; k < m; ++k) {
            AP[r][q] += A[r][k] * P[k][q];
            A2[r][q] += A[r][k] * A[k][q];
          }
      for (int r = 0; r < m; ++r)
        for (int q = 0; q < m; ++q) {
          double apa = 0.0;
          for (int k = 0; k < m; ++k) apa += AP[r][k] * A[q][k];
          P[r][q] += apa;
        }
      for (int r = 0; r < m; ++r)
        for (int q = 0; q < m; ++q) {
          A[r][q] = A2[r][q];
          norm += std::fabs(A2[r][q]);
        }
      if (norm < 1e-18) break;
    }
    double var_u = 0.0, PC[n] = {};
    for (int r = 0; r < m; ++r) {
      for (int q = 0; q < m; ++q) PC[r] += P[r][q] * C[q];
      var_u += C[r] * PC[r];
    }
    c = 1.0 / std::sqrt(var_u);
    const double c2 = c * c;
    // With the scaled noise: P c², Var(u) = 1; given u: mean P Cᵀ u, covariance P − P Cᵀ C P.
    double Q[n][n] = {};
    for (int r = 0; r < m; ++r) gain[r] = PC[r] * c2;
    var_w = highpass ? P[3][3] * c2 : 0.0;
    for (int r = 0; r < m; ++r)
      for (int q = 0; q < m; ++q) Q[r][q] = P[r][q] * c2 - gain[r] * gain[q];
    dim = m;
    for (int r = 0; r < m; ++r) {
      Cm[r] = C[r];
      for (int q = 0; q < m; ++q) P_stat[r][q] = P[r][q] * c2;
    }
    {  // A and G of the scaled step (c now set)
      for (int i = 0; i < m; ++i) {
        double e[n] = {};
        e[i] = 1.0;
        step(e, 0.0);
        for (int r = 0; r < m; ++r) Am[r][i] = e[r];
      }
      double g0[n] = {};
      step(g0, 1.0);
      for (int r = 0; r < m; ++r) Gm[r] = g0[r];
    }
    for (int q = 0; q < m; ++q) {  // Cholesky, columns of a (numerically) zero pivot left at zero
      double d = Q[q][q];
      for (int k = 0; k < q; ++k) d -= chol[q][k] * chol[q][k];
      const double scale = std::fabs(P[q][q] * c2);
      if (!(d > 1e-12 * scale)) continue;
      chol[q][q] = std::sqrt(d);
      for (int r = q + 1; r < m; ++r) {
        double v = Q[r][q];
        for (int k = 0; k < q; ++k) v -= chol[r][k] * chol[q][k];
        chol[r][q] = v / chol[q][q];
      }
    }
  }
};

// A uniform variate of unit variance and zero mean: √3·(2u − 1). The filter's output is a weighted sum of many of
// them, Gaussian for every practical purpose, at a fraction of a normal variate's cost.
inline double unit_uniform(synthesis::RandomStream& rs) { return 1.7320508075688772 * (2.0 * rs.uniform() - 1.0); }

std::uint64_t member_seed(std::uint64_t seed, int member) {
  std::uint64_t s = seed;
  const std::uint64_t base = synthesis::splitmix64(s);
  return base + 0x9E3779B97F4A7C15ULL * (static_cast<std::uint64_t>(member) + 1);
}

// Linear interpolation between order statistics (Hyndman & Fan type 7) of v[0 .. n), reordering v.
double quantile(std::vector<double>& v, int n, double q) {
  const double pos = q * double(n - 1);
  const int lo = static_cast<int>(std::floor(pos));
  const int hi = std::min(lo + 1, n - 1);
  std::nth_element(v.begin(), v.begin() + lo, v.begin() + n);
  const double v_lo = v[static_cast<std::size_t>(lo)];
  if (hi == lo) return v_lo;
  const double v_hi = *std::min_element(v.begin() + lo + 1, v.begin() + n);
  return v_lo + (pos - double(lo)) * (v_hi - v_lo);
}

// Lower Cholesky factor of the symmetric m×m matrix S (a numerically zero pivot leaves its column at zero).
void cholesky(const double S[4][4], int m, double L[4][4]) {
  for (int r = 0; r < 4; ++r)
    for (int q = 0; q < 4; ++q) L[r][q] = 0.0;
  for (int q = 0; q < m; ++q) {
    double d = S[q][q];
    for (int k = 0; k < q; ++k) d -= L[q][k] * L[q][k];
    if (!(d > 1e-12 * std::fabs(S[q][q]) && d > 0.0)) continue;
    L[q][q] = std::sqrt(d);
    for (int r = q + 1; r < m; ++r) {
      double v = S[r][q];
      for (int k = 0; k < q; ++k) v -= L[r][k] * L[q][k];
      L[r][q] = v / L[q][q];
    }
  }
}

// The Kalman filter of the ground filter's model over the record's last window (SPEC §10 "The ground's phase"):
// from the stationary distribution at the window's start, one prediction per members' step h and one scalar
// observation u_k = ü(t_k)/σ(t_k) (linear interpolation of the record at t_k; clamped to ±6) of variance r.
void condition_on_record(const GroundFilter& f, const double* ug, std::size_t n, double dt_s, double window_s,
                         double sigma_now, double beta, double r, GroundModel& g) {
  const int m = f.dim;
  const double span = std::min(window_s, dt_s * double(n - 1));
  const int steps = static_cast<int>(std::floor(span / f.h + 1e-9));
  double mean[4] = {}, P[4][4] = {};
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) P[a][b] = f.P_stat[a][b];
  const double t_end = dt_s * double(n - 1);  // the forecast time on the record's clock
  for (int k = steps; k >= 0; --k) {
    const double t = t_end - double(k) * f.h;
    if (k != steps) {  // predict: mean ← A mean, P ← A P Aᵀ + G Gᵀ
      double nm[4] = {}, AP[4][4] = {}, NP[4][4] = {};
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) nm[a] += f.Am[a][b] * mean[b];
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b)
          for (int c = 0; c < m; ++c) AP[a][b] += f.Am[a][c] * P[c][b];
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) {
          for (int c = 0; c < m; ++c) NP[a][b] += AP[a][c] * f.Am[b][c];
          NP[a][b] += f.Gm[a] * f.Gm[b];
        }
      for (int a = 0; a < m; ++a) {
        mean[a] = nm[a];
        for (int b = 0; b < m; ++b) P[a][b] = NP[a][b];
      }
    }
    // observe
    const double pos = std::clamp(t / dt_s, 0.0, double(n - 1));
    const auto i0 = static_cast<std::size_t>(std::floor(pos));
    const std::size_t i1 = std::min(i0 + 1, n - 1);
    const double ug_t = ug[i0] + (pos - double(i0)) * (ug[i1] - ug[i0]);
    const double sigma_t = sigma_now * std::exp(beta * (t - t_end));
    const double obs = std::clamp(ug_t / sigma_t, -6.0, 6.0);
    double PC[4] = {}, S = r, pred = 0.0;
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b < m; ++b) PC[a] += P[a][b] * f.Cm[b];
      S += f.Cm[a] * PC[a];
      pred += f.Cm[a] * mean[a];
    }
    for (int a = 0; a < m; ++a) mean[a] += PC[a] / S * (obs - pred);
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) P[a][b] -= PC[a] * PC[b] / S;
  }
  for (int a = 0; a < m; ++a) {  // symmetric, as rounding may not keep it
    for (int b = 0; b < a; ++b) P[a][b] = P[b][a] = 0.5 * (P[a][b] + P[b][a]);
  }
  g.conditioned = true;
  for (int a = 0; a < 4; ++a) g.filter_mean[a] = a < m ? mean[a] : 0.0;
  cholesky(P, m, g.filter_chol);
}

}  // namespace

const char* forecast_settings_error(const ForecastSettings& s) {
  if (!(s.members >= kForecastMembersMin && s.members <= kForecastMembersMax)) return "members";
  if (!(s.horizon_s > 0.0 && s.horizon_s <= kForecastHorizonMax_s)) return "horizon_s";
  if (!in(s.step_s, 1e-4, 0.01)) return "step_s";
  if (!in(s.rest_speed_mps, 1e-7, 1e-2)) return "rest_speed_mps";
  if (!in(s.window_s, 0.5, 60.0)) return "window_s";
  if (!in(s.block_s, 0.1, s.window_s)) return "block_s";
  if (!(s.damping >= 0.05 && s.damping < 1.0)) return "damping";
  if (!in(s.highpass_ratio, 0.0, 0.5)) return "highpass_ratio";
  if (!(in(s.growth_min_per_s, -10.0, 0.0) && in(s.growth_max_per_s, 0.0, 2.0))) return "growth";
  if (!in(s.sigma_now_cap, 1.0, 10.0)) return "sigma_now_cap";
  if (!in(s.intensity_log_sigma, 0.0, 2.0)) return "intensity_log_sigma";
  if (!in(s.intensity_ramp_s, 0.0, 60.0)) return "intensity_ramp_s";
  if (!in(s.record_noise_var, 1e-6, 1.0)) return "record_noise_var";
  if (s.match_velocity && !(s.highpass_ratio > 0.0)) return "match_velocity";
  if (!in(s.default_sigma_fraction, 0.0, 0.5)) return "default_sigma_fraction";
  return nullptr;
}

GroundModel fit_ground_model(const double* ug, std::size_t n, double dt_s, const ForecastSettings& s) {
  GroundModel g;
  if (n < 2 || !(dt_s > 0.0)) return g;
  const std::size_t want = static_cast<std::size_t>(std::ceil(s.window_s / dt_s)) + 1;
  const std::size_t m = std::min(n, want);
  const double* w = ug + (n - m);
  const double span = dt_s * double(m - 1);
  g.window_used_s = span;
  // Dominant frequency: sign changes per second (zeros skipped).
  int crossings = 0;
  int last_sign = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const int sg = w[i] > 0.0 ? 1 : (w[i] < 0.0 ? -1 : 0);
    if (sg == 0) continue;
    if (last_sign != 0 && sg != last_sign) ++crossings;
    last_sign = sg;
  }
  g.zero_crossing_rate_hz = span > 0.0 ? double(crossings) / span : 0.0;
  {  // RMS of ü and of the velocity (trapezoid from 0, its mean removed) over the window
    double v = 0.0, sv = 0.0, svv = 0.0, saa = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      if (i > 0) v += 0.5 * (w[i - 1] + w[i]) * dt_s;
      sv += v;
      svv += v * v;
      saa += w[i] * w[i];
    }
    const double md = double(m);
    g.accel_rms_mps2 = std::sqrt(saa / md);
    g.velocity_rms_mps = std::sqrt(std::max(0.0, svv / md - (sv / md) * (sv / md)));
  }
  const double omega_max = 1.0 / s.step_s;  // ω_g h ≤ 1: the discrete filter stays accurate and stable
  g.omega_rps = std::clamp(kPi * g.zero_crossing_rate_hz, kOmegaMin_rps, omega_max);
  // Envelope: RMS in equal blocks ending at the forecast time, log-linear least squares against the blocks' centres.
  int nb = static_cast<int>(std::floor(span / s.block_s + 1e-9));
  nb = std::clamp(nb, 1, kMaxBlocks);
  const std::size_t per = std::max<std::size_t>(1, m / static_cast<std::size_t>(nb));
  double rms[kMaxBlocks] = {}, centre[kMaxBlocks] = {};
  double rms_max = 0.0;
  for (int b = 0; b < nb; ++b) {
    const std::size_t end = m - static_cast<std::size_t>(nb - 1 - b) * per;  // exclusive
    const std::size_t begin = end >= per ? end - per : 0;
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i) sum += w[i] * w[i];
    rms[b] = std::sqrt(sum / double(end - begin));
    centre[b] = -dt_s * (double(m - 1) - 0.5 * double(begin + end - 1));  // ≤ 0: seconds before the forecast time
    rms_max = std::max(rms_max, rms[b]);
  }
  if (!(rms_max > 0.0)) return g;  // a record of zeros: σ_now = 0, no ground to come
  if (nb == 1) {
    g.sigma_now_mps2 = rms[0];
    g.growth_per_s = 0.0;
    return g;
  }
  const double floor_rms = 1e-6 * rms_max;
  double st = 0.0, sl = 0.0, stt = 0.0, stl = 0.0;
  for (int b = 0; b < nb; ++b) {
    const double l = std::log(std::max(rms[b], floor_rms));
    st += centre[b];
    sl += l;
    stt += centre[b] * centre[b];
    stl += centre[b] * l;
  }
  const double nbd = double(nb);
  const double den = nbd * stt - st * st;
  const double beta = den > 0.0 ? (nbd * stl - st * sl) / den : 0.0;
  const double alpha = (sl - beta * st) / nbd;  // log σ at τ = 0 (the forecast time)
  g.growth_per_s = std::clamp(beta, s.growth_min_per_s, s.growth_max_per_s);
  // With β clamped, the level is refitted through the blocks' mean: log σ_now = mean(l) − β·mean(t).
  const double level = g.growth_per_s == beta ? alpha : (sl - g.growth_per_s * st) / nbd;
  g.sigma_now_mps2 = std::min(std::exp(level), s.sigma_now_cap * rms_max);
  return g;
}

void sample_unit_ground(double omega_g, const ForecastSettings& s, std::uint64_t seed, double* out, std::size_t n) {
  const GroundFilter f(omega_g, s.damping, s.highpass_ratio * omega_g, s.step_s);
  synthesis::RandomStream rs(seed);
  double g[GroundFilter::n];
  double zg[GroundFilter::n];
  for (double& v : zg) v = rs.normal();
  for (int r = 0; r < GroundFilter::n; ++r) {
    g[r] = 0.0;
    for (int k = 0; k <= r; ++k) g[r] += f.chol[r][k] * zg[k];
  }
  for (std::size_t i = 0; i < n; ++i) {
    f.step(g, unit_uniform(rs));
    out[i] = f.output(g);
  }
}

EnsembleForecaster::EnsembleForecaster(const core::WallParameters& wall, core::ModelKind model, double r_energy,
                                       double kappa, const ForecastSettings& settings)
    : settings_(settings) {
  if (const char* bad = forecast_settings_error(settings)) {
    throw std::invalid_argument(std::string("forecast setting out of range: ") + bad);
  }
  if (!(kappa >= 1.0) || !(r_energy >= 0.0 && r_energy <= 1.0)) {
    throw std::invalid_argument("forecast: kappa must be >= 1 and r in [0, 1]");
  }
  core::StepperOptions so;
  so.dt_s = settings.step_s;
  so.kappa = kappa;
  so.v_rest_mps = settings.rest_speed_mps;
  setup_ = core::make_stepper_setup(wall, model, r_energy, so);
  const double barrier = std::min(core::energy_barrier_jpm(setup_.model, core::Side::negative, wall.g_mps2),
                                  core::energy_barrier_jpm(setup_.model, core::Side::positive, wall.g_mps2));
  v_barrier_mps_ = std::sqrt(2.0 * barrier / setup_.model.c1);
  max_ratio_.assign(static_cast<std::size_t>(settings.members), 0.0);
  for (const core::Side side : {core::Side::negative, core::Side::positive}) {
    const int i = core::side_index(side);
    barrier_jpm_[i] = core::energy_barrier_jpm(setup_.model, side, wall.g_mps2);
    free_[i] = core::evaluate(setup_.model, side, 0.0, wall.g_mps2);
  }
}

double EnsembleForecaster::energy_ratio(double x_m, double xd_mps, int side) const {
  const int i = core::side_index(side > 0 ? core::Side::positive : core::Side::negative);
  return core::mechanical_energy(free_[i], x_m, xd_mps) / barrier_jpm_[i];
}

double EnsembleForecaster::x_over_x_inst(double x_m, int side) const {
  const int i = core::side_index(side > 0 ? core::Side::positive : core::Side::negative);
  return std::fabs(x_m) / setup_.x_inst_m[i];
}

ForecastResult EnsembleForecaster::forecast(const ForecastState& st, const double* ug, std::size_t n, double dt_s) {
  GroundModel g = fit_ground_model(ug, n, dt_s, settings_);
  if (settings_.condition_on_record && st.moving && g.sigma_now_mps2 > 0.0 && n >= 2 && dt_s > 0.0 &&
      !settings_.match_velocity) {
    const double omega_g = g.omega_rps > 0.0 ? g.omega_rps : kOmegaMin_rps;
    const GroundFilter f(omega_g, settings_.damping, settings_.highpass_ratio * omega_g, settings_.step_s);
    condition_on_record(f, ug, n, dt_s, settings_.window_s, g.sigma_now_mps2, g.growth_per_s,
                        settings_.record_noise_var, g);
  }
  return forecast(st, g);
}

ForecastResult EnsembleForecaster::forecast(const ForecastState& st, const GroundModel& ground) {
  ForecastResult res;
  res.ground = ground;
  if (!st.moving) {
    res.status = ForecastStatus::wall_at_rest;
    return res;
  }
  const ForecastSettings& s = settings_;
  core::RockingStepper<double> stepper;
  stepper.init(setup_);
  if (st.capacity_scale != 1.0 || st.stiffness_scale != 1.0) {
    stepper.set_capacity_scales(st.capacity_scale, st.stiffness_scale);
  }
  if (st.sqrt_r >= 0.0) stepper.set_sqrt_r(st.sqrt_r);
  const core::StepperSetup<double>& su = stepper.setup();
  const double x_inst_ref = std::min(su.x_inst_m[0], su.x_inst_m[1]);
  const double sigma_x = st.sigma_x_m >= 0.0 ? st.sigma_x_m : s.default_sigma_fraction * x_inst_ref;
  const double v_scale = v_barrier_mps_ * std::sqrt(st.capacity_scale * st.capacity_scale / st.stiffness_scale);
  const double sigma_v = st.sigma_xd_mps >= 0.0 ? st.sigma_xd_mps : s.default_sigma_fraction * v_scale;
  const double rho = std::clamp(st.rho_x_xd, -1.0, 1.0);
  const double rho_c = std::sqrt(std::max(0.0, 1.0 - rho * rho));

  const int n_steps = static_cast<int>(std::ceil(s.horizon_s / s.step_s - 1e-9));
  const double omega_g = ground.omega_rps > 0.0 ? ground.omega_rps : kOmegaMin_rps;
  const GroundFilter f(omega_g, s.damping, s.highpass_ratio * omega_g, s.step_s);
  const double decay = std::exp(ground.growth_per_s * s.step_s);
  double sigma_now = ground.sigma_now_mps2;
  if (s.match_velocity && f.highpass && ground.accel_rms_mps2 > 0.0 && f.var_w > 0.0) {
    // The model's velocity per unit σ is √var_w (its state w = ∫u): scale so that it matches the record's.
    sigma_now *= ground.velocity_rms_mps / (std::sqrt(f.var_w) * ground.accel_rms_mps2);
  }
  // The filter starts at the ground's value now (u(0) = ü(t)/σ_now, clamped), the rest of its state drawn given it.
  const double u_start =
      sigma_now > 0.0 ? std::clamp(st.ug_now_mps2 / sigma_now, -kInitialFilterClamp, kInitialFilterClamp) : 0.0;
  const double kappa_ratio = su.x_collapse_m[1] / su.x_inst_m[1];

  const int ramp_steps = s.intensity_ramp_s > 0.0 ? static_cast<int>(std::ceil(s.intensity_ramp_s / s.step_s - 1e-9)) : 0;
  int collapsed = 0;
  const int N = s.members;
  for (int m = 0; m < N; ++m) {
    synthesis::RandomStream rs(member_seed(s.seed, m));
    const double z1 = rs.normal(), z2 = rs.normal();
    const double x0 = st.x_m + sigma_x * z1;
    const double v0 = st.xd_mps + sigma_v * (rho * z1 + rho_c * z2);
    stepper.set_state(x0, v0, st.ug_now_mps2, 0.0);
    double g[GroundFilter::n];
    double zg[GroundFilter::n];
    for (double& v : zg) v = rs.normal();
    if (ground.conditioned) {
      for (int r = 0; r < GroundFilter::n; ++r) {
        g[r] = ground.filter_mean[r];
        for (int k = 0; k <= r; ++k) g[r] += ground.filter_chol[r][k] * zg[k];
      }
    } else {
      for (int r = 0; r < GroundFilter::n; ++r) {
        g[r] = f.gain[r] * u_start;
        for (int k = 0; k <= r; ++k) g[r] += f.chol[r][k] * zg[k];
      }
    }
    const double s_i = s.intensity_log_sigma;
    const double z_i = rs.normal();
    double env = sigma_now * std::exp(s_i * z_i - 0.5 * s_i * s_i);
    // With a ramp, the factor grows from 1 to its full spread over ramp_steps steps (the envelope's decay applied
    // to the base level; the factor multiplied in).
    double base = sigma_now;
    if (ramp_steps > 0) env = sigma_now;
    const int side0 = core::side_index(stepper.side());
    double max_ratio = std::fabs(x0) / su.x_inst_m[side0];
    bool fell = std::fabs(x0) >= su.x_collapse_m[side0];
    for (int k = 0; !fell && k < n_steps; ++k) {
      f.step(g, unit_uniform(rs));
      env *= decay;
      if (k < ramp_steps) {
        base *= decay;
        const double r = double(k + 1) / double(ramp_steps);
        env = base * std::exp(s_i * r * z_i - 0.5 * s_i * s_i * r * r);
      } else if (k == ramp_steps && ramp_steps > 0) {
        base *= decay;
        env = base * std::exp(s_i * z_i - 0.5 * s_i * s_i);
      }
      const auto report = stepper.step(env * f.output(g), 0.0);
      if (report.collapsed) {
        fell = true;
        break;
      }
      const double r = std::fabs(stepper.state().x_m) / su.x_inst_m[core::side_index(stepper.side())];
      if (r > max_ratio) max_ratio = r;
    }
    if (fell) {
      ++collapsed;
      max_ratio = kappa_ratio;
    }
    max_ratio_[static_cast<std::size_t>(m)] = max_ratio;
  }
  res.members = N;
  res.collapsed = collapsed;
  res.p_collapse = double(collapsed) / double(N);
  res.p_collapse_se = std::sqrt(res.p_collapse * (1.0 - res.p_collapse) / double(N));
  res.q50_max_x_over_x_inst = quantile(max_ratio_, N, 0.5);
  res.q90_max_x_over_x_inst = quantile(max_ratio_, N, 0.9);
  return res;
}

}  // namespace rockwatch::sim
