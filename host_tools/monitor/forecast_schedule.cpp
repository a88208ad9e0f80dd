#include "forecast_schedule.hpp"

#include <cmath>

namespace rockwatch::monitor {

ForecastTap::ForecastTap(const MonitorConfig& config, firmware::Transport& out) : out_(out) {
  if (!config.forecast.enabled) return;
  feed_ = std::make_unique<ForecastFeed>(config.settings.channels, config.settings.engine.observer_enabled);
  tap_ = std::make_unique<FeedTransport>(out, *feed_);
}

LogTimeForecasts::LogTimeForecasts(MonitorForecaster& forecaster, MonitorClock& clock, firmware::Transport& output)
    : forecaster_(forecaster),
      clock_(clock),
      output_(output),
      period_us_(static_cast<std::int64_t>(std::llround(1e6 / forecaster.config().rate_hz))) {}

void LogTimeForecasts::run_due(std::int64_t now_us) {
  constexpr std::int64_t kMinuteUs = 60 * 1000000;
  if (next_us_ == 0) next_us_ = now_us + period_us_;
  for (; now_us >= next_us_; next_us_ += period_us_) {
    clock_.enter(next_us_);
    const std::size_t n = encode_forecast(forecaster_.run_once(), bytes_);
    forecaster_.note_publish(n > 0 && output_.publish(forecaster_.config().channel.c_str(), bytes_.data(), n));
    if (now_us - next_us_ >= kMinuteUs) next_us_ += (now_us - next_us_) / period_us_ * period_us_;
  }
}

}  // namespace rockwatch::monitor
