// Identification of a wall from a test (sim::identify, SPEC §9): the reduced parameters against SPEC §9's values;
// snap-back and forced tests of walls that differ from the starting (paper) wall — thinner, with an overburden,
// with unequal blocks — recovered within the accuracy (r within 0.005, x_inst within 1 %) and within a few
// of their stated standard errors; records that do not identify the wall refused, saying why.
#include <cmath>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/identification.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"
#include "identification_test_records.hpp"

#include <CppUTest/TestHarness.h>

namespace core = rockwatch::core;
namespace sim = rockwatch::sim;
using rockwatch::test::energy_ratio;
using rockwatch::test::suite_motion;
using rockwatch::test::test_record;

namespace {

sim::IdentificationResult identify_from_paper_wall(std::vector<core::WallSensorSample> samples,
                                                   const sim::GroundMotion* ground = nullptr) {
  sim::IdentificationInput in;
  in.samples = std::move(samples);
  in.ground = ground;
  return sim::identify(in);
}

void check_recovered(const sim::IdentificationResult& got, const core::WallParameters& truth, double r_true) {
  const sim::ReducedParameters want = sim::reduced_parameters(truth);
  const double x_inst_error = std::fabs(got.reduced.x_inst_m - want.x_inst_m);
  const double omega_error = std::fabs(got.reduced.omega_radps - want.omega_radps);
  // The accuracy, and the stated uncertainty honest (within 4 σ).
  CHECK_TEXT(std::fabs(got.r - r_true) < 0.005, ("r " + std::to_string(got.r)).c_str());
  CHECK_TEXT(x_inst_error < 0.01 * want.x_inst_m, ("x_inst " + std::to_string(got.reduced.x_inst_m)).c_str());
  CHECK_TEXT(std::fabs(got.r - r_true) < 4.0 * got.sigma_r + 1e-6, ("r sigma " + std::to_string(got.sigma_r)).c_str());
  CHECK_TEXT(x_inst_error < 4.0 * got.sigma_x_inst_m + 1e-7,
             ("x_inst sigma " + std::to_string(got.sigma_x_inst_m)).c_str());
  CHECK_TEXT(omega_error < 4.0 * got.sigma_omega_radps + 1e-6,
             ("omega " + std::to_string(got.reduced.omega_radps) + " want " + std::to_string(want.omega_radps)).c_str());
  CHECK(std::fabs(got.offset_m - 2e-3) < 4.0 * got.sigma_offset_m + 1e-7);
  // A noise of 0.5 mm: the residual is the noise.
  CHECK(got.residual_rms_m > 0.4e-3 && got.residual_rms_m < 0.6e-3);
  CHECK(got.converged);
  CHECK(got.fit_explains_record);
  CHECK(got.n_impacts >= 5);
}

}  // namespace

TEST_GROUP(Identification){};

TEST(Identification, ReducedParametersAreSpecNineValues) {
  const sim::ReducedParameters p = sim::reduced_parameters(core::paper_wall());
  DOUBLES_EQUAL(1.660032, p.c_mps2[0], 1e-6);
  DOUBLES_EQUAL(1.660032, p.c_mps2[1], 1e-6);
  DOUBLES_EQUAL(16.546117, p.k_ps2, 1e-6);
  DOUBLES_EQUAL(1.480661, p.gamma, 1e-6);
  DOUBLES_EQUAL(0.1003276, p.x_inst_m, 1e-7);
  DOUBLES_EQUAL(1.121143, p.threshold_mps2, 1e-6);
  DOUBLES_EQUAL(std::sqrt(16.546117), p.omega_radps, 1e-6);
  // An overburden of 2 kN/m scales c and k together: the same x_inst (SPEC §9).
  core::WallParameters loaded = core::paper_wall();
  loaded.fp_npm = 2000.0;
  const sim::ReducedParameters q = sim::reduced_parameters(loaded);
  DOUBLES_EQUAL(2.734, q.c_mps2[0], 1e-3);
  DOUBLES_EQUAL(27.255, q.k_ps2, 1e-3);
  DOUBLES_EQUAL(p.gamma, q.gamma, 1e-12);
  DOUBLES_EQUAL(p.x_inst_m, q.x_inst_m, 2e-3 * p.x_inst_m);
}

TEST(Identification, SnapBackOfAThinnerWallGivesItsCapacityAndRestitution) {
  core::WallParameters wall = core::paper_wall();
  wall.b_m = 0.09;
  const sim::IdentificationResult got = identify_from_paper_wall(test_record(wall, 0.85, 0.05, nullptr, 6.0, 3));
  CHECK(got.snap_back);
  check_recovered(got, wall, 0.85);
  CHECK(got.x0_m.has_value());
  DOUBLES_EQUAL(0.05, *got.x0_m, 4.0 * *got.sigma_x0_m + 1e-7);
  // The equivalent wall of a thinner wall of the same heights is that wall.
  DOUBLES_EQUAL(0.09, got.wall.b_m, 4.0 * got.sigma_b_m);
  DOUBLES_EQUAL(1.75, got.wall.h1_m, 4.0 * got.sigma_h1_m);
}

TEST(Identification, AnOverburdenIsIdentifiedAsAnEquivalentShorterWall) {
  core::WallParameters wall = core::paper_wall();
  wall.fp_npm = 2500.0;
  wall.b_m = 0.11;
  const sim::IdentificationResult got = identify_from_paper_wall(test_record(wall, 0.80, 0.06, nullptr, 8.0, 5));
  check_recovered(got, wall, 0.80);
  CHECK(got.wall.fp_npm == 0.0);      // held at the starting wall's
  CHECK(got.wall.h1_m < 1.75 * 0.8);  // a stiffer wall: shorter
}

TEST(Identification, UnequalBlocksAreReproducedByTheEquivalentWall) {
  core::WallParameters wall = core::paper_wall();
  wall.h1_m = 1.5;
  wall.h2_m = 2.0;
  const sim::IdentificationResult got = identify_from_paper_wall(test_record(wall, 0.90, -0.04, nullptr, 6.0, 7));
  // h1:h2 is held at 1:1, so the equivalent wall matches (c, k) but not the geometry: x_inst and r as the true wall's.
  check_recovered(got, wall, 0.90);
}

TEST(Identification, AForcedTestIdentifiesTheWallThroughItsGroundMotion) {
  // Four seconds of a 2.5 Hz sine of 1.5 m/s², above the threshold: the wall rocks (75 impacts, max |x| 0.3 x_inst)
  // and survives. (Near collapse a forced response is chaotic, SPEC §4: no test there identifies a wall.)
  const sim::GroundMotion ground = sim::sample_motion(
      [](double t) { return t < 4.0 ? 1.5 * std::sin(2.0 * M_PI * 2.5 * t) : 0.0; }, 0.005, 8.0);
  core::WallParameters wall = core::paper_wall();
  wall.b_m = 0.095;
  const sim::IdentificationResult got =
      identify_from_paper_wall(test_record(wall, 0.82, 0.0, &ground, 8.0, 11), &ground);
  CHECK_FALSE(got.snap_back);
  CHECK_FALSE(got.x0_m.has_value());
  check_recovered(got, wall, 0.82);
}

TEST(Identification, AForcedTestOfARealRecordIsFoundFromThePaperWall) {
#ifdef ROCKWATCH_TEST_SANITIZED
  // Release only (issue 42): a whole real record's fit, the statistics of the release build; the sanitized suite
  // keeps the shorter forced fits above and below.
  return;
#endif
  // A real record that rocks a 10 % thinner wall to 0.6 x_inst: a minimum per phase of the response. The search before
  // the windows from the first motion, the finer grid and the carried minima (SPEC §9.1) ended 11 % off in x_inst with
  // a residual twice the noise, and called it explained; the noise was overstated by 15 % from first differences.
  const sim::GroundMotion ground = suite_motion(3, 0.22);
  core::WallParameters wall = core::paper_wall();
  wall.b_m = 0.09;
  const double t_end_s = double(ground.ug_mps2.size() - 1) * ground.dt_s;
  const sim::IdentificationResult got = identify_from_paper_wall(test_record(wall, 0.85, 0.0, &ground, t_end_s, 4), &ground);
  const sim::ReducedParameters want = sim::reduced_parameters(wall);
  CHECK_TEXT(std::fabs(got.r - 0.85) < 0.005, ("r " + std::to_string(got.r)).c_str());
  CHECK_TEXT(std::fabs(got.reduced.x_inst_m - want.x_inst_m) < 0.01 * want.x_inst_m,
             ("x_inst " + std::to_string(got.reduced.x_inst_m)).c_str());
  CHECK(got.fit_explains_record);
  // The noise from second differences while the wall rocks at up to 0.5 m/s: within 5 % of the 0.5 mm drawn.
  CHECK_TEXT(std::fabs(got.noise_estimate_m - 0.5e-3) < 0.025e-3, ("noise " + std::to_string(got.noise_estimate_m)).c_str());
}

TEST(Identification, AForcedTestTheEquivalentWallCannotDescribeIsFlaggedAndTheRightHeldFieldsFindIt) {
  // Blocks of 1.5 : 2.0 m forced by a real record: a forced test sees γ, which the held h1 : h2 sets, so the paper
  // wall's 1 : 1 cannot reproduce it (SPEC §9.1): the fit must say so rather than return a wall; started from a wall
  // with the right heights it finds the truth.
  sim::GroundMotion ground = suite_motion(3, 0.15);
#ifdef ROCKWATCH_TEST_SANITIZED
  const double t_end_s = 5.0;  // under the sanitizers the first 5 s, the paper wall's fit only (issue 42)
#else
  const double t_end_s = 10.0;  // the record's first 10 s (the test's run time under the sanitizers)
#endif
  ground.ug_mps2.resize(std::size_t(t_end_s / ground.dt_s) + 1);
  core::WallParameters wall = core::paper_wall();
  wall.h1_m = 1.5;
  wall.h2_m = 2.0;
  const std::vector<core::WallSensorSample> samples = test_record(wall, 0.85, 0.0, &ground, t_end_s, 11);
  const sim::IdentificationResult from_paper = identify_from_paper_wall(samples, &ground);
  CHECK_FALSE(from_paper.fit_explains_record);
  CHECK(from_paper.residual_rms_m > 1.2 * from_paper.noise_estimate_m);
#ifdef ROCKWATCH_TEST_SANITIZED
  return;  // One fit under the sanitizers (issue 42: the suite within a quarter of its timeout); the release build's
           // second fit finds the truth from the right heights.
#endif
  sim::IdentificationInput in;
  in.samples = samples;
  in.ground = &ground;
  in.start_wall = wall;  // the drawings' heights (b and their scale are identified)
  const sim::IdentificationResult got = sim::identify(in);
  CHECK(got.fit_explains_record);
  CHECK(std::fabs(got.r - 0.85) < 0.005);
  CHECK(std::fabs(got.reduced.x_inst_m - sim::reduced_parameters(wall).x_inst_m) < 0.01 * sim::reduced_parameters(wall).x_inst_m);
}

TEST(Identification, ARecordThatDoesNotIdentifyTheWallIsRefusedSayingWhy) {
  const auto message_of = [](std::vector<core::WallSensorSample> samples, const sim::GroundMotion* ground) {
    try {
      identify_from_paper_wall(std::move(samples), ground);
    } catch (const sim::IdentificationError& e) {
      return std::string(e.what());
    }
    return std::string("identified");
  };
  core::WallParameters wall = core::paper_wall();
  std::vector<core::WallSensorSample> snap = test_record(wall, 0.85, 0.05, nullptr, 6.0, 1);
  // Too short: ten samples.
  std::vector<core::WallSensorSample> few(snap.begin(), snap.begin() + 10);
  CHECK(message_of(few, nullptr).rfind("too short", 0) == 0);
  // At rest throughout: the offset and noise only.
  std::vector<core::WallSensorSample> still;
  for (int i = 0; i < 1000; ++i) {
    core::WallSensorSample s;
    s.utime_us = std::int64_t(i) * 5000;
    s.x_mid_m = 2e-3 + 0.4e-3 * std::sin(0.7 * i) * std::cos(1.3 * i);
    s.x_valid = true;
    still.push_back(s);
  }
  CHECK(message_of(still, nullptr).rfind("at rest throughout", 0) == 0);
  // No impact: a slow drift of the transducer (5 mm over 5 s) under ground motion below every wall's threshold.
  const sim::GroundMotion weak =
      sim::sample_motion([](double t) { return 0.3 * std::sin(2.0 * M_PI * 2.0 * t); }, 0.005, 5.0);
  std::vector<core::WallSensorSample> drift = still;
  for (core::WallSensorSample& s : drift) s.x_mid_m += 1e-3 * double(s.utime_us) * 1e-6;
  CHECK(message_of(drift, &weak).rfind("no impact", 0) == 0);
  // No displacement column.
  std::vector<core::WallSensorSample> accel_only = still;
  for (core::WallSensorSample& s : accel_only) {
    s.x_valid = false;
    s.a_valid = true;
  }
  CHECK(message_of(accel_only, nullptr).rfind("no displacement samples", 0) == 0);
}
