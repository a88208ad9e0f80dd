// The two per-sample engines the fixed-point benchmarks compare, set up identically (paper wall, linear model,
// r = r_exp, κ = 2, dt = 5 ms, default alarm settings), and the input record they run on: set 1, component X of the
// shipped suite (sim/suites/npr9998-2015/set01.txt), scaled to PGA 0.2 g = 1.962 m/s², no vertical.
//   fixed  firmware::WallEngine::process: sensor axes → FixedRockingStepper → fixed indicators → InstabilityAlarm
//   double core::RockingStepper<double> + evaluate_instability<double> + InstabilityAlarm
// Used by bench_fixed_engine.cpp (Google Benchmark) and bench_sample_instructions.cpp (callgrind).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/instability_indicators.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/records/suite_format.hpp"

namespace rockwatch::bench {

namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;

inline constexpr double kEngineDt = 0.005;
inline constexpr double kEnginePgaMps2 = 1.962;  // 0.2 g

// X of the set file scaled to peak |ü| = 1.962 m/s² (reads the file: call before any measurement).
inline std::vector<double> suite_record_x(const std::string& path) {
  const records::SuiteRecordFile file = records::read_suite_record(path);
  std::vector<double> x = file.components_mps2[0];
  double peak = 0.0;
  for (double v : x) peak = std::fabs(v) > peak ? std::fabs(v) : peak;
  for (double& v : x) v *= kEnginePgaMps2 / peak;
  return x;
}

inline core::StepperSetup<double> engine_setup() {
  core::StepperOptions o;
  o.dt_s = kEngineDt;
  o.kappa = 2.0;
  const core::WallParameters wall = core::paper_wall();
  return core::make_stepper_setup(wall, core::ModelKind::linear, core::r_exp(wall), o);
}

inline firmware::WallEngineConfig fixed_engine_config() {
  firmware::WallEngineConfig c;
  c.wall = core::paper_wall();
  c.r_energy = core::r_exp(c.wall);
  c.kappa = 2.0;
  c.dt_s = kEngineDt;
  return c;
}

// The input type of FixedRockingStepper::step (its own wide format), whatever the engine's formats are.
using FixedStepInput = core::AlarmChainTraits<core::FixedRockingStepper>::Input;

inline std::vector<FixedStepInput> to_fixed_step_inputs(const std::vector<double>& ug) {
  std::vector<FixedStepInput> out;
  out.reserve(ug.size());
  for (double v : ug) out.push_back(FixedStepInput(v));
  return out;
}

// Sensor samples for the fixed engine (default axes: x → ü, z → v̈ = 0), converted before any measurement.
inline std::vector<firmware::SensorSampleQ> to_sensor_samples(const std::vector<double>& ug) {
  std::vector<firmware::SensorSampleQ> out(ug.size());
  for (std::size_t i = 0; i < ug.size(); ++i) {
    out[i] << core::AccelQ7_24(ug[i]), core::AccelQ7_24(0.0), core::AccelQ7_24(0.0);
  }
  return out;
}

// The double engine with the same stages as WallEngine::process (no sensor-axes mapping: the input is ü itself).
class DoubleEngine {
 public:
  void init() {
    const core::StepperSetup<double> setup = engine_setup();
    const core::AlarmSettings settings{};
    stepper_.init(setup);
    constants_ = core::make_instability_constants(setup, settings);
    alarm_.init(core::hold_samples(settings, kEngineDt));
  }
  void reset(double ug_mps2) {
    stepper_.reset(ug_mps2, 0.0);
    alarm_.reset();
  }
  // Step + indicators + alarm: one sample.
  core::AlarmUpdate process(double ug_mps2) {
    report_ = stepper_.step(ug_mps2, 0.0);
    indicators_ = core::evaluate_instability(constants_, stepper_, report_);
    return alarm_.update(indicators_.conditions);
  }
  core::RockingStepper<double>& stepper() { return stepper_; }
  const core::StepReport<double>& report() const { return report_; }

 private:
  core::RockingStepper<double> stepper_{};
  core::InstabilityConstants<double> constants_{};
  core::InstabilityAlarm alarm_{};
  core::StepReport<double> report_{};
  core::InstabilityIndicators<double> indicators_{};
};

}  // namespace rockwatch::bench
