// Google Benchmark: ns per sample of the two monitor engines through the seam (core::SampleEngine::step_at), with the
// wall observer off and on (one wall-sensor sample, displacement and acceleration, pushed before every step), over
// set 1 X of the shipped suite at PGA 0.2 g with the sensors of a true wall that differs from the nominal one
// (observer_input.hpp). One iteration = one sample; the 20 s record is replayed in a loop, every lap from start().
// Figures and commands: docs/BENCHMARKS.md, "Observer cost per sample". Run a Release build.
#include <cstddef>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "observer_input.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

namespace {

namespace core = rockwatch::core;
namespace bench = rockwatch::bench;

const std::vector<double>& record_x() {
  static const std::vector<double> x = bench::suite_record_x(std::string(ROCKWATCH_SUITE_DIR) + "/set01.txt");
  return x;
}

template <typename Engine>
void BM_Seam(benchmark::State& state, bool observer) {
  const std::vector<double>& ug = record_x();
  const std::vector<core::WallSensorSample> sensors = bench::true_wall_sensors(ug);
  Engine engine;
  if (engine.init(bench::engine_config(observer)) != core::WallEngineError::ok) {
    state.SkipWithError("init failed");
    return;
  }
  engine.start(ug[0], 0.0);
  std::size_t n = 1;
  std::int64_t corrected = 0;
  for (auto _ : state) {
    const core::EngineSample e = bench::seam_sample(engine, observer, ug, sensors, n);
    benchmark::DoNotOptimize(&e);
    corrected += e.observer.corrected ? 1 : 0;
    if (++n == ug.size()) {
      // A new lap: sensor times start again, so a new observer (init) as well as the wall at rest.
      n = 1;
      state.PauseTiming();
      engine.init(bench::engine_config(observer));
      engine.start(ug[0], 0.0);
      state.ResumeTiming();
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["corrected_frac"] = state.iterations() > 0 ? double(corrected) / double(state.iterations()) : 0.0;
}

}  // namespace

void BM_FixedObserverOff(benchmark::State& s) { BM_Seam<rockwatch::firmware::WallEngine>(s, false); }
void BM_FixedObserverOn(benchmark::State& s) { BM_Seam<rockwatch::firmware::WallEngine>(s, true); }
void BM_DoubleObserverOff(benchmark::State& s) { BM_Seam<rockwatch::sim::DoubleWallEngine>(s, false); }
void BM_DoubleObserverOn(benchmark::State& s) { BM_Seam<rockwatch::sim::DoubleWallEngine>(s, true); }
BENCHMARK(BM_FixedObserverOff);
BENCHMARK(BM_FixedObserverOn);
BENCHMARK(BM_DoubleObserverOff);
BENCHMARK(BM_DoubleObserverOn);

BENCHMARK_MAIN();
