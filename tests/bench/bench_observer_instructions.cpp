// Per-sample instruction counts of the two monitor engines through the seam with the wall observer off and on, for
// callgrind_per_sample.sh --observer (run under `valgrind --tool=callgrind --collect-atstart=no
// --combine-dumps=yes`; each measured call wrapped in CALLGRIND_TOGGLE_COLLECT and followed by
// CALLGRIND_DUMP_STATS_AT(pass), as bench_sample_instructions.cpp). Input: observer_input.hpp (set 1 X at 0.2 g, the
// sensors of a true wall with r = 0.9 r_exp). Passes: fixed_off, fixed_observer (firmware::WallEngine), double_off,
// double_observer (sim::DoubleWallEngine): push_sensor (observer on) + step_at; overhead: an empty call.
//
//   bench_observer_instructions SET_FILE
#include <cstdint>
#include <cstdio>
#include <exception>
#include <vector>

#include <valgrind/callgrind.h>

#include "observer_input.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

namespace {

namespace core = rockwatch::core;
namespace bench = rockwatch::bench;

[[gnu::noipa]] void overhead(core::SampleEngine&, double) {}
[[gnu::noipa]] core::EngineSample measured(core::SampleEngine& e, bool observer, const std::vector<double>& ug,
                                           const std::vector<core::WallSensorSample>& sensors, std::size_t i) {
  return bench::seam_sample(e, observer, ug, sensors, i);
}

template <typename Engine>
int pass(const char* name, bool observer, const std::vector<double>& ug,
         const std::vector<core::WallSensorSample>& sensors) {
  Engine e;
  if (e.init(bench::engine_config(observer)) != core::WallEngineError::ok) {
    std::fprintf(stderr, "error: %s: init failed\n", name);
    return 1;
  }
  e.start(ug[0], 0.0);
  std::uint64_t corrected = 0, collapses = 0, moving = 0;
  double max_abs_x = 0.0;
  for (std::size_t i = 1; i < ug.size(); ++i) {
    CALLGRIND_TOGGLE_COLLECT;
    const core::EngineSample s = measured(e, observer, ug, sensors, i);
    CALLGRIND_TOGGLE_COLLECT;
    CALLGRIND_DUMP_STATS_AT(name);
    corrected += s.observer.corrected ? 1U : 0U;
    moving += s.moving ? 1U : 0U;
    max_abs_x = s.x_m > max_abs_x ? s.x_m : (-s.x_m > max_abs_x ? -s.x_m : max_abs_x);
    if (e.stepper().collapsed()) {
      ++collapses;
      e.restart(ug[i], 0.0);
    }
  }
  std::fprintf(stderr,
               "%-15s samples %zu moving %llu max_abs_x_m %.4f corrected %llu collapses %llu x_updates %lld "
               "a_updates %lld rejected %lld\n",
               name, ug.size() - 1, static_cast<unsigned long long>(moving), max_abs_x,
               static_cast<unsigned long long>(corrected),
               static_cast<unsigned long long>(collapses), static_cast<long long>(e.observer_counters().x_updates),
               static_cast<long long>(e.observer_counters().a_updates),
               static_cast<long long>(e.observer_counters().rejected));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SET_FILE\n", argv[0]);
    return 2;
  }
  std::vector<double> ug;
  try {
    ug = bench::suite_record_x(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  const std::vector<core::WallSensorSample> sensors = bench::true_wall_sensors(ug);
  if (pass<rockwatch::firmware::WallEngine>("fixed_off", false, ug, sensors) != 0 ||
      pass<rockwatch::firmware::WallEngine>("fixed_observer", true, ug, sensors) != 0 ||
      pass<rockwatch::sim::DoubleWallEngine>("double_off", false, ug, sensors) != 0 ||
      pass<rockwatch::sim::DoubleWallEngine>("double_observer", true, ug, sensors) != 0) {
    return 1;
  }
  rockwatch::firmware::WallEngine e;
  for (std::size_t i = 1; i < ug.size(); ++i) {
    CALLGRIND_TOGGLE_COLLECT;
    overhead(e, ug[i]);
    CALLGRIND_TOGGLE_COLLECT;
    CALLGRIND_DUMP_STATS_AT("overhead");
  }
  return 0;
}
