// firmware::MultiWallMonitor: the time of one ground message (decode, every wall's engine step, encode and publish of
// each wall's wall_state_t) for 1, 4 and 16 walls on a shared ground channel, the fixed-point engine at 200 Hz, a wall
// rocking (0.15 g at 2 Hz: impacts, the alarm busy, no collapse). The per-wall cost per sample is the slope; the walls
// one core follows at a rate R is 1 / (R x that), bounded by kMaxMonitorWalls (docs/BENCHMARKS.md, "Scale:
// portfolios, shards, MPI").
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

namespace {
namespace fw = rockwatch::firmware;

class NullTransport final : public fw::Transport {
 public:
  bool publish(const char*, const std::uint8_t*, std::size_t size) override {
    bytes += size;
    return true;
  }
  std::size_t bytes = 0;
};

void set(char (&field)[fw::kChannelNameMax], const std::string& name) {
  std::memset(field, 0, sizeof field);
  std::memcpy(field, name.data(), name.size());
}

void BM_MultiWallMessage(benchmark::State& state) {
  const auto walls = static_cast<std::size_t>(state.range(0));
  std::vector<fw::MonitorSettings> settings(walls);
  for (std::size_t i = 0; i < walls; ++i) {
    fw::MonitorSettings& s = settings[i];
    s.engine.wall = rockwatch::core::paper_wall();
    s.engine.wall.h1_m = s.engine.wall.h2_m = 1.5 + 0.02 * double(i);  // all rock at 0.15 g, none collapses
    s.engine.r_energy = rockwatch::core::r_exp(s.engine.wall);
    s.sample_rate_hz = 200.0;
    const std::string n = "_w" + std::to_string(i);
    set(s.channels.wall_state, "ROCKWATCH_WALL_STATE" + n);
    set(s.channels.alarm, "ROCKWATCH_ALARM" + n);
    set(s.channels.status, "ROCKWATCH_STATUS" + n);
    set(s.channels.wall_estimate, "ROCKWATCH_WALL_ESTIMATE" + n);
  }
  std::vector<std::unique_ptr<fw::WallEngine>> engines;
  std::vector<fw::SampleEngine*> engine_ptrs;
  std::vector<fw::MonitorListener*> listeners(walls, nullptr);
  for (std::size_t i = 0; i < walls; ++i) {
    engines.push_back(std::make_unique<fw::WallEngine>());
    engine_ptrs.push_back(engines.back().get());
  }
  NullTransport transport;
  auto multi = std::make_unique<fw::MultiWallMonitor>();
  if (multi->init(settings.data(), engine_ptrs.data(), listeners.data(), walls, transport) != fw::MultiWallError::ok) {
    state.SkipWithError("init refused");
    return;
  }
  // 60 s of samples, encoded beforehand.
  constexpr std::int64_t kSamples = 12000;
  std::vector<std::vector<std::uint8_t>> messages;
  for (std::int64_t k = 0; k < kSamples; ++k) {
    rockwatch::ground_accel_t m{};
    m.utime = 1700000000000000 + k * 5000;
    m.seq = k;
    m.schema_version = 1;
    m.ug_mps2 = 0.15 * 9.81 * std::sin(2.0 * 3.14159265358979 * 2.0 * double(k) * 0.005);
    std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    messages.push_back(b);
  }
  std::size_t k = 0;
  for (auto _ : state) {
    const std::vector<std::uint8_t>& b = messages[k];
    multi->on_message("ROCKWATCH_ACCEL", b.data(), b.size(), 1700000000000000 + std::int64_t(k) * 5000 + 1000);
    if (++k == messages.size()) {
      k = 0;  // seq restarts: a publisher restart, the walls at rest again (a few per run)
      state.PauseTiming();
      state.ResumeTiming();
    }
  }
  state.counters["walls"] = double(walls);
  state.counters["ns_per_wall"] =
      benchmark::Counter(double(walls), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  benchmark::DoNotOptimize(transport.bytes);
}
BENCHMARK(BM_MultiWallMessage)->Arg(1)->Arg(4)->Arg(16);

}  // namespace

BENCHMARK_MAIN();
