// Per-sample instruction counts of the fixed-point engine and the double engine, for callgrind_per_sample.sh.
// Run under `valgrind --tool=callgrind --collect-atstart=no --combine-dumps=yes`: each measured call is wrapped in
// CALLGRIND_TOGGLE_COLLECT and followed by CALLGRIND_DUMP_STATS_AT(pass), so every sample becomes one dump part
// whose total is that call's instruction count (plus a constant few instructions of the call and the toggle).
// Reading the record and everything between calls is not collected. Outside valgrind the requests are no-ops.
//
// Passes, in this order, each over every sample of the record (sample 0 is the initial input; reset after a
// collapse, outside the measurement):
//   fixed_step      core::FixedRockingStepper::step alone, wall inputs converted beforehand
//   fixed_process   firmware::WallEngine::process (sensor axes + step + indicators + alarm)
//   double_step     core::RockingStepper<double>::step alone
//   double_process  step + evaluate_instability<double> + InstabilityAlarm::update
//   overhead        an empty out-of-line call: the constant cost of the measurement window
//
//   bench_sample_instructions SET_FILE      (e.g. sim/suites/npr9998-2015/set01.txt; X scaled to PGA 0.2 g)
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <valgrind/callgrind.h>

#include "sample_engines.hpp"

namespace {

namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;
namespace bench = rockwatch::bench;

struct Outcome {
  std::uint64_t impacts = 0, collapses = 0, moving = 0;
  double max_abs_x_m = 0.0;
};

// The measured calls: out of line and opaque to the optimiser (noipa), so that exactly the call is inside the
// collection window. `overhead` does nothing: its count is the constant cost of the window itself (call, return,
// the toggle's client request), which callgrind_per_sample.sh subtracts.
[[gnu::noipa]] void overhead(bench::DoubleEngine&, double) {}
[[gnu::noipa]] core::FixedStepReport fixed_step(core::FixedRockingStepper& s, bench::FixedStepInput ug) {
  return s.step(ug, bench::FixedStepInput{});
}
[[gnu::noipa]] const firmware::WallEngineOutput& fixed_process(firmware::WallEngine& e,
                                                                  const firmware::SensorSampleQ& x) {
  return e.process(x);
}
[[gnu::noipa]] core::StepReport<double> double_step(core::RockingStepper<double>& s, double ug) {
  return s.step(ug, 0.0);
}
[[gnu::noipa]] core::AlarmUpdate double_process(bench::DoubleEngine& e, double ug) { return e.process(ug); }

void note(Outcome& o, std::uint64_t impacts, bool moving, double x_m) {
  o.impacts += impacts;
  o.moving += moving ? 1U : 0U;
  const double ax = x_m < 0.0 ? -x_m : x_m;
  if (ax > o.max_abs_x_m) o.max_abs_x_m = ax;
}

void print(const char* pass, std::size_t n, const Outcome& o) {
  std::fprintf(stderr, "%-15s samples %zu impacts %llu collapses %llu moving_samples %llu max_abs_x_m %.4f\n", pass, n,
               static_cast<unsigned long long>(o.impacts), static_cast<unsigned long long>(o.collapses),
               static_cast<unsigned long long>(o.moving), o.max_abs_x_m);
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
  const std::vector<firmware::SensorSampleQ> sensor = bench::to_sensor_samples(ug);
  const std::vector<bench::FixedStepInput> ug_q = bench::to_fixed_step_inputs(ug);
  const std::size_t n = ug.size();

  {
    core::FixedRockingStepper s;
    s.init(bench::engine_setup());
    s.reset(ug_q[0], bench::FixedStepInput{});
    Outcome o;
    for (std::size_t i = 1; i < n; ++i) {
      CALLGRIND_TOGGLE_COLLECT;
      const core::FixedStepReport r = fixed_step(s, ug_q[i]);
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS_AT("fixed_step");
      note(o, r.impacts_total, s.moving(), s.x_m().to_double());
      if (r.collapsed) {
        ++o.collapses;
        s.reset(ug_q[i], bench::FixedStepInput{});
      }
    }
    print("fixed_step", n - 1, o);
  }
  {
    firmware::WallEngine e;
    if (e.init(bench::fixed_engine_config()) != firmware::WallEngineError::ok) {
      std::fprintf(stderr, "error: WallEngine::init failed\n");
      return 1;
    }
    e.reset(sensor[0]);
    Outcome o;
    for (std::size_t i = 1; i < n; ++i) {
      CALLGRIND_TOGGLE_COLLECT;
      const firmware::WallEngineOutput& out = fixed_process(e, sensor[i]);
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS_AT("fixed_process");
      note(o, out.step.impacts_total, e.stepper().moving(), e.stepper().x_m().to_double());
      if (out.step.collapsed) {
        ++o.collapses;
        e.reset(sensor[i]);
      }
    }
    print("fixed_process", n - 1, o);
  }
  {
    core::RockingStepper<double> s;
    s.init(bench::engine_setup());
    s.reset(ug[0], 0.0);
    Outcome o;
    for (std::size_t i = 1; i < n; ++i) {
      CALLGRIND_TOGGLE_COLLECT;
      const core::StepReport<double> r = double_step(s, ug[i]);
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS_AT("double_step");
      note(o, r.impacts_total, s.moving(), s.state().x_m);
      if (r.collapsed) {
        ++o.collapses;
        s.reset(ug[i], 0.0);
      }
    }
    print("double_step", n - 1, o);
  }
  {
    bench::DoubleEngine e;
    e.init();
    e.reset(ug[0]);
    Outcome o;
    for (std::size_t i = 1; i < n; ++i) {
      CALLGRIND_TOGGLE_COLLECT;
      double_process(e, ug[i]);
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS_AT("double_process");
      note(o, e.report().impacts_total, e.stepper().moving(), e.stepper().state().x_m);
      if (e.report().collapsed) {
        ++o.collapses;
        e.reset(ug[i]);
      }
    }
    print("double_process", n - 1, o);
    for (std::size_t i = 1; i < n; ++i) {
      CALLGRIND_TOGGLE_COLLECT;
      overhead(e, ug[i]);
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS_AT("overhead");
    }
  }
  return 0;
}
