// When the monitor's forecasts (--forecast, monitor_forecast.hpp) run, as the monitor loop (monitor_event_loop.hpp)
// sees it: the loop asks for the forecasts due at its clock's time before each input and stops them at shutdown.
// Live they run in their own thread, which keeps its own time (the sample path never waits for a forecast); a replay
// runs them in the loop, in log time, so the output log is the same for the same input.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "monitor_clock.hpp"
#include "monitor_config.hpp"
#include "monitor_forecast.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"

namespace rockwatch::monitor {

// With --forecast, the loop's outputs also go to the forecast's feed (the latest states, monitor_forecast.hpp) on
// their way to `out`; without it, straight to `out`.
class ForecastTap {
 public:
  ForecastTap(const MonitorConfig& config, firmware::Transport& out);
  firmware::Transport& transport() { return tap_ ? static_cast<firmware::Transport&>(*tap_) : out_; }
  ForecastFeed* feed() { return feed_.get(); }  // null without --forecast

 private:
  firmware::Transport& out_;
  std::unique_ptr<ForecastFeed> feed_;
  std::unique_ptr<FeedTransport> tap_;
};

class ForecastSchedule {
 public:
  virtual ~ForecastSchedule() = default;
  // Runs the forecasts due at or before now_us (the loop's clock), from what the loop has done by then.
  virtual void run_due(std::int64_t now_us) = 0;
  // At shutdown, before the loop's last samples and status: no forecast runs after this.
  virtual void stop() = 0;
};

// Live: the ForecastThread (set once the loop has started) runs on its own; stop() joins it.
class ThreadForecasts final : public ForecastSchedule {
 public:
  void start(std::unique_ptr<ForecastThread> thread) { thread_ = std::move(thread); }
  void run_due(std::int64_t /*now_us*/) override {}
  void stop() override {
    if (thread_) thread_->stop();
  }

 private:
  std::unique_ptr<ForecastThread> thread_;
};

// Offline: every 1/rate s of log time after the first event, synchronously, published on `output` at the tick's
// time (compute_us 0: the forecaster does not measure time). A gap of a minute or more in the log gets one forecast.
class LogTimeForecasts final : public ForecastSchedule {
 public:
  LogTimeForecasts(MonitorForecaster& forecaster, MonitorClock& clock, firmware::Transport& output);
  void run_due(std::int64_t now_us) override;
  void stop() override {}

 private:
  MonitorForecaster& forecaster_;
  MonitorClock& clock_;
  firmware::Transport& output_;
  std::int64_t period_us_ = 0;
  std::int64_t next_us_ = 0;  // 0: not scheduled yet (before the first event)
  std::vector<std::uint8_t> bytes_;
};

}  // namespace rockwatch::monitor
