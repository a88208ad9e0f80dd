#include "monitor_forecast.hpp"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "rockwatch/core/model.hpp"
#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/wall_estimate_t.hpp"
#include "rockwatch/wall_state_t.hpp"

namespace rockwatch::monitor {

namespace {

// A gap in the ground stream longer than this starts the ground history again (the fit assumes evenly spaced
// samples; a gap of a few samples, which the loop bridges, is kept as if none were missing) [µs].
constexpr std::int64_t kGroundResetGap_us = 1000000;
// The ground history: the forecaster's window plus a margin [s].
constexpr double kGroundMargin_s = 1.0;

std::int64_t steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

sim::ForecastSettings forecaster_settings(const ForecastConfig& c) {
  sim::ForecastSettings s;
  s.members = c.members;
  s.horizon_s = c.horizon_s;
  s.seed = c.seed;
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------

bool SeqlockSlot::write(const std::uint8_t* data, std::size_t size) {
  if (size > kBytes) return false;
  const std::uint32_t s = seq_.load(std::memory_order_relaxed);
  seq_.store(s + 1, std::memory_order_relaxed);  // odd: a write is under way
  std::atomic_thread_fence(std::memory_order_release);
  for (std::size_t w = 0; w * 8 < size; ++w) {
    std::uint64_t word = 0;
    std::memcpy(&word, data + w * 8, std::min<std::size_t>(8, size - w * 8));
    words_[w].store(word, std::memory_order_relaxed);
  }
  size_.store(static_cast<std::uint32_t>(size), std::memory_order_relaxed);
  seq_.store(s + 2, std::memory_order_release);
  return true;
}

std::size_t SeqlockSlot::read(std::uint8_t* out) const {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const std::uint32_t s1 = seq_.load(std::memory_order_acquire);
    if (s1 == 0) return 0;       // never written
    if (s1 & 1u) continue;       // a write is under way
    const std::size_t size = size_.load(std::memory_order_relaxed);
    for (std::size_t w = 0; w * 8 < size; ++w) {
      const std::uint64_t word = words_[w].load(std::memory_order_relaxed);
      std::memcpy(out + w * 8, &word, std::min<std::size_t>(8, size - w * 8));
    }
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) == s1) return size;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------------------------

ForecastFeed::ForecastFeed(const firmware::MonitorChannels& channels, bool observer)
    : accel_(channels.accel),
      accel_batch_(channels.accel_batch),
      wall_state_(channels.wall_state),
      wall_estimate_(channels.wall_estimate),
      observer_(observer),
      slots_(new Slot[kSlots]) {}

void ForecastFeed::on_input(const char* channel, const std::uint8_t* data, std::size_t size) {
  std::uint8_t kind;
  if (accel_ == channel) {
    kind = kAccel;
  } else if (accel_batch_ == channel) {
    kind = kAccelBatch;
  } else {
    return;  // the wall sensors: the observer's; the forecast takes the fused state from wall_estimate_t
  }
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  const std::uint64_t tail = tail_.load(std::memory_order_acquire);
  if (head - tail >= kSlots || size > kSlotBytes) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  Slot& s = slots_[head % kSlots];
  std::memcpy(s.data, data, size);
  s.size = static_cast<std::uint32_t>(size);
  s.kind = kind;
  head_.store(head + 1, std::memory_order_release);
}

void ForecastFeed::on_output(const char* channel, const std::uint8_t* data, std::size_t size) {
  if (wall_state_ == channel) {
    state_.write(data, size);
  } else if (observer_ && wall_estimate_ == channel) {
    estimate_.write(data, size);
  }
}

// ---------------------------------------------------------------------------------------------------------------

MonitorForecaster::MonitorForecaster(const ForecastConfig& config, const firmware::MonitorSettings& settings,
                                     ForecastFeed& feed, bool measure_time)
    : config_(config),
      feed_(feed),
      observer_(settings.engine.observer_enabled),
      measure_time_(measure_time),
      dt_s_(1.0 / settings.sample_rate_hz),
      forecaster_(settings.engine.wall, settings.engine.model, settings.engine.r_energy, settings.engine.kappa,
                  forecaster_settings(config)),
      energy_(static_cast<std::size_t>(std::ceil(sim::kCalibrationEnergyWindow_s * config.rate_hz)) + 4) {
  if (config.calibration) {
    calibration_.c = *config.calibration;
    calibration_.horizon_s = config.horizon_s;
    calibration_.source = "configured";
    calibration_fused_ = calibration_;
    calibration_applied_ = true;
  } else if (const auto shipped = sim::default_forecast_calibration(config.horizon_s)) {
    // A forecast from the observer's fused state takes the coefficients fitted on such forecasts (SPEC §10).
    calibration_ = *shipped;
    calibration_fused_ = *sim::default_forecast_calibration(config.horizon_s, true);
    calibration_applied_ = true;
  }
  const core::Coefficients<double> k =
      core::evaluate(forecaster_.setup().model, core::Side::positive, 0.0, settings.engine.wall.g_mps2);
  c_nominal_mps2_ = std::fabs(k.p6) / k.p1;
  k_nominal_ps2_ = std::fabs(k.p4) / k.p1;
  const auto n = static_cast<std::size_t>(
      std::ceil((forecaster_.settings().window_s + kGroundMargin_s) * settings.sample_rate_hz)) + 2;
  ground_.assign(n, 0.0);
  window_.assign(n, 0.0);
  buffer_.assign(SeqlockSlot::kBytes, 0);
  message_.wall = "wall";
  message_.schema_version = rockwatch::wall_forecast_t::SCHEMA_VERSION;
  message_.horizon_s = config.horizon_s;
  message_.rate_hz = config.rate_hz;
}

void MonitorForecaster::push_ground(std::int64_t utime, double ug) {
  if (ground_count_ > 0 && utime <= last_ground_utime_) return;  // a repeat or out of order: the loop's concern
  if (ground_count_ > 0 && utime - last_ground_utime_ > kGroundResetGap_us) {
    ground_count_ = 0;
    ++counters_.ground_resets;
  }
  last_ground_utime_ = utime;
  ground_[ground_next_] = ug;
  ground_next_ = (ground_next_ + 1) % ground_.size();
  ground_count_ = std::min(ground_count_ + 1, ground_.size());
  ++counters_.ground_samples;
}

void MonitorForecaster::take_ground(std::uint8_t kind, const std::uint8_t* data, std::size_t size) {
  const int n = static_cast<int>(size);
  if (kind == ForecastFeed::kAccel) {
    rockwatch::ground_accel_t m{};  // (zeroed: g++ -O3 compiling this file alone cannot see that decode fills it)
    if (m.decode(data, 0, n) != n) return;
    if (std::isfinite(m.ug_mps2)) push_ground(m.utime, m.ug_mps2);
    return;
  }
  rockwatch::ground_accel_batch_t m{};
  if (m.decode(data, 0, n) != n) return;
  if (m.count < 1 || m.count > rockwatch::ground_accel_batch_t::MAX_SAMPLES || m.sample_period_us <= 0) return;
  for (int i = 0; i < m.count; ++i) {
    if (std::isfinite(m.ug_mps2[i])) push_ground(m.utime + std::int64_t(i) * m.sample_period_us, m.ug_mps2[i]);
  }
}

const rockwatch::wall_forecast_t& MonitorForecaster::run_once() {
  const std::int64_t start_us = steady_us();
  feed_.drain([this](std::uint8_t kind, const std::uint8_t* data, std::size_t size) { take_ground(kind, data, size); });
  rockwatch::wall_forecast_t& m = message_;
  ++m.seq;
  m.status = rockwatch::wall_forecast_t::STATUS_NO_INPUT;
  m.fused = 0;
  m.members = 0;
  m.p_collapse = m.p_collapse_se = m.q50_max_x_over_x_inst = m.q90_max_x_over_x_inst = 0.0;
  m.sigma_now_mps2 = m.omega_g_rps = m.growth_per_s = 0.0;
  m.p_collapse_calibrated = std::numeric_limits<double>::quiet_NaN();
  m.energy_ratio_max_2s = m.x_over_x_inst = std::numeric_limits<double>::quiet_NaN();
  rockwatch::wall_state_t state{};  // (zeroed, as in take_ground: for g++ compiling this file alone)
  const std::size_t state_size = feed_.read_state(buffer_.data());
  const bool have_state =
      state_size > 0 && state.decode(buffer_.data(), 0, static_cast<int>(state_size)) == static_cast<int>(state_size);
  if (have_state) {
    m.utime = state.utime;
    // ρ_max of the calibration: the wall states read at the forecast ticks (not every sample) over the last 2 s.
    if (std::isfinite(state.energy_ratio)) energy_.push(double(state.utime) * 1e-6, state.energy_ratio);
    if (const auto e = energy_.max()) m.energy_ratio_max_2s = *e;
  }
  if (have_state && state.alarm_level == rockwatch::alarm_event_t::LEVEL_COLLAPSED) {
    // The wall has fallen (the engine stops at κ·x_inst and the alarm latches): certain, nothing to run.
    m.status = rockwatch::wall_forecast_t::STATUS_COLLAPSED;
    m.p_collapse = 1.0;
    m.p_collapse_calibrated = 1.0;
    ++counters_.collapsed;
  } else if (have_state && ground_count_ >= 2) {
    sim::ForecastState st;
    st.moving = state.moving != 0;
    st.x_m = state.x_m;
    st.xd_mps = state.xd_mps;
    st.ug_now_mps2 = ground_[(ground_next_ + ground_.size() - 1) % ground_.size()];
    if (observer_) {
      rockwatch::wall_estimate_t e{};
      const std::size_t size = feed_.read_estimate(buffer_.data());
      if (size > 0 && e.decode(buffer_.data(), 0, static_cast<int>(size)) == static_cast<int>(size)) {
        // The fused state and the estimated wall (SPEC §10 "State uncertainty"); its spread only while a
        // displacement reading bounds it: with the sensor lost or never there, the filter's σ grows with its process
        // noise alone and members drawn from it fall at once (SPEC §10 "From the fused state"), so the members start
        // at the state and the open loop's coefficients apply (fused = 0), as in simulate.
        st.x_m = e.x_m;
        st.xd_mps = e.xd_mps;
        st.moving = st.moving || e.x_m != 0.0 || e.xd_mps != 0.0;
        if (e.sensor_health & rockwatch::wall_estimate_t::SENSOR_X_ACTIVE) {
          st.sigma_x_m = e.sigma_x_m;
          st.sigma_xd_mps = e.sigma_xd_mps;
          m.fused = 1;
        }
        if (e.r_estimate >= 0.0 && e.r_estimate <= 1.0) st.sqrt_r = std::sqrt(e.r_estimate);
        if (e.c_estimate_mps2 > 0.0 && e.k_estimate_ps2 > 0.0) {
          st.capacity_scale = e.c_estimate_mps2 / c_nominal_mps2_;
          st.stiffness_scale = e.k_estimate_ps2 / k_nominal_ps2_;
        }
      }
    }
    // The ring in time order.
    const std::size_t n = ground_count_, size = ground_.size();
    const std::size_t first = (ground_next_ + size - n) % size;
    for (std::size_t i = 0; i < n; ++i) window_[i] = ground_[(first + i) % size];
    const sim::ForecastResult f = forecaster_.forecast(st, window_.data(), n, dt_s_);
    m.x_over_x_inst = forecaster_.x_over_x_inst(st.x_m, state.side);
    if (f.status == sim::ForecastStatus::wall_at_rest) {
      m.status = rockwatch::wall_forecast_t::STATUS_AT_REST;
      m.p_collapse_calibrated = 0.0;
      ++counters_.at_rest;
    } else {
      m.status = rockwatch::wall_forecast_t::STATUS_OK;
      m.members = f.members;
      m.p_collapse = f.p_collapse;
      m.p_collapse_se = f.p_collapse_se;
      m.q50_max_x_over_x_inst = f.q50_max_x_over_x_inst;
      m.q90_max_x_over_x_inst = f.q90_max_x_over_x_inst;
      m.sigma_now_mps2 = f.ground.sigma_now_mps2;
      m.omega_g_rps = f.ground.omega_rps;
      m.growth_per_s = f.ground.growth_per_s;
      if (calibration_applied_ && std::isfinite(m.energy_ratio_max_2s)) {
        m.p_collapse_calibrated = sim::calibrated_probability(m.fused ? calibration_fused_ : calibration_,
                                                              f.p_collapse, f.members,
                                                              m.energy_ratio_max_2s, m.x_over_x_inst);
      }
      ++counters_.ok;
    }
  } else {
    ++counters_.no_input;
  }
  m.compute_us = measure_time_ ? steady_us() - start_us : 0;
  counters_.compute_us_max = std::max(counters_.compute_us_max, m.compute_us);
  counters_.compute_us_sum += double(m.compute_us);
  counters_.input_dropped = feed_.input_dropped();
  m.ticks_skipped = counters_.ticks_skipped;
  m.input_dropped = counters_.input_dropped;
  return m;
}

// ---------------------------------------------------------------------------------------------------------------

ForecastThread::ForecastThread(MonitorForecaster& forecaster, Publish publish, int avoid_cpu)
    : forecaster_(forecaster), publish_(std::move(publish)), avoid_cpu_(avoid_cpu), thread_([this] { run(); }) {}

ForecastThread::~ForecastThread() { stop(); }

void ForecastThread::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ForecastThread::run() {
  // SIGINT and SIGTERM are the receive thread's to take (its wait is what they should interrupt).
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  // Below the receive thread: a thread started after --realtime inherits SCHED_FIFO and the CPU pinning; the
  // forecast takes milliseconds at a time and must never hold the sample path's CPU at its priority.
  const sched_param ordinary{};
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &ordinary);
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
  if (avoid_cpu_ >= 0) {
    cpu_set_t cpus;
    CPU_ZERO(&cpus);
    const long online = sysconf(_SC_NPROCESSORS_ONLN);
    for (long c = 0; c < online && c < CPU_SETSIZE; ++c) {
      if (c != avoid_cpu_) CPU_SET(static_cast<int>(c), &cpus);
    }
    if (CPU_COUNT(&cpus) > 0) pthread_setaffinity_np(pthread_self(), sizeof cpus, &cpus);
  }
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<clock::duration>(
      std::chrono::duration<double>(1.0 / forecaster_.config().rate_hz));
  std::vector<std::uint8_t> bytes;
  auto next = clock::now() + period;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    if (wake_.wait_until(lock, next, [this] { return stop_; })) break;
    lock.unlock();
    const rockwatch::wall_forecast_t& m = forecaster_.run_once();
    const std::size_t size = encode_forecast(m, bytes);
    forecaster_.note_publish(size > 0 && publish_(forecaster_.config().channel, bytes.data(), size));
    // The ticks this forecast overran are skipped, not made up: the rate drops.
    next += period;
    const auto now = clock::now();
    if (now >= next) {
      const auto missed = (now - next) / period + 1;
      forecaster_.note_ticks_skipped(static_cast<std::int64_t>(missed));
      next += missed * period;
    }
    lock.lock();
  }
}

std::size_t encode_forecast(const rockwatch::wall_forecast_t& m, std::vector<std::uint8_t>& bytes) {
  const int size = m.getEncodedSize();
  if (size <= 0) return 0;
  bytes.resize(static_cast<std::size_t>(size));
  return m.encode(bytes.data(), 0, size) == size ? static_cast<std::size_t>(size) : 0;
}

void forecast_human_summary(std::ostream& err, const ForecastCounters& c) {
  const std::int64_t runs = c.ok + c.at_rest + c.no_input + c.collapsed;
  err << "  forecast: " << c.published << " published (" << c.ok << " forecasts, " << c.at_rest << " at rest, "
      << c.no_input << " without input, " << c.collapsed << " after the collapse), " << c.ticks_skipped << " ticks skipped, " << c.input_dropped
      << " ground messages dropped; compute mean " << (runs > 0 ? c.compute_us_sum / double(runs) : 0.0) << " us, max "
      << c.compute_us_max << " us\n";
}

nlohmann::json forecast_summary(const ForecastConfig& config, const ForecastCounters& c) {
  const std::int64_t runs = c.ok + c.at_rest + c.no_input + c.collapsed;
  return {{"channel", config.channel},
          {"members", config.members},
          {"horizon_s", config.horizon_s},
          {"rate_hz", config.rate_hz},
          {"published", c.published},
          {"publish_failures", c.publish_failures},
          {"forecasts", c.ok},
          {"at_rest", c.at_rest},
          {"no_input", c.no_input},
          {"collapsed", c.collapsed},
          {"ticks_skipped", c.ticks_skipped},
          {"input_dropped", c.input_dropped},
          {"ground_samples", c.ground_samples},
          {"ground_resets", c.ground_resets},
          {"compute_us_max", c.compute_us_max},
          {"compute_us_mean", runs > 0 ? c.compute_us_sum / double(runs) : 0.0},
          {"calibration", config.calibration ? nlohmann::json(*config.calibration) : nlohmann::json("default")}};
}

}  // namespace rockwatch::monitor
