// The input of the observer benchmarks (bench_observer.cpp, bench_observer_instructions.cpp): the record of
// sample_engines.hpp (set 1 X at PGA 0.2 g) and, per sample, the wall sensors of a *true* wall that dissipates more
// than the engines assume (r = 0.9 r_exp against r_exp): the double stepper run over the record, its displacement with a 1 mm offset
// (transducer) and its absolute acceleration at mid-height ü + ẍ − g·x/h1 (accelerometer). Computed before any
// measurement. The engines are driven through the monitor's seam (core::SampleEngine): start, then per sample
// push_sensor (observer on) and step_at.
#pragma once

#include <cstdint>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/sample_engine.hpp"
#include "rockwatch/core/wall.hpp"
#include "sample_engines.hpp"

namespace rockwatch::bench {

inline constexpr std::int64_t kStepUs = 5000;

inline std::vector<core::WallSensorSample> true_wall_sensors(const std::vector<double>& ug) {
  const core::WallParameters wall = core::paper_wall();
  core::StepperOptions o;
  o.dt_s = kEngineDt;
  core::RockingStepper<double> truth;
  truth.init(core::make_stepper_setup(wall, core::ModelKind::linear, 0.9 * core::r_exp(wall), o));
  truth.reset(ug[0], 0.0);
  std::vector<core::WallSensorSample> out(ug.size());
  for (std::size_t i = 0; i < ug.size(); ++i) {
    if (i > 0 && truth.step(ug[i], 0.0).collapsed) truth.reset(ug[i], 0.0);
    core::WallSensorSample& s = out[i];
    s.utime_us = std::int64_t(i) * kStepUs;
    s.x_mid_m = truth.state().x_m + 1e-3;
    s.x_valid = true;
    s.a_mid_mps2 = ug[i] + truth.state().xdd_mps2 - wall.g_mps2 * truth.state().x_m / wall.h1_m;
    s.a_valid = true;
  }
  return out;
}

inline core::WallEngineConfig engine_config(bool observer) {
  core::WallEngineConfig c = fixed_engine_config();
  c.observer_enabled = observer;
  return c;
}

// One sample through the seam: the sensor sample of its time (observer on), then the step to it.
inline core::EngineSample seam_sample(core::SampleEngine& e, bool observer, const std::vector<double>& ug,
                                      const std::vector<core::WallSensorSample>& sensors, std::size_t i) {
  if (observer) e.push_sensor(sensors[i]);
  return e.step_at(ug[i], 0.0, std::int64_t(i) * kStepUs, kStepUs);
}

}  // namespace rockwatch::bench
