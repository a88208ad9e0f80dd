// Google Benchmark: ns per sample of the fixed-point engine (firmware::WallEngine::process) against the double
// engine (RockingStepper<double> + evaluate_instability<double> + InstabilityAlarm), and of each engine's step
// alone, over set 1 X of the shipped suite scaled to PGA 0.2 g (sample_engines.hpp). One iteration = one sample.
// The 20 s record is replayed in a loop; every lap starts from reset() with the record's first sample, so every lap
// is the same; a collapse resets the engine (counted). Figures and commands: docs/BENCHMARKS.md, "Fixed-point
// engine". Run a Release build; report the median of --benchmark_repetitions=5.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "sample_engines.hpp"

namespace {

namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;
namespace bench = rockwatch::bench;

const std::vector<double>& record_x() {
  static const std::vector<double> x = bench::suite_record_x(std::string(ROCKWATCH_SUITE_DIR) + "/set01.txt");
  return x;
}

struct Tally {
  std::int64_t impacts = 0, collapses = 0, moving = 0;
  void report(benchmark::State& state) const {
    const double n = double(state.iterations());
    state.SetItemsProcessed(state.iterations());
    state.counters["impacts_per_s"] = n > 0.0 ? double(impacts) / (n * bench::kEngineDt) : 0.0;  // simulated time
    state.counters["moving_frac"] = n > 0.0 ? double(moving) / n : 0.0;
    state.counters["collapses_per_lap"] =
        n > 0.0 ? double(collapses) * double(record_x().size() - 1) / n : 0.0;
  }
};

void BM_FixedProcess(benchmark::State& state) {
  const std::vector<firmware::SensorSampleQ> input = bench::to_sensor_samples(record_x());
  firmware::WallEngine engine;
  if (engine.init(bench::fixed_engine_config()) != firmware::WallEngineError::ok) {
    state.SkipWithError("WallEngine::init failed");
    return;
  }
  engine.reset(input[0]);
  benchmark::DoNotOptimize(&engine);
  std::size_t n = 1;
  Tally t;
  for (auto _ : state) {
    const firmware::WallEngineOutput& out = engine.process(input[n]);
    benchmark::DoNotOptimize(&out);
    t.impacts += out.step.impacts_total;
    t.moving += out.indicators.conditions.moving ? 1 : 0;
    if (out.step.collapsed) {
      ++t.collapses;
      engine.reset(input[n]);
    }
    if (++n == input.size()) {
      n = 1;
      engine.reset(input[0]);
    }
    benchmark::ClobberMemory();
  }
  t.report(state);
}

void BM_FixedStep(benchmark::State& state) {
  const std::vector<bench::FixedStepInput> input = bench::to_fixed_step_inputs(record_x());
  core::FixedRockingStepper stepper;
  if (stepper.init(bench::engine_setup()) != core::FixedSetupError::ok) {
    state.SkipWithError("FixedRockingStepper::init failed");
    return;
  }
  stepper.reset(input[0], bench::FixedStepInput{});
  benchmark::DoNotOptimize(&stepper);
  std::size_t n = 1;
  Tally t;
  for (auto _ : state) {
    core::FixedStepReport r = stepper.step(input[n], bench::FixedStepInput{});
    benchmark::DoNotOptimize(r);
    t.impacts += r.impacts_total;
    t.moving += stepper.moving() ? 1 : 0;
    if (r.collapsed) {
      ++t.collapses;
      stepper.reset(input[n], bench::FixedStepInput{});
    }
    if (++n == input.size()) {
      n = 1;
      stepper.reset(input[0], bench::FixedStepInput{});
    }
    benchmark::ClobberMemory();
  }
  t.report(state);
}

void BM_DoubleProcess(benchmark::State& state) {
  const std::vector<double>& input = record_x();
  bench::DoubleEngine engine;
  engine.init();
  engine.reset(input[0]);
  benchmark::DoNotOptimize(&engine);
  std::size_t n = 1;
  Tally t;
  for (auto _ : state) {
    core::AlarmUpdate u = engine.process(input[n]);
    benchmark::DoNotOptimize(u);
    t.impacts += engine.report().impacts_total;
    t.moving += engine.stepper().moving() ? 1 : 0;
    if (engine.report().collapsed) {
      ++t.collapses;
      engine.reset(input[n]);
    }
    if (++n == input.size()) {
      n = 1;
      engine.reset(input[0]);
    }
    benchmark::ClobberMemory();
  }
  t.report(state);
}

void BM_DoubleStep(benchmark::State& state) {
  const std::vector<double>& input = record_x();
  core::RockingStepper<double> stepper;
  stepper.init(bench::engine_setup());
  stepper.reset(input[0], 0.0);
  benchmark::DoNotOptimize(&stepper);
  std::size_t n = 1;
  Tally t;
  for (auto _ : state) {
    core::StepReport<double> r = stepper.step(input[n], 0.0);
    benchmark::DoNotOptimize(r);
    t.impacts += r.impacts_total;
    t.moving += stepper.moving() ? 1 : 0;
    if (r.collapsed) {
      ++t.collapses;
      stepper.reset(input[n], 0.0);
    }
    if (++n == input.size()) {
      n = 1;
      stepper.reset(input[0], 0.0);
    }
    benchmark::ClobberMemory();
  }
  t.report(state);
}

BENCHMARK(BM_FixedProcess);
BENCHMARK(BM_DoubleProcess);
BENCHMARK(BM_FixedStep);
BENCHMARK(BM_DoubleStep);

}  // namespace

BENCHMARK_MAIN();
