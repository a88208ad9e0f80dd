// Shared input and driver of the firmware engine's no-allocation proofs (test_engine_allocations.cpp,
// test_engine_eigen_no_malloc.cpp): the paper wall's WallEngine over a repeating 12 s cycle that makes it rock
// with impacts and then collapse, with reset() after every collapse. The input is built (and may allocate)
// before the measured window; run_engine itself only calls process()/reset() and adds up plain counters.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

namespace rockwatch::engine_test {

namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;

inline constexpr double kDt = 0.005;
inline constexpr double kG = 9.81;
inline constexpr std::size_t kMeasuredSamples = 100000;

inline firmware::WallEngineConfig paper_config() {
  firmware::WallEngineConfig c;
  c.wall = core::paper_wall();
  c.r_energy = core::r_exp(c.wall);
  c.dt_s = kDt;
  return c;
}

// One cycle, sensor frame (default axes: x → ü, z → v̈), 2400 samples:
//   0–7 s   2 Hz sine at 0.20 g with a 3 Hz vertical at 0.05 g: rocking with impacts (about 19), up to
//           0.8 x_inst (WARNING, IMMINENT by energy), no collapse
//   7–8 s   one cycle of 1 Hz at 0.50 g: collapse within 0.4 s; after reset() the rest of the pulse tips the
//           wall again (collapses at 7.38, 7.84 and 8.56 s: three per cycle)
//   8–12 s  no input
inline std::vector<firmware::SensorSampleQ> make_cycle() {
  constexpr double kPi = 3.14159265358979323846;
  std::vector<firmware::SensorSampleQ> cycle;
  const std::size_t n = static_cast<std::size_t>(12.0 / kDt + 0.5);
  cycle.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = double(k) * kDt;
    double u = 0.0, v = 0.0;
    if (t < 7.0) {
      u = 0.20 * kG * std::sin(2.0 * kPi * 2.0 * t);
      v = 0.05 * kG * std::sin(2.0 * kPi * 3.0 * t);
    } else if (t < 8.0) {
      u = 0.50 * kG * std::sin(2.0 * kPi * 1.0 * (t - 7.0));
    }
    firmware::SensorSampleQ s;
    s << core::AccelQ7_24(u), core::AccelQ7_24(0.0), core::AccelQ7_24(v);
    cycle.push_back(s);
  }
  return cycle;
}

struct RunCounts {
  std::uint64_t samples = 0;
  std::uint64_t impacts = 0;          // impacts_total over all samples
  std::uint64_t collapses = 0;        // samples whose step collapsed (each followed by reset())
  std::uint64_t moving_samples = 0;
  std::uint64_t imminent_samples = 0; // alarm level IMMINENT after the sample
  std::uint64_t saturated_samples = 0;
};

// n process() calls over the looped cycle; reset() with the next sample after a collapse.
inline RunCounts run_engine(firmware::WallEngine& engine, const std::vector<firmware::SensorSampleQ>& cycle,
                            std::size_t n) {
  RunCounts c;
  std::size_t k = 0;
  engine.reset(cycle[0]);
  for (std::size_t i = 0; i < n; ++i) {
    k = k + 1 == cycle.size() ? 0 : k + 1;
    const firmware::WallEngineOutput& out = engine.process(cycle[k]);
    ++c.samples;
    c.impacts += out.step.impacts_total;
    c.moving_samples += out.indicators.conditions.moving ? 1U : 0U;
    c.imminent_samples += out.alarm.level == core::AlarmLevel::imminent ? 1U : 0U;
    c.saturated_samples += out.step.saturated ? 1U : 0U;
    if (out.step.collapsed) {
      ++c.collapses;
      engine.reset(cycle[k]);
    }
  }
  return c;
}

// The run really exercised impacts and collapses (so a zero count is not the count of a wall at rest).
inline bool run_was_eventful(const RunCounts& c) {
  return c.samples == kMeasuredSamples && c.impacts >= 100 && c.collapses >= 1 && c.moving_samples >= 1000 &&
         c.imminent_samples >= 1;
}

}  // namespace rockwatch::engine_test
