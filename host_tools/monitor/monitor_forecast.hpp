// rockwatch-monitor --forecast (issue 29 item 3): the ensemble forecast of collapse (sim::EnsembleForecaster, SPEC
// §10) computed live, at a configured rate, from the wall's latest state, and published as wall_forecast_t.
//
// The sample path is never held by it. What the sample path does for the forecast is bounded and wait-free:
//   - every ground message it receives (ground_accel_t, ground_accel_batch_t) is copied, raw, into a single-producer
//     single-consumer ring (ForecastFeed::on_input: one memcpy of ≤ 1 KiB; a full ring drops the message and counts
//     it, it never waits);
//   - every wall_state_t and wall_estimate_t it publishes is copied, raw, into a seqlock slot (on_output: the latest
//     one only; the writer never waits, a reader retries).
// The forecast thread decodes them, keeps the last seconds of ü, and every 1/rate s runs one forecast from the latest
// state (the fused state, σ and the estimated √r, κc, κk when the observer is on) and publishes it on its own LCM
// instance (live) — so the sample path's lcm_publish never waits for the forecast's. When a forecast takes longer
// than the period, the ticks it overran are skipped and counted (wall_forecast_t.ticks_skipped): the forecast rate
// drops, the sample path does not. The thread runs under ordinary scheduling at nice +10 whatever the receive thread
// has (--realtime: it does not inherit SCHED_FIFO), and off the receive thread's CPU when that is pinned (--cpu).
//
// Offline (--offline-in): the same forecaster is run synchronously every 1/rate s of log time, so the output log
// stays deterministic.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "monitor_config.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/sim/ensemble_forecast.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/wall_forecast_t.hpp"

namespace rockwatch::monitor {

// The latest value of a message written by one thread, read by another: a sequence lock over atomic words (no data
// race, no wait for the writer; the reader retries while a write is under way).
class SeqlockSlot {
 public:
  static constexpr std::size_t kBytes = 512;  // wall_state_t ≈ 100 B, wall_estimate_t ≈ 300 B
  // Sample path. false (and nothing stored) when the message is larger than kBytes.
  bool write(const std::uint8_t* data, std::size_t size);
  // Forecast thread: the latest message into out (kBytes); its size, or 0 when none was written or every attempt
  // met a write under way.
  std::size_t read(std::uint8_t* out) const;

 private:
  static constexpr std::size_t kWords = kBytes / 8;
  std::atomic<std::uint32_t> seq_{0};
  std::atomic<std::uint32_t> size_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

// The hand-over from the sample path (producer) to the forecast thread (consumer).
class ForecastFeed {
 public:
  static constexpr std::size_t kSlots = 2048;      // at 1 kHz single-sample messages: 2 s of input
  static constexpr std::size_t kSlotBytes = 1024;  // ground_accel_batch_t is 852 bytes
  enum : std::uint8_t { kAccel = 0, kAccelBatch = 1 };

  ForecastFeed(const firmware::MonitorChannels& channels, bool observer);

  // Sample path (the one receive thread): wait-free.
  void on_input(const char* channel, const std::uint8_t* data, std::size_t size);
  void on_output(const char* channel, const std::uint8_t* data, std::size_t size);

  // Forecast thread: every queued ground message, oldest first: fn(kind, data, size).
  template <typename Fn>
  void drain(Fn&& fn) {
    std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    for (; tail != head; ++tail) {
      const Slot& s = slots_[tail % kSlots];
      fn(s.kind, s.data, s.size);
    }
    tail_.store(tail, std::memory_order_release);
  }
  std::size_t read_state(std::uint8_t* out) const { return state_.read(out); }
  std::size_t read_estimate(std::uint8_t* out) const { return estimate_.read(out); }
  std::int64_t input_dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  struct Slot {
    std::uint32_t size = 0;
    std::uint8_t kind = 0;
    std::uint8_t data[kSlotBytes];
  };
  std::string accel_, accel_batch_, wall_state_, wall_estimate_;
  bool observer_ = false;
  std::unique_ptr<Slot[]> slots_;
  std::atomic<std::uint64_t> head_{0}, tail_{0};
  std::atomic<std::int64_t> dropped_{0};
  SeqlockSlot state_, estimate_;
};

// Wraps the loop's transport: each message also goes to the feed (the latest wall state and estimate).
class FeedTransport final : public firmware::Transport {
 public:
  FeedTransport(firmware::Transport& inner, ForecastFeed& feed) : inner_(inner), feed_(feed) {}
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override {
    feed_.on_output(channel, data, size);
    return inner_.publish(channel, data, size);
  }

 private:
  firmware::Transport& inner_;
  ForecastFeed& feed_;
};

// What the forecasts did, for the monitor's summary.
struct ForecastCounters {
  std::int64_t published = 0, ok = 0, at_rest = 0, no_input = 0, collapsed = 0, publish_failures = 0;
  std::int64_t ticks_skipped = 0, input_dropped = 0, ground_samples = 0, ground_resets = 0;
  std::int64_t compute_us_max = 0;
  double compute_us_sum = 0.0;
};

// The forecaster fed from a ForecastFeed: drain the ground, read the latest state, forecast. One thread at a time.
class MonitorForecaster {
 public:
  // Throws std::invalid_argument for settings the forecaster refuses.
  // measure_time false (offline): compute_us is 0, so the output log stays the same byte for byte.
  MonitorForecaster(const ForecastConfig& config, const firmware::MonitorSettings& settings, ForecastFeed& feed,
                    bool measure_time = true);

  // One forecast now, as the message to publish (seq, compute_us and the counters filled in).
  const rockwatch::wall_forecast_t& run_once();
  void note_ticks_skipped(std::int64_t n) { counters_.ticks_skipped += n; }
  void note_publish(bool ok) {
    ++counters_.published;
    if (!ok) ++counters_.publish_failures;
  }
  const ForecastCounters& counters() const { return counters_; }
  const ForecastConfig& config() const { return config_; }

 private:
  void take_ground(std::uint8_t kind, const std::uint8_t* data, std::size_t size);
  void push_ground(std::int64_t utime, double ug_mps2);

  ForecastConfig config_;
  ForecastFeed& feed_;
  bool observer_ = false;
  bool measure_time_ = true;
  double dt_s_ = 0.0;
  sim::EnsembleForecaster forecaster_;
  sim::ForecastCalibration calibration_;  // the configured coefficients, or the shipped ones
  sim::ForecastCalibration calibration_fused_;  // for a forecast from the fused state: the same configured, or its own
  bool calibration_applied_ = false;      // given, or the shipped ones at their own horizon
  sim::TrailingMax energy_;               // E/E_barrier of the states read at the forecast ticks, over 2 s
  double c_nominal_mps2_ = 0.0, k_nominal_ps2_ = 0.0;  // per unit p1, side +1 (wall_estimate_t's c and k)
  std::vector<double> ground_;     // the last samples of ü, a ring of ground_.size()
  std::vector<double> window_;     // the ring in time order, for the fit
  std::size_t ground_count_ = 0, ground_next_ = 0;
  std::int64_t last_ground_utime_ = 0;
  std::vector<std::uint8_t> buffer_;  // a decoding buffer of SeqlockSlot::kBytes
  rockwatch::wall_forecast_t message_{};
  ForecastCounters counters_;
};

// The live forecast thread: every 1/rate s, MonitorForecaster::run_once and publish(channel, bytes).
class ForecastThread {
 public:
  using Publish = std::function<bool(const std::string& channel, const std::uint8_t* data, std::size_t size)>;
  // avoid_cpu ≥ 0: the CPU the receive thread is pinned to (--cpu); the forecast thread runs on the others.
  ForecastThread(MonitorForecaster& forecaster, Publish publish, int avoid_cpu = -1);
  ~ForecastThread();  // stops and joins
  void stop();
  ForecastThread(const ForecastThread&) = delete;
  ForecastThread& operator=(const ForecastThread&) = delete;

 private:
  void run();
  MonitorForecaster& forecaster_;
  Publish publish_;
  int avoid_cpu_ = -1;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

// Encodes the message into bytes (grown as needed) and returns its size, or 0 when encoding failed.
std::size_t encode_forecast(const rockwatch::wall_forecast_t& m, std::vector<std::uint8_t>& bytes);

// The human summary's forecast line.
void forecast_human_summary(std::ostream& err, const ForecastCounters& counters);

// The summary's "forecast" object.
nlohmann::json forecast_summary(const ForecastConfig& config, const ForecastCounters& counters);

}  // namespace rockwatch::monitor
