// The parametric bootstrap of sim::identify (SPEC §9.1): on a forced test of a real record the curvature's standard
// errors are orders of magnitude below the distance to the truth and the bootstrap's cover it; on a snap-back test
// the two agree; the result does not depend on the thread count. Its own ctest entry: each test runs the whole
// identification a dozen times. Under the sanitizers (ROCKWATCH_TEST_SANITIZED, tests/CMakeLists.txt) the bootstraps
// are smaller and only their structure is checked; the statistics are the release build's.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "identification_test_records.hpp"
#include "rockwatch/sim/identification.hpp"

#include <CppUTest/TestHarness.h>

namespace core = rockwatch::core;
namespace sim = rockwatch::sim;
using rockwatch::test::suite_motion;
using rockwatch::test::test_record;

#ifdef ROCKWATCH_TEST_SANITIZED
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

TEST_GROUP(IdentificationBootstrap){};

TEST(IdentificationBootstrap, ABootstrapStatesTheUncertaintyOfAForcedTestThatTheCurvatureUnderstates) {
  // A real record rocking the paper wall (r 0.80) for 10 s: the cost has many narrow minima (SPEC §9.1), the search
  // ends in one near the truth's, and the curvature there is far narrower than the distance to the truth. The
  // bootstrap's spread covers that distance; the point estimate is the one without it.
  sim::GroundMotion ground = suite_motion(3, 0.15);
  const double t_end_s = kSanitized ? 4.0 : 10.0;  // (under the sanitizers the structure only, on the first 4 s)
  ground.ug_mps2.resize(std::size_t(t_end_s / ground.dt_s) + 1);
  const core::WallParameters wall = core::paper_wall();
  const std::vector<core::WallSensorSample> samples = test_record(wall, 0.80, 0.0, &ground, t_end_s, 27);
  sim::IdentificationInput in;
  in.samples = samples;
  in.ground = &ground;
  const sim::IdentificationResult plain = sim::identify(in);
  in.bootstrap_replicates = kSanitized ? 2 : 6;
  in.bootstrap_jobs = 2;
  const sim::IdentificationResult got = sim::identify(in);
  const double want_x_inst_m = sim::reduced_parameters(wall).x_inst_m;
  const double x_error_m = std::fabs(got.reduced.x_inst_m - want_x_inst_m);
  const double r_error = std::fabs(got.r - 0.80);
  std::printf("\nbootstrap: x_inst error %.3g m, curvature sigma %.3g, bootstrap sigma %.3g; r error %.3g, curvature %.3g, "
              "bootstrap %.3g\n", x_error_m, plain.sigma_x_inst_m, got.sigma_x_inst_m, r_error, plain.sigma_r, got.sigma_r);
  CHECK(got.reduced.x_inst_m == plain.reduced.x_inst_m);
  CHECK(got.r == plain.r);
  CHECK(got.bootstrap.has_value());
  CHECK(!plain.bootstrap.has_value());
  CHECK_EQUAL(in.bootstrap_replicates, got.bootstrap->replicates);
  CHECK_EQUAL(0, got.bootstrap->refused);
  CHECK_EQUAL(in.bootstrap_replicates, got.bootstrap->used + got.bootstrap->flagged);
  CHECK(got.bootstrap->used >= 2);
  CHECK_TRUE(got.sigma_by_bootstrap);
  CHECK_FALSE(plain.sigma_by_bootstrap);
  CHECK(got.bootstrap->curvature_sigma_x_inst_m == plain.sigma_x_inst_m);
  if (kSanitized) return;  // (2 replicates on 4 s: the statistics are the release build's)
  // The curvature's error is not an uncertainty here (the case is chosen so: more than 10 of its σ off) ...
  CHECK(x_error_m > 10.0 * plain.sigma_x_inst_m);
  // ... the bootstrap's is.
  CHECK_TEXT(x_error_m < 3.0 * got.sigma_x_inst_m, ("x_inst bootstrap sigma " + std::to_string(got.sigma_x_inst_m)).c_str());
  CHECK_TEXT(r_error < 3.0 * got.sigma_r, ("r bootstrap sigma " + std::to_string(got.sigma_r)).c_str());
}

TEST(IdentificationBootstrap, ABootstrapIsTheSameOnAnyNumberOfThreadsAndAgreesWithASnapBacksCurvature) {
  core::WallParameters wall = core::paper_wall();
  wall.b_m = 0.09;
  sim::IdentificationInput in;
  in.samples = test_record(wall, 0.85, 0.05, nullptr, 4.0, 3);
  in.bootstrap_replicates = kSanitized ? 2 : 5;  // (under the sanitizers: the threads' equality, not the spread)
  in.bootstrap_jobs = 1;
  const sim::IdentificationResult one = sim::identify(in);
  in.bootstrap_jobs = 2;
  const sim::IdentificationResult two = sim::identify(in);
  CHECK(one.sigma_x_inst_m == two.sigma_x_inst_m);
  CHECK(one.sigma_r == two.sigma_r);
  CHECK(one.sigma_x0_m == two.sigma_x0_m);
  // A snap-back test's minimum is regular: the bootstrap's spread is the curvature's error (5 replicates: the
  // standard deviation within about ±35 %, one σ).
  const double ratio_x = one.sigma_x_inst_m / one.bootstrap->curvature_sigma_x_inst_m;
  const double ratio_r = one.sigma_r / one.bootstrap->curvature_sigma_r;
  std::printf("\nsnap-back bootstrap / curvature: x_inst %.3f, r %.3f\n", ratio_x, ratio_r);
  if (kSanitized) return;
  CHECK(ratio_x > 0.4 && ratio_x < 2.5);
  CHECK(ratio_r > 0.4 && ratio_r < 2.5);
}


// Two-sided (issue 42): the bootstrap's σ is neither under- nor overstated. Snap-back tests of one thinner wall under
// 6 noise seeds, 8 replicates each: the errors of x_inst and r in their bootstrap σ, 12 values z, have an RMS near 1
// (z of a σ from 8 replicates is Student-t with 7 dof: E z² = 7/5, RMS 1.18; measured 1.43). The band [0.6, 2.2]: for 12 z the
// RMS falls outside it with a probability below 0.01 (below 0.6: χ²(12) < 12·0.36/1.4 = 3.1, P ≈ 0.005 before the
// t-tails, which only widen it upwards; above 2.2: the mean of 12 t₇² above 4.8, P < 1e-3); a σ three times too large
// gives RMS 0.48 here, a third of the true one 4.3. Release only (54 identifications, ~13 s).
TEST(IdentificationBootstrap, TheBootstrapSigmaIsNeitherUnderNorOverstatedOverSeeds) {
  if (kSanitized) return;
  core::WallParameters wall = core::paper_wall();
  wall.b_m = 0.09;
  const double want_x_inst_m = sim::reduced_parameters(wall).x_inst_m;
  double sum_z2 = 0.0;
  int n = 0;
  for (int seed = 21; seed < 27; ++seed) {
    sim::IdentificationInput in;
    in.samples = test_record(wall, 0.85, 0.05, nullptr, 4.0, seed);
    in.bootstrap_replicates = 8;
    in.bootstrap_jobs = 2;
    const sim::IdentificationResult got = sim::identify(in);
    CHECK(got.sigma_by_bootstrap);
    CHECK(got.sigma_x_inst_m > 0.0 && got.sigma_r > 0.0);
    const double zx = (got.reduced.x_inst_m - want_x_inst_m) / got.sigma_x_inst_m;
    const double zr = (got.r - 0.85) / got.sigma_r;
    std::printf("\nseed %d: x_inst error %.2f bootstrap sigma, r error %.2f", seed, zx, zr);
    CHECK(std::isfinite(zx) && std::isfinite(zr));
    sum_z2 += zx * zx + zr * zr;
    n += 2;
  }
  const double rms = std::sqrt(sum_z2 / double(n));
  std::printf("\nRMS of the errors in bootstrap sigmas over %d: %.2f (band [0.6, 2.2])\n", n, rms);
  CHECK_TEXT(rms > 0.6, ("the bootstrap overstates sigma: RMS z " + std::to_string(rms)).c_str());
  CHECK_TEXT(rms < 2.2, ("the bootstrap understates sigma: RMS z " + std::to_string(rms)).c_str());
}
