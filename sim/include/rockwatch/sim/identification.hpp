// Batch identification of a wall from a test record (SPEC §9): the wall's capacity, stiffness and restitution from
// its own motion, measured by the displacement transducer at the mid-height hinge (SPEC §8).
//
// Method: maximum likelihood under white Gaussian transducer noise = nonlinear least squares over the whole record,
// the model evaluated through the engine (sim::analyse, the double engine every tool uses), Levenberg–Marquardt with
// central-difference Jacobians, started from the best point of a coarse grid around the starting wall.
//
// What is identified. The linear model is fixed by (c_±, k, γ) and r (SPEC §9); a free (snap-back) test sees c and k
// (so x_inst = c/k and ω = √k) and r, a forced one also γ, which for walls without overburden is ≈ 1.48 whatever their
// slenderness. The result is written as an *equivalent wall*: the thickness b and a common scale of the two heights
// (h1 : h2, ρ, Fp, a, a', g held at the starting wall's) — two geometric parameters that reproduce the identified
// (c, k) exactly — with r, the transducer's zero offset and, for a snap-back test, the release displacement x0.
// An overburden is reproduced by a shorter equivalent wall (the same c/k, a higher k; SPEC §9): the same response.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim {

// The reduced parameters of the linear model on one side (SPEC §9), with ü = v̈ = 0, G = g.
struct ReducedParameters {
  double c_mps2[2] = {0.0, 0.0};        // c_s = |p6|/p1 per side (index core::side_index) [m/s²]
  double k_ps2 = 0.0;                   // k = |p4|/p1 [1/s²] (the same on both sides)
  double gamma = 0.0;                   // γ = (m1 + m2)/(2 p1) [-]
  double x_inst_m = 0.0;                // min over the sides of c_s/k [m]
  double omega_radps = 0.0;             // free-rocking rate √k [rad/s]
  double threshold_mps2 = 0.0;          // uplift threshold min c_s/γ [m/s²]
};
ReducedParameters reduced_parameters(const core::WallParameters& wall);

struct IdentificationInput {
  core::WallParameters start_wall = core::paper_wall();  // the start of the search; its held fields are kept
  double start_r = 0.0;                 // the start of r [-] (the caller's --r; 0: 0.9 r_ana)
  core::ModelKind model = core::ModelKind::linear;
  double max_step_s = core::kDefaultMaxStep_s;
  double kappa = 2.0;
  // The ground motion of a forced test (the record's clock: t = 0 at its first sample, as the sensors'). Null: the
  // ground at rest, a snap-back test released at t = 0 from an identified x0.
  const GroundMotion* ground = nullptr;
  std::vector<core::WallSensorSample> samples;  // the transducer's samples (x_valid rows are used), utime ascending
  int max_iterations = 60;
  // A parametric bootstrap of the estimator (SPEC §9.1): `bootstrap_replicates` records made of the fitted response
  // plus new white noise of the noise estimate's σ at the same sample times, each identified from the same start
  // (grid, continuation, every step); the standard deviations of the replicates' estimates are then the reported
  // standard errors. 0: none, the errors are the minimum's curvature (honest for a snap-back test, not for a forced
  // one: docs/BENCHMARKS.md "Identification").
  int bootstrap_replicates = 0;
  std::uint64_t bootstrap_seed = 1;       // replicate i's noise: RandomStream(splitmix64 of seed and i)
  std::size_t bootstrap_jobs = 0;         // threads (0: one per core); the result does not depend on it
  std::function<void(std::size_t done, std::size_t total)> bootstrap_progress;  // called after each replicate
};

// The curvature's standard errors (the covariance s² (JᵀJ)⁻¹ at the minimum) beside the bootstrap's.
struct IdentificationBootstrap {
  int replicates = 0;                   // refits attempted
  int refused = 0;                      // replicates whose record did not identify the wall (IdentificationError)
  int flagged = 0;                      // replicates identified whose fit does not explain their record
  int used = 0;                         // the rest: their standard deviations are the sigma_* (when used >= 2;
                                        // otherwise the sigma_* stay the curvature's)
  std::uint64_t seed = 1;
  double curvature_sigma_r = 0.0;       // [-]
  double curvature_sigma_x_inst_m = 0.0;  // [m]
  double curvature_sigma_omega_radps = 0.0;  // [rad/s]
  double curvature_sigma_offset_m = 0.0;  // [m]
};

struct IdentificationResult {
  bool snap_back = false;               // no ground motion: a free test (x0 identified)
  core::WallParameters wall{};          // the equivalent wall
  double r = 0.0, sigma_r = 0.0;        // energy ratio at impact and its standard error [-]
  ReducedParameters reduced{};          // of the equivalent wall
  double sigma_x_inst_m = 0.0;          // [m]
  double sigma_omega_radps = 0.0;       // [rad/s]
  double sigma_k_ps2 = 0.0;             // [1/s²]
  double sigma_c_mps2 = 0.0;            // of the smaller side's c [m/s²]
  double sigma_b_m = 0.0, sigma_h1_m = 0.0, sigma_h2_m = 0.0;  // of the identified wall fields [m]
  double offset_m = 0.0, sigma_offset_m = 0.0;                  // the transducer's zero offset [m]
  std::optional<double> x0_m, sigma_x0_m;                       // the release displacement (snap-back) [m]
  double residual_rms_m = 0.0;          // RMS of measured − fitted [m]
  double noise_estimate_m = 0.0;        // the transducer's noise from the data alone (median |second difference|) [m]
  // The residual is at the noise level (residual RMS ≤ 1.2 × noise_estimate_m, more below 400 samples): the identified
  // wall explains the record.
  // False: a response the model does not follow (a minimum a cycle off; near collapse a forced response is chaotic,
  // SPEC §4; or a wall the equivalent wall does not describe: a forced test sees γ, which h1 : h2 and Fp set) — the
  // estimates are then not to be trusted, whatever their standard errors.
  bool fit_explains_record = true;
  std::size_t samples_used = 0;         // displacement samples in the fit
  int n_impacts = 0;                    // counted impacts (|ẋ⁻| ≥ 1 mm/s, SPEC §3) of the fitted response
  int iterations = 0;                   // Levenberg–Marquardt iterations
  int model_evaluations = 0;            // engine runs in all (grid, iterations, Jacobians)
  bool converged = false;               // the step and the cost change fell below their tolerances
  std::vector<double> t_s, measured_m, fitted_m;  // the samples used, for plots: measured and fitted x_mid [s, m]
  // Set when a bootstrap ran: the sigma_* above are then its standard deviations (over the replicates identified).
  std::optional<IdentificationBootstrap> bootstrap;
  // The sigma_* are the bootstrap's (it ran and used ≥ 2 replicates), not the curvature's: what every report says.
  bool sigma_by_bootstrap = false;
};

// The record does not identify the wall (no displacement samples, too short, at rest throughout, no impact, a
// singular fit): `what()` says why. The CLI exits 2 with it.
class IdentificationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws IdentificationError (the data) or AnalysisError (the starting wall or options).
IdentificationResult identify(const IdentificationInput& input);

}  // namespace rockwatch::sim
