// Consistency of the wall observer (core/wall_observer.hpp): Monte-Carlo over sensor-noise seeds, walls, records
// and sensor sets. A true wall (its own r, b, overburden) is simulated by sim::analyse (keep_history) — or, for the
// NEES bands, drawn from the filter's own model (its prior on κc, κk, √r and the offset, its process noise: the
// nominal stepper with the drawn scales, model_truth) — and its sensors synthesised (sim::synthesize_wall_sensors); the nominal wall (paper wall, r_exp) is run fused with them exactly as
// sim::analyse runs it (sub-steps of 1 ms, samples pushed when due, the observer after every sub-step), and the
// estimation errors are compared with the observer's covariance:
//   - the normalised estimation error squared (NEES) of x, ẋ, r and x_inst, averaged over N runs, lies in the 95 %
//     band of χ²(N)/N (each a scalar, d = 1);
//   - r̂ is within 3 σ_r of the true r at the end of every run.
// Records are short (3–4 s of a suite record, or synthetic pulses) so that the suite stays within its budget under
// the sanitizers.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/synthesis/random_stream.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;

namespace {

constexpr double kMaxStep = 0.001;

// Set `set`, component 0 (X) or 1 (Y), of the shipped suite from t0_s for len_s, scaled to pga_g.
sim::GroundMotion suite_window(int set, int component, double t0_s, double len_s, double pga_g) {
  const records::SuiteRecordFile f = records::read_suite_record(records::suite_set_path(ROCKWATCH_SUITE_DIR, set));
  sim::GroundMotion m;
  m.dt_s = f.dt_s;
  const std::vector<double>& all = f.components_mps2[static_cast<std::size_t>(component)];
  const auto k0 = static_cast<std::size_t>(t0_s / f.dt_s);
  const auto n = std::min(all.size() - k0, static_cast<std::size_t>(len_s / f.dt_s));
  m.ug_mps2.assign(all.begin() + static_cast<std::ptrdiff_t>(k0), all.begin() + static_cast<std::ptrdiff_t>(k0 + n));
  // Taper the first and last 0.2 s so that the window starts and ends quietly.
  const auto taper = static_cast<std::size_t>(0.2 / f.dt_s);
  for (std::size_t i = 0; i < taper && i < n; ++i) {
    const double w = double(i) / double(taper);
    m.ug_mps2[i] *= w;
    m.ug_mps2[n - 1 - i] *= w;
  }
  const double factor = pga_g * 9.81 / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  return m;
}

sim::GroundMotion real_record(const char* name, double pga_g) {
  const records::Record r = records::read_record(std::string(ROCKWATCH_TEST_DATA_DIR) + "/records/" + name);
  sim::GroundMotion m;
  m.dt_s = r.dt_s;
  m.ug_mps2 = r.horizontal_mps2;
  const double factor = pga_g * 9.81 / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  return m;
}

core::Restitution restitution_value(double r) {
  core::Restitution x;
  x.kind = core::RestitutionKind::value;
  x.value = r;
  return x;
}

struct Scenario {
  core::WallParameters true_wall;
  double true_r;
  sim::GroundMotion motion;
  sim::SensorModel sensors;
  core::ObserverOptions observer{};
  // A truth inside the filter's model class (the textbook condition of a NEES test): the nominal wall's stepper with
  // the capacity scales κc, κk (SPEC §9) and √r of the truth (true_wall is then the nominal wall, for the sensors).
  bool in_model = false;
  double kappa_c = 1.0, kappa_k = 1.0;
  // … and the filter's own model error: a white acceleration of this σ, one draw per sub-step while the wall rocks
  // (the filter's process noise: q = σ²·[h⁴/4 h³/2; h³/2 h²]) [m/s²].
  double truth_process_mps2 = 0.0;
  std::uint64_t truth_seed = 1;
};

// The nominal wall's stepper setup (paper wall, r_exp): the filter's model, and the in-model truth's.
core::StepperSetup<double> nominal_setup(double dt_s) {
  const core::WallParameters nominal = core::paper_wall();
  const int n = core::substeps_per_sample(dt_s, kMaxStep);
  core::StepperOptions so;
  so.dt_s = dt_s / double(n);
  return core::make_stepper_setup(nominal, core::ModelKind::linear,
                                  core::restitution_energy_ratio(nominal, core::Restitution{}), so);
}

// The in-model truth: the nominal stepper with the scenario's κc, κk and √r, stepped as sim::analyse steps it (rows
// at t = 0 and after every sub-step), its history kept for the sensor synthesis.
sim::AnalysisResult model_truth(const Scenario& sc) {
  sim::AnalysisResult res;
  const std::vector<double>& ug = sc.motion.ug_mps2;
  const int n = core::substeps_per_sample(sc.motion.dt_s, kMaxStep);
  const double h = sc.motion.dt_s / double(n);
  core::RockingStepper<double> stepper;
  stepper.init(nominal_setup(sc.motion.dt_s));
  stepper.set_sqrt_r(std::sqrt(sc.true_r));
  stepper.set_capacity_scales(sc.kappa_c, sc.kappa_k);
  stepper.reset(ug[0], 0.0);
  auto row = [&](double t, double u) {
    const core::MotionState<double>& m = stepper.state();
    res.history.push_back(sim::HistoryRow{t, u, 0.0, m.x_m, m.xd_mps, m.xdd_mps2, -m.x_m / sc.true_wall.h1_m,
                                          m.x_m / sc.true_wall.h2_m, stepper.side() == core::Side::positive ? 1 : -1});
    res.max_abs_x_m = std::fmax(res.max_abs_x_m, std::fabs(m.x_m));
  };
  row(0.0, ug[0]);
  sim::synthesis::RandomStream noise(sc.truth_seed);
  for (std::size_t k = 0; k + 1 < ug.size() && !stepper.collapsed(); ++k) {
    for (int j = 1; j <= n && !stepper.collapsed(); ++j) {
      const double u = j == n ? ug[k + 1] : ug[k] + (ug[k + 1] - ug[k]) * double(j) / double(n);
      const core::StepReport<double> rep = stepper.step(u, 0.0);
      res.n_impacts += rep.impacts_counted;
      if (sc.truth_process_mps2 > 0.0 && stepper.moving() && !stepper.collapsed() && rep.impacts_total == 0) {
        const double w = sc.truth_process_mps2 * noise.normal();
        const core::MotionState<double> m = stepper.state();
        const double x1 = m.x_m + 0.5 * h * h * w;
        // Never across the hinge (an impact the stepper would not see).
        if ((x1 > 0.0) == (m.x_m > 0.0) && x1 != 0.0) stepper.set_state(x1, m.xd_mps + h * w, u, 0.0);
      }
      row(double(k * std::size_t(n) + std::size_t(j)) * h, u);
    }
  }
  res.collapsed = stepper.collapsed();
  return res;
}

// What one fused run gives: the errors and variances at a checkpoint and at the end.
struct RunOutcome {
  bool truth_collapsed = false;
  bool have_checkpoint = false;
  double nees_x = 0.0, nees_v = 0.0;  // at the checkpoint (both walls rocking)
  double r_hat = 0.0, sigma_r = 0.0, r_true = 0.0;
  double nees_r = 0.0;
  double x_inst_hat = 0.0, sigma_x_inst = 0.0, x_inst_true = 0.0, nees_x_inst = 0.0;
  long impacts = 0;
};

RunOutcome fused_run(const Scenario& sc) {
  RunOutcome out;
  // The truth.
  sim::AnalysisOptions to;
  to.restitution = restitution_value(sc.true_r);
  to.keep_history = true;
  to.max_step_s = kMaxStep;
  const sim::AnalysisResult truth = sc.in_model ? model_truth(sc) : sim::analyse(sc.true_wall, sc.motion, to);
  out.truth_collapsed = truth.verdict_collapse();
  const std::vector<core::WallSensorSample> samples =
      sim::synthesize_wall_sensors(sc.true_wall, truth, sc.motion.dt_s, sc.sensors);
  // The nominal wall, fused: the loop of sim::analyse.
  const core::WallParameters nominal = core::paper_wall();
  const int n = core::substeps_per_sample(sc.motion.dt_s, kMaxStep);
  const core::StepperSetup<double> setup = nominal_setup(sc.motion.dt_s);
  core::RockingStepper<double> stepper;
  stepper.init(setup);
  core::WallObserver<core::RockingStepper<double>> observer;
  CHECK(observer.init(sc.observer, setup, nominal) == core::ObserverError::ok);
  const std::vector<double>& ug = sc.motion.ug_mps2;
  stepper.reset(ug[0], 0.0);
  const std::int64_t step_us = std::llround(sc.motion.dt_s * 1e6);
  std::size_t next = 0;
  const std::size_t checkpoint_row = truth.history.size() * 2 / 3;
  for (std::size_t k = 0; k + 1 < ug.size() && !stepper.collapsed(); ++k) {
    const std::int64_t t_us = core::observed_step_end_us(double(k) * sc.motion.dt_s, sc.motion.dt_s);
    while (next < samples.size() && samples[next].utime_us <= t_us) observer.push(samples[next++]);
    for (int j = 1; j <= n; ++j) {
      const double u = j == n ? ug[k + 1] : ug[k] + (ug[k + 1] - ug[k]) * double(j) / double(n);
      const core::StepReport<double> rep = stepper.step(u, 0.0);
      out.impacts += rep.impacts_counted;
      const std::int64_t end_us = t_us - (step_us * (n - j)) / n;
      observer.after_step(stepper, rep, u, 0.0, end_us, step_us / n);
      const std::size_t row = k * std::size_t(n) + std::size_t(j);
      if (!out.have_checkpoint && row >= checkpoint_row && row < truth.history.size() && stepper.moving() &&
          truth.history[row].x_m != 0.0) {
        const sim::HistoryRow& tr = truth.history[row];
        const auto& p = observer.covariance();
        const double ex = stepper.state().x_m - tr.x_m, ev = stepper.state().xd_mps - tr.xd_mps;
        if (p(0, 0) > 0.0 && p(1, 1) > 0.0) {
          out.nees_x = ex * ex / p(0, 0);
          out.nees_v = ev * ev / p(1, 1);
          out.have_checkpoint = true;
        }
      }
    }
  }
  out.r_hat = observer.r_estimate();
  out.sigma_r = observer.sigma_r_filter();
  out.r_true = sc.true_r;
  const double er = out.r_hat - out.r_true;
  out.nees_r = out.sigma_r > 0.0 ? er * er / (out.sigma_r * out.sigma_r) : 1e9;
  out.x_inst_hat = observer.x_inst_estimate_m();
  // The filter's own σ: its consistency (the model's form is added only to what is published, SPEC §11).
  out.sigma_x_inst = observer.sigma_x_inst_filter_m();
  out.x_inst_true = core::x_inst_m(core::model_constants(sc.true_wall, core::ModelKind::linear), core::Side::positive,
                                   sc.true_wall.g_mps2) *
                    (sc.in_model ? sc.kappa_c / sc.kappa_k : 1.0);
  const double ei = out.x_inst_hat - out.x_inst_true;
  out.nees_x_inst = ei * ei / (out.sigma_x_inst * out.sigma_x_inst);
  return out;
}

// The 95 % band of the mean of N independent χ²(1) variables: χ²(N)/N, by the Wilson–Hilferty approximation.
void chi2_band(int n, double& lo, double& hi) {
  const double a = 2.0 / (9.0 * double(n));
  lo = std::pow(1.0 - a - 1.959964 * std::sqrt(a), 3.0);
  hi = std::pow(1.0 - a + 1.959964 * std::sqrt(a), 3.0);
}

}  // namespace

TEST_GROUP(ObserverConsistency){};

namespace {

// A true wall: the paper wall, b × 0.9 and × 1.1, and with a light overburden (c and k both ≈ 8 % up).
core::WallParameters true_wall(int i) {
  core::WallParameters w = core::paper_wall();
  if (i == 1) w.b_m *= 0.9;
  if (i == 2) w.b_m *= 1.1;
  if (i == 3) w.fp_npm = 300.0;
  return w;
}

struct Tally {
  int n = 0, n_state = 0;
  double x = 0.0, v = 0.0, r = 0.0, x_inst = 0.0;
  int r_outside_3sigma = 0;
  double worst_r_sigmas = 0.0;
  // Runs with a NaN or infinite r̂, σ_r, x̂_inst or NEES (issue 42: `NaN > 3.0` is false and fmax drops a NaN, so
  // such runs were never counted): each also counts as outside 3 σ.
  int non_finite = 0;
  // Learning r: the largest σ_r and |r̂ − r| at the end of a run, and the sum of |r̂ − r|.
  double max_sigma_r = 0.0, max_abs_r_error = 0.0, sum_abs_r_error = 0.0;
  // Every run's NEES (x, ẋ of the runs that reached the checkpoint), for the counts of NeesQuantilesOverSixBlocks.
  std::vector<double> all_x, all_v, all_r, all_x_inst;

  // One run's NEES (x, ẋ only when it reached the checkpoint) and its final |r̂ − r| in σ.
  void add(const RunOutcome& o) {
    ++n;
    r += o.nees_r;
    x_inst += o.nees_x_inst;
    all_r.push_back(o.nees_r);
    all_x_inst.push_back(o.nees_x_inst);
    if (o.have_checkpoint) {
      ++n_state;
      x += o.nees_x;
      v += o.nees_v;
      all_x.push_back(o.nees_x);
      all_v.push_back(o.nees_v);
    }
    const double error = std::fabs(o.r_hat - o.r_true);
    const double sigmas = error / o.sigma_r;
    const bool finite = std::isfinite(sigmas) && std::isfinite(o.sigma_r) && o.sigma_r > 0.0 &&
                        std::isfinite(o.nees_r) && std::isfinite(o.nees_x_inst) &&
                        (!o.have_checkpoint || (std::isfinite(o.nees_x) && std::isfinite(o.nees_v)));
    if (!finite) ++non_finite;
    worst_r_sigmas = std::isfinite(sigmas) ? std::fmax(worst_r_sigmas, sigmas) : HUGE_VAL;
    if (!finite || !(sigmas <= 3.0)) ++r_outside_3sigma;
    max_sigma_r = std::isfinite(o.sigma_r) ? std::fmax(max_sigma_r, o.sigma_r) : HUGE_VAL;
    max_abs_r_error = std::isfinite(error) ? std::fmax(max_abs_r_error, error) : HUGE_VAL;
    sum_abs_r_error += std::isfinite(error) ? error : HUGE_VAL;
  }
};

Tally monte_carlo(bool with_accelerometer, int seeds) {
  Tally t;
  for (int wall = 0; wall < 4; ++wall) {
    for (int seed = 1; seed <= seeds; ++seed) {
      Scenario sc;
      sc.true_wall = true_wall(wall);
      sc.true_r = seed % 2 == 0 ? 0.80 : 0.95;
      sc.motion = suite_window(1 + (seed + wall) % 11, seed % 2, 1.0, 3.0, 0.25);
      sc.sensors.rate_hz = 200.0;
      sc.sensors.x_noise_m = 0.5e-3;
      sc.sensors.x_bias_m = 1e-3 * double(seed % 3);
      if (with_accelerometer) sc.sensors.a_noise_mps2 = 0.05;
      sc.sensors.seed = std::uint64_t(100 * wall + seed);
      t.add(fused_run(sc));
    }
  }
  return t;
}

// The truth drawn from the filter's own prior (Bar-Shalom's condition for a NEES test): per run κc, κk ~ 1 ± σ0
// (capacity_sigma0), √r ~ √r_exp ± r_sigma0 (drawn again when above 0.995: the filter holds √r ≤ 1, and its prior
// mass beyond is clamped), the transducer's offset ~ 0 ± bias_sigma0; the ground a 3 s window of one of the
// suite's 11 sets (either component, starting 0.5–3 s in) at a PGA 0.2–0.35 g; the sensor noise of the seed.
Tally monte_carlo_prior(bool with_accelerometer, int seeds, const core::ObserverOptions& options = {},
                        double truth_process_mps2 = -1.0, int first_seed = 1) {
  Tally t;
  const double e0 = std::sqrt(core::restitution_energy_ratio(core::paper_wall(), core::Restitution{}));
  for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
    sim::synthesis::RandomStream rng(std::uint64_t(7919 * seed + (with_accelerometer ? 1 : 0)));
    Scenario sc;
    sc.true_wall = core::paper_wall();
    sc.in_model = true;
    sc.observer = options;
    sc.kappa_c = 1.0 + options.capacity_sigma0 * rng.normal();
    sc.kappa_k = 1.0 + options.capacity_sigma0 * rng.normal();
    double e = 2.0;
    while (e > 0.995) e = e0 + options.r_sigma0 * rng.normal();
    sc.true_r = e * e;
    sc.sensors.x_bias_m = options.bias_sigma0_m * rng.normal();
    const int set = 1 + int(rng.uniform() * 11.0);
    const int component = rng.uniform() < 0.5 ? 0 : 1;
    const double t0 = rng.uniform(0.5, 3.0), pga = rng.uniform(0.2, 0.35);
    sc.motion = suite_window(set, component, t0, 3.0, pga);
    sc.sensors.rate_hz = 200.0;
    sc.sensors.x_noise_m = options.x_noise_m;
    if (with_accelerometer) sc.sensors.a_noise_mps2 = options.a_noise_mps2;
    sc.sensors.seed = std::uint64_t(1000 + seed);
    sc.truth_process_mps2 = truth_process_mps2 >= 0.0 ? truth_process_mps2 : options.process_accel_mps2;
    sc.truth_seed = std::uint64_t(5000 + seed);
    t.add(fused_run(sc));
  }
  return t;
}

void print_tally(const Tally& t, const char* what) {
  double lo = 0.0, hi = 0.0, lo_s = 0.0, hi_s = 0.0;
  chi2_band(t.n, lo, hi);
  chi2_band(t.n_state, lo_s, hi_s);
  const double r = t.r / t.n, xi = t.x_inst / t.n, x = t.x / t.n_state, v = t.v / t.n_state;
  std::printf("\n%s: %d runs (%d with both walls rocking at the checkpoint); mean NEES r %.2f, x_inst %.2f "
              "[%.2f, %.2f]; x %.2f, xd %.2f [%.2f, %.2f]; r outside 3 sigma: %d (worst %.1f sigma); non-finite %d; "
              "|r error| mean %.4f max %.4f, max sigma_r %.4f",
              what, t.n, t.n_state, r, xi, lo, hi, x, v, lo_s, hi_s, t.r_outside_3sigma, t.worst_r_sigmas,
              t.non_finite, t.sum_abs_r_error / t.n, t.max_abs_r_error, t.max_sigma_r);
}

void check_tally(const Tally& t, const char* what) {
  print_tally(t, what);
  double lo = 0.0, hi = 0.0, lo_s = 0.0, hi_s = 0.0;
  chi2_band(t.n, lo, hi);
  chi2_band(t.n_state, lo_s, hi_s);
  const double r = t.r / t.n, xi = t.x_inst / t.n, x = t.x / t.n_state, v = t.v / t.n_state;
  CHECK(t.n >= 50);
  CHECK(t.n_state >= 50);
  LONGS_EQUAL(0, t.non_finite);
  CHECK(r >= lo && r <= hi);
  CHECK(xi >= lo && xi <= hi);
  CHECK(x >= lo_s && x <= hi_s);
  CHECK(v >= lo_s && v <= hi_s);
  LONGS_EQUAL(0, t.r_outside_3sigma);
}

}  // namespace

// r̂ within 3 σ of the true r at the end of every run: 4 walls × 8 seeds × 2 sensor sets (64 runs, 3 s windows of the
// suite at 0.25 g, true r 0.80 / 0.95, 200 Hz, 0.5 mm, offsets 0–2 mm). Measured: worst 1.4 σ (transducer alone),
// 2.0 σ (with the accelerometer). The NEES figures of these runs are printed.
TEST(ObserverConsistency, RestitutionWithinThreeSigmaInEveryRun) {
  const Tally d = monte_carlo(false, 8), a = monte_carlo(true, 8);
  print_tally(d, "displacement");
  print_tally(a, "displacement + accelerometer");
  LONGS_EQUAL(32, d.n);
  LONGS_EQUAL(32, a.n);
  LONGS_EQUAL(0, d.non_finite);
  LONGS_EQUAL(0, a.non_finite);
  LONGS_EQUAL(0, d.r_outside_3sigma);
  LONGS_EQUAL(0, a.r_outside_3sigma);
  // And r is learnt (issue 42: the prior's σ_r ≈ 0.19 puts an observer that never learns r within 3 σ too). Measured:
  // mean |r̂ − r| 0.017 (transducer alone), 0.011 (with the accelerometer), largest σ_r 0.11 and 0.13; an observer
  // that keeps its prior (r̂ 0.894 against r 0.80 / 0.95) has a mean |r̂ − r| of 0.075 and σ_r 0.19.
  const double prior_sigma_r =
      2.0 * std::sqrt(core::restitution_energy_ratio(core::paper_wall(), core::Restitution{})) * core::ObserverOptions{}.r_sigma0;
  for (const Tally* t : {&d, &a}) {
    CHECK_TEXT(t->sum_abs_r_error / t->n <= 0.04, ("mean |r error| " + std::to_string(t->sum_abs_r_error / t->n)).c_str());
    CHECK_TEXT(t->max_sigma_r <= 0.9 * prior_sigma_r, ("largest sigma_r " + std::to_string(t->max_sigma_r)).c_str());
  }
}

// The NEES bands, on the textbook condition (Bar-Shalom): the truth drawn from the filter's own stochastic model —
// κc, κk, √r and the offset from its prior, its process noise (the default 0.2 m/s²) in the true motion
// (monte_carlo_prior) — 64 runs per sensor set; the 95 % band of the mean of 64 χ²(1) is [0.68, 1.38]. Mean NEES at
// the end (r, x_inst) and at a checkpoint 2/3 into the true wall's motion with both walls rocking (x, ẋ), measured
// (seeds 1–64):
//   displacement only               r 0.87  x_inst 1.10  x 1.01  ẋ 0.91   (worst r 2.3 σ)
//   displacement + accelerometer    r 0.88  x_inst 0.84  x 0.92  ẋ 1.09   (worst r 2.2 σ)
// With five more blocks of 64 seeds (MeasureSeedBlocks, -ri), of 12 block × sensor pairs x_inst is in the band in 12,
// r in 12 (one at its edge), x in 10 and ẋ in 9 (the checkpoint is one χ²(1) draw per run: heavy-tailed), and 4 of
// 768 runs end with r̂ beyond 3 σ (at most 3.4 σ; a Gaussian error gives 2). The fixed walls of
// RestitutionWithinThreeSigmaInEveryRun carry no model error while the filter assumes 0.2 m/s²: there it is
// under-confident (NEES x_inst 0.26 transducer alone), as it should be. With the truth's process noise equal to the
// filter's (MeasureProcessNoise, -ri) 0.1 m/s² is in the band too; at 0.05 and 0.02 r is under-confident with the
// transducer alone (0.56, 0.61): the default 0.2 is kept. Learning from half-cycles of 5 σ_x instead of 10 (inform_peak_noises)
// passes at 0.2 m/s² but one run diverges at 0.1 (r̂ 9.6 σ from the truth, mean NEES ẋ 10.9) and two at 0.02 with the
// accelerometer (6.4 σ): not adopted (docs/BENCHMARKS.md, "Consistency").
TEST(ObserverConsistency, DisplacementTransducerAloneIsConsistent) {
  check_tally(monte_carlo_prior(false, 64), "prior-drawn truth, displacement");
}

TEST(ObserverConsistency, DisplacementAndAccelerometerAreConsistent) {
  check_tally(monte_carlo_prior(true, 64), "prior-drawn truth, displacement + accelerometer");
}

TEST(ObserverConsistency, ReportedRBiasIsGone) {
  // The reported case: true r = 0.80, nominal r_exp (0.894), 16833_H1.cor.acc at 0.2 g (the wall rocks at
  // sub-noise amplitude), a 200 Hz transducer with 0.5 mm noise. Was r̂ 0.49 ± 0.037 and 0.52 ± 0.024 (seeds 1, 2):
  // the fused model's noise-driven impacts were read as a low r. Now r̂ stays within 3 σ of the truth (nothing about
  // r is observable there: the prior stays, 0.894 ± 0.19), and so on the other real records at 0.2 and 0.3 g. Where
  // the observer has learnt r (σ_r ≤ 0.02: 8 of the 12 runs, measured σ_r 0.004–0.010) r̂ is 0.80 ± 0.005 (measured
  // within 0.0043); the prior stays on 16833 at 0.2 g, and on ELC180 at 0.3 g r̂ 0.88 / 0.95 ± 0.14 (issue 42: the
  // |r̂ − 0.80| stated here is now checked, and the count of runs that learnt r).
  Scenario sc;
  sc.true_wall = core::paper_wall();
  sc.true_r = 0.80;
  sc.sensors.rate_hz = 200.0;
  sc.sensors.x_noise_m = 0.5e-3;
  int learnt = 0;
  for (const char* name : {"16833_H1.cor.acc", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "RSN960_NORTHR_LOS270.AT2"}) {
    for (const double pga : {0.2, 0.3}) {
      sc.motion = real_record(name, pga);
      for (int seed = 1; seed <= 2; ++seed) {
        sc.sensors.seed = std::uint64_t(seed);
        const RunOutcome o = fused_run(sc);
        std::printf("\n%s %.1f g seed %d: r %.4f sigma %.4f", name, pga, seed, o.r_hat, o.sigma_r);
        CHECK(std::isfinite(o.r_hat) && std::isfinite(o.sigma_r) && o.sigma_r > 0.0);
        CHECK(std::fabs(o.r_hat - o.r_true) <= 3.0 * o.sigma_r);
        if (o.sigma_r <= 0.02) {
          ++learnt;
          CHECK_TEXT(std::fabs(o.r_hat - 0.80) <= 0.005, ("r " + std::to_string(o.r_hat)).c_str());
        }
      }
    }
  }
  CHECK_TEXT(learnt >= 8, ("runs that learnt r: " + std::to_string(learnt)).c_str());
}

// The NEES bands without the heavy tail (issue 42: the mean NEES of x and ẋ — one χ²(1) draw per run at the
// checkpoint — left its 95 % band in 2 and 3 of 12 blocks of 64 seeds, so a change of draw order failed the mean's
// check about one time in four). Six blocks (seeds 1–384) per sensor set, and per quantity the COUNT of runs whose NEES
// is below χ²(1)'s median (0.4549) and below its 95 % point (3.8415): for a consistent filter these are binomial,
// Bin(N, 0.5) and Bin(N, 0.95), whatever the tail; the bands are ±3.29 binomial standard deviations (a two-sided
// 0.1 % each; 8 counts per sensor set). Below the median too often: under-confident (σ overstated, e.g. σ × 3 puts
// 96 % of the runs there); too rarely, or too few within the 95 % point: over-confident. Release only (768 runs,
// ~3 s; under the sanitizers the block of the two tests above).
TEST(ObserverConsistency, NeesQuantilesOverSixBlocks) {
#ifdef ROCKWATCH_TEST_SANITIZED
  return;
#endif
  for (const bool accel : {false, true}) {
    Tally t;
    for (int block = 0; block < 6; ++block) {
      const Tally b = monte_carlo_prior(accel, 64, {}, -1.0, 1 + 64 * block);
      t.all_x.insert(t.all_x.end(), b.all_x.begin(), b.all_x.end());
      t.all_v.insert(t.all_v.end(), b.all_v.begin(), b.all_v.end());
      t.all_r.insert(t.all_r.end(), b.all_r.begin(), b.all_r.end());
      t.all_x_inst.insert(t.all_x_inst.end(), b.all_x_inst.begin(), b.all_x_inst.end());
      LONGS_EQUAL(0, b.non_finite);
    }
    const struct {
      const char* name;
      const std::vector<double>* nees;
    } quantities[] = {{"x", &t.all_x}, {"xd", &t.all_v}, {"r", &t.all_r}, {"x_inst", &t.all_x_inst}};
    for (const auto& q : quantities) {
      const double n = double(q.nees->size());
      const auto below = [&](double v) { return double(std::count_if(q.nees->begin(), q.nees->end(), [v](double e) { return e < v; })); };
      const double at_median = below(0.454936), at_95 = below(3.841459);
      const double sd_median = std::sqrt(n * 0.25), sd_95 = std::sqrt(n * 0.95 * 0.05);
      char what[200];
      std::snprintf(what, sizeof what, "%s, %s: %d runs, %.0f below the median (band %.0f ± %.0f), %.0f below the 95 %% "
                    "point (band %.0f ± %.0f)", accel ? "displacement + accelerometer" : "displacement", q.name, int(n),
                    at_median, 0.5 * n, 3.29 * sd_median, at_95, 0.95 * n, 3.29 * sd_95);
      std::printf("\n%s", what);
      CHECK_TEXT(n >= 370, what);
      CHECK_TEXT(std::fabs(at_median - 0.5 * n) <= 3.29 * sd_median, what);
      CHECK_TEXT(std::fabs(at_95 - 0.95 * n) <= 3.29 * sd_95, what);
    }
  }
}

// Measurement (run with -ri): the prior-drawn Monte-Carlo at several process noises.
IGNORE_TEST(ObserverConsistency, MeasureSeedBlocks) {
  for (int block = 0; block < 6; ++block) {
    char what[96];
    std::snprintf(what, sizeof what, "prior, seeds %d.., displacement", 1 + 64 * block);
    print_tally(monte_carlo_prior(false, 64, {}, -1.0, 1 + 64 * block), what);
    std::snprintf(what, sizeof what, "prior, seeds %d.., + accelerometer", 1 + 64 * block);
    print_tally(monte_carlo_prior(true, 64, {}, -1.0, 1 + 64 * block), what);
  }
}

IGNORE_TEST(ObserverConsistency, MeasureProcessNoise) {
  for (const double q : {0.2, 0.1, 0.05, 0.02}) {
    for (const double tq : {q, 0.0}) {
      core::ObserverOptions o;
      o.process_accel_mps2 = q;
      char what[96];
      std::snprintf(what, sizeof what, "prior, q %.2f, truth %.2f, displacement", q, tq);
      print_tally(monte_carlo_prior(false, 64, o, tq), what);
      std::snprintf(what, sizeof what, "prior, q %.2f, truth %.2f, + accelerometer", q, tq);
      print_tally(monte_carlo_prior(true, 64, o, tq), what);
    }
  }
}
