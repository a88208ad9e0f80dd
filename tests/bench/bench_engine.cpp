// Google Benchmark timings of the double-precision engine on the paper wall (r_exp): one stepper step while
// rocking (linear and full model), one step at rest for reference, and sim::analyse of a whole 40 s record.
// Figures, machine and exact commands: docs/BENCHMARKS.md. Run a Release build; report the median of
// --benchmark_repetitions=5.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "synthetic_motion.hpp"

namespace {

using rockwatch::bench::kDt;
using rockwatch::bench::kG;
namespace core = rockwatch::core;
namespace sim = rockwatch::sim;

// 0.2 g rocks the paper wall with a few impacts per second and no collapse (see synthetic_motion.hpp);
// 0.05 g stays below its 0.114 g start threshold, so the wall never leaves rest.
constexpr double kRockingPeakMps2 = 0.2 * kG;
constexpr double kQuietPeakMps2 = 0.05 * kG;

core::RockingStepper<double> make_stepper(core::ModelKind kind) {
  core::StepperOptions options;
  options.dt_s = kDt;
  core::RockingStepper<double> stepper;
  stepper.init(core::make_stepper_setup(core::paper_wall(), kind, core::r_exp(core::paper_wall()), options));
  return stepper;
}

// One iteration = one RockingStepper::step, so the reported time is the time per step. The 40 s stationary
// input is replayed in a loop (it is exactly periodic), which keeps the wall rocking for as many iterations as
// the library asks for; the counters show how the measured steps were spent.
void BM_StepperStep(benchmark::State& state, core::ModelKind kind, double peak_mps2) {
  const std::vector<double> input = rockwatch::bench::stationary_motion(peak_mps2);
  core::RockingStepper<double> stepper = make_stepper(kind);
  stepper.reset(input[0], 0.0);
  // The stepper escapes here and memory is clobbered after every step, so each step loads and stores the
  // state like a call per sample does, instead of the optimiser carrying it in registers from step to step.
  benchmark::DoNotOptimize(&stepper);
  std::size_t n = 1;
  std::int64_t impacts = 0, moving_steps = 0, collapses = 0;
  for (auto _ : state) {
    core::StepReport<double> report = stepper.step(input[n], 0.0);
    benchmark::DoNotOptimize(report);
    impacts += report.impacts_counted;
    moving_steps += stepper.moving() ? 1 : 0;
    // Never expected with this input; without the restart a collapsed stepper would return at once and the
    // figure would silently become the cost of a no-op. The counter makes it visible if the input changes.
    if (stepper.collapsed()) {
      ++collapses;
      stepper.reset(input[n], 0.0);
    }
    n = n + 1 == input.size() ? 0 : n + 1;
    benchmark::ClobberMemory();
  }
  const double steps = double(state.iterations());
  state.SetItemsProcessed(state.iterations());
  state.counters["impacts_per_s"] = steps > 0.0 ? double(impacts) / (steps * kDt) : 0.0;  // simulated time
  state.counters["moving_frac"] = steps > 0.0 ? double(moving_steps) / steps : 0.0;
  state.counters["collapses"] = double(collapses);
}

BENCHMARK_CAPTURE(BM_StepperStep, rocking_linear, core::ModelKind::linear, kRockingPeakMps2);
BENCHMARK_CAPTURE(BM_StepperStep, rocking_full, core::ModelKind::full, kRockingPeakMps2);
BENCHMARK_CAPTURE(BM_StepperStep, quiet_linear, core::ModelKind::linear, kQuietPeakMps2);

// sim::analyse of the 40 s, 8001-sample record at PGA 0.2 g: input checks, 8000 forced steps, the free-motion
// tail until the energy verdict, and the summary. Time is per record; per_step divides it by the steps run.
void BM_WholeRecord(benchmark::State& state, core::ModelKind kind) {
  const sim::GroundMotion motion = rockwatch::bench::earthquake_record(kRockingPeakMps2);
  sim::AnalysisOptions options;
  options.model = kind;
  // The analysis is deterministic, so one untimed run gives the figures of every timed one (and keeps
  // PauseTiming, which costs about as much as a few hundred steps, out of the loop).
  sim::AnalysisOptions probe_options = options;
  probe_options.keep_history = true;  // only to count the steps spent rocking; the timed runs keep none
  const sim::AnalysisResult probe = sim::analyse(core::paper_wall(), motion, probe_options);
  const double steps_per_record = std::round(probe.t_final_s / probe.dt_s);
  std::size_t moving_rows = 0;
  for (const sim::HistoryRow& row : probe.history) moving_rows += row.x_m != 0.0 || row.xd_mps != 0.0 ? 1U : 0U;
  for (auto _ : state) {
    sim::AnalysisResult result = sim::analyse(core::paper_wall(), motion, options);
    benchmark::DoNotOptimize(result);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(steps_per_record));
  state.counters["per_step"] =
      benchmark::Counter(steps_per_record, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["steps"] = steps_per_record;
  state.counters["n_impacts"] = double(probe.n_impacts);
  state.counters["max_abs_x_mm"] = probe.max_abs_x_m * 1e3;
  state.counters["collapse"] = probe.verdict_collapse() ? 1.0 : 0.0;
  state.counters["pga_g"] = probe.pga_mps2 / kG;
  // Share of the record's steps with the wall in motion: the per-step figure mixes rocking and rest steps.
  state.counters["moving_frac"] = double(moving_rows) / double(probe.history.size());
}

BENCHMARK_CAPTURE(BM_WholeRecord, linear, core::ModelKind::linear)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_WholeRecord, full, core::ModelKind::full)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("wall", "paper_wall (b 0.10 m, h1 = h2 1.75 m), r_exp, dt 0.005 s");
  benchmark::AddCustomContext("input", "synthetic Kanai-Tajimi 1.5-15 Hz; stepper: 0.2 g / 0.05 g looped, record: 40 s PGA 0.2 g");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
