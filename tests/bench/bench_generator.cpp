// Google Benchmark of the spectrum-compatible generator (sim/synthesis): one draw of one component (the 80
// Fourier-correction iterations, each a 120-period spectrum of the enveloped signal and a 100-period check of the
// finished candidate), and one whole set as `rockwatch generate` makes it (three components on their own threads,
// redrawn until accepted). Figures and commands: docs/BENCHMARKS.md ("Ground-motion generator").
#include <cstddef>

#include <benchmark/benchmark.h>

#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

namespace {

namespace synthesis = rockwatch::sim::synthesis;

void BM_GenerateOneDraw(benchmark::State& state) {
  synthesis::GeneratorSettings settings;
  settings.max_attempts = 1;
  const auto component = static_cast<synthesis::Component>(state.range(0));
  for (auto _ : state) {
    const synthesis::GeneratedComponent c = synthesis::generate_component(settings, 3, component);
    benchmark::DoNotOptimize(c.acc_mps2.data());
  }
}
BENCHMARK(BM_GenerateOneDraw)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

// Set 3 takes 5 draws in all (X 1, Y 3, Z 1), set 1 takes 7 (3, 3, 1); `draws` reports them.
void BM_GenerateSet(benchmark::State& state) {
  const synthesis::GeneratorSettings settings;
  const auto set_number = static_cast<int>(state.range(0));
  std::size_t draws = 0;
  for (auto _ : state) {
    const synthesis::GeneratedSet set = synthesis::generate_set(settings, set_number);
    draws = set.components[0].attempts + set.components[1].attempts + set.components[2].attempts;
    benchmark::DoNotOptimize(set.components[0].acc_mps2.data());
  }
  state.counters["draws"] = static_cast<double>(draws);
}
BENCHMARK(BM_GenerateSet)->Arg(3)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
