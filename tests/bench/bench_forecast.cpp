// Google Benchmark: the cost of one ensemble forecast of collapse (sim::EnsembleForecaster, SPEC §10, issue 29) on
// the paper wall (r_exp), horizon 5 s, the default settings (members' step 10 ms), against the number of members N
// (the target: 200 members over 5 s ≤ 10 ms on one core). Two states, the ground model fitted to the last 4 s of the
// stationary synthetic record (synthetic_motion.hpp):
//   rocking  x = 0.3 x_inst, ẋ = 0.2 v_b on the 0.2 g record: some members collapse (and stop early);
//   settling x = 0.1 x_inst, ẋ = 0 on the 0.1 g record: nearly every member runs the whole horizon.
// Counters: P(collapse), member-steps per forecast (at most: members that collapse stop), member-steps per second,
// and heap allocations per forecast (counted by the global operator new below: 0 = allocation-free after set-up).
// Figures and exact commands: docs/BENCHMARKS.md, "Forecast". Run a Release build.
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include <benchmark/benchmark.h>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/ensemble_forecast.hpp"
#include "synthetic_motion.hpp"

namespace {
std::atomic<std::int64_t> g_allocations{0};
// Out of line, so the compiler does not pair the replaced operator new with a visible free() (-Wmismatched-new-delete).
[[gnu::noinline]] void release(void* p) noexcept { std::free(p); }
}  // namespace

// Plain new and delete (array new calls them): what a std::vector in the forecaster would use.
void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }

namespace {

namespace core = rockwatch::core;
namespace sim = rockwatch::sim;
using rockwatch::bench::kDt;
using rockwatch::bench::kG;

void BM_Forecast(benchmark::State& state, double peak_g, double x_over_x_inst, double xd_over_v_b) {
  const std::vector<double> motion = rockwatch::bench::stationary_motion(peak_g * kG);
  const std::size_t n_recent = static_cast<std::size_t>(20.0 / kDt);  // the record up to t = 20 s
  sim::ForecastSettings s;
  s.members = static_cast<int>(state.range(0));
  s.horizon_s = 5.0;
  const core::WallParameters w = core::paper_wall();
  sim::ForecastState st;
  st.moving = true;
  {
    const sim::EnsembleForecaster probe(w, core::ModelKind::linear, core::r_exp(w), 2.0, s);
    st.x_m = x_over_x_inst * std::fmin(probe.setup().x_inst_m[0], probe.setup().x_inst_m[1]);
    st.xd_mps = xd_over_v_b * probe.velocity_scale_mps();
  }
  st.ug_now_mps2 = motion[n_recent - 1];
  if (state.range(1) > 0) s.rest_speed_mps = 1e-7;  // SPEC §3's rest threshold, for comparison
  if (state.range(2) > 0) s.step_s = 1e-3 * double(state.range(2));  // another members' step [ms]
  sim::EnsembleForecaster f(w, core::ModelKind::linear, core::r_exp(w), 2.0, s);
  sim::ForecastResult r;
  std::int64_t allocations = 0;
  for (auto _ : state) {
    const std::int64_t before = g_allocations.load();
    r = f.forecast(st, motion.data(), n_recent, kDt);
    allocations += g_allocations.load() - before;
    benchmark::DoNotOptimize(r);
  }
  const double forecasts = double(state.iterations());
  state.counters["p_collapse"] = r.p_collapse;
  state.counters["allocs_per_forecast"] = double(allocations) / forecasts;
  state.counters["member_steps"] = double(s.members) * std::ceil(s.horizon_s / s.step_s);
  state.counters["member_steps_per_s"] =
      benchmark::Counter(double(s.members) * std::ceil(s.horizon_s / s.step_s) * forecasts, benchmark::Counter::kIsRate);
}

}  // namespace

// Args: N; 1 for SPEC §3's rest threshold 1e-7 m/s instead of the forecast's 1 mm/s (ForecastSettings); the members'
// step in ms (0: the default 10 ms).
BENCHMARK_CAPTURE(BM_Forecast, rocking, 0.2, 0.3, 0.2)
    ->ArgsProduct({{25, 50, 100, 200, 400, 800}, {0}, {0}})->Args({200, 1, 0})->Args({200, 0, 5})->Args({200, 0, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Forecast, settling, 0.1, 0.1, 0.0)
    ->ArgsProduct({{25, 50, 100, 200, 400, 800}, {0}, {0}})->Args({200, 1, 0})->Args({200, 0, 5})->Args({200, 0, 1})
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
