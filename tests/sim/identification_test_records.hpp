// The test records of the identification suites (test_identification, test_identification_bootstrap): a true wall's
// transducer samples as a lab records them, and the shipped suite's ground motions.
#pragma once

#include <cstdint>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::test {

namespace core = rockwatch::core;
namespace sim = rockwatch::sim;

inline core::Restitution energy_ratio(double r) {
  core::Restitution out;
  out.kind = core::RestitutionKind::value;
  out.value = r;
  return out;
}

// The true wall released at x0 on ground at rest (or forced by `ground`), its transducer at 200 Hz, 0.5 mm noise and
// an offset of 2 mm: the samples a lab records.
inline std::vector<core::WallSensorSample> test_record(const core::WallParameters& wall, double r, double x0_m,
                                                       const sim::GroundMotion* ground, double t_end_s, std::uint64_t seed) {
  sim::AnalysisOptions o;
  o.restitution = energy_ratio(r);
  o.keep_history = true;
  o.t_end_s = t_end_s;
  sim::GroundMotion quiet;
  quiet.dt_s = 0.005;
  quiet.ug_mps2.assign(2, 0.0);
  if (!ground) o.initial_x_m = x0_m;
  const sim::AnalysisResult truth = sim::analyse(wall, ground ? *ground : quiet, o);
  sim::SensorModel m;
  m.rate_hz = 200.0;
  m.x_noise_m = 0.5e-3;
  m.x_bias_m = 2e-3;
  m.seed = seed;
  return sim::synthesize_wall_sensors(wall, truth, ground ? ground->dt_s : quiet.dt_s, m);
}

// Set `set`, component X, of the shipped suite scaled to pga_g (as `--suite DIR --set N --component X --scale-pga`).
inline sim::GroundMotion suite_motion(int set, double pga_g) {
  const rockwatch::records::SuiteRecordFile f =
      rockwatch::records::read_suite_record(rockwatch::records::suite_set_path(ROCKWATCH_SUITE_DIR, set));
  sim::GroundMotion m;
  m.dt_s = f.dt_s;
  m.ug_mps2 = f.components_mps2[0];
  const double factor = pga_g * 9.81 / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  return m;
}

}  // namespace rockwatch::test
