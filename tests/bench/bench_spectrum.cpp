// Google Benchmark of sim::response_spectrum: the 40 s, 200 Hz synthetic record (8001 samples) at the default 100
// log-spaced periods (0.02–4 s), 5 % damping. Target: < 10 ms per spectrum. Figures and the exact command:
// docs/BENCHMARKS.md ("Response spectrum"). Run a Release build; report the median of --benchmark_repetitions=5.
#include <cstddef>
#include <vector>

#include <benchmark/benchmark.h>

#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "synthetic_motion.hpp"

namespace {

namespace sim = rockwatch::sim;
using rockwatch::bench::kG;

constexpr double kPgaMps2 = 0.2 * kG;  // the scale does not change the work, only the numbers

// One iteration = one whole spectrum (100 oscillators × 8000 steps); per_step divides by the oscillator steps.
void BM_ResponseSpectrum(benchmark::State& state) {
  const sim::GroundMotion motion = rockwatch::bench::earthquake_record(kPgaMps2);
  const std::vector<double> periods = sim::default_spectrum_periods();
  double peak_psa = 0.0;
  for (auto _ : state) {
    const sim::ResponseSpectrum s = sim::response_spectrum(motion.ug_mps2, motion.dt_s, periods);
    benchmark::DoNotOptimize(s.psa_mps2.data());
    peak_psa = s.psa_mps2[periods.size() / 2];
  }
  const double steps = double(periods.size()) * double(motion.ug_mps2.size() - 1);
  state.counters["per_step"] =
      benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["psa_mid_g"] = peak_psa / kG;  // a check that the input is the documented one
}
BENCHMARK(BM_ResponseSpectrum)->Unit(benchmark::kMillisecond);

// The intensity measures of the same record (PGA, baseline-corrected PGV/PGD, Arias, D5-75, D5-95), for scale.
void BM_IntensityMeasures(benchmark::State& state) {
  const sim::GroundMotion motion = rockwatch::bench::earthquake_record(kPgaMps2);
  for (auto _ : state) {
    const sim::IntensityMeasures m = sim::intensity_measures(motion.ug_mps2, motion.dt_s, kG);
    benchmark::DoNotOptimize(m.pgv_mps);
  }
}
BENCHMARK(BM_IntensityMeasures)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
