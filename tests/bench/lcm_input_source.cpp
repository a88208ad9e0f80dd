#include "lcm_input_source.hpp"

#include "lcm_transport.hpp"

namespace rockwatch::bench {

LcmInputSource::~LcmInputSource() {
  lcm_t* const raw = lcm_.getUnderlyingLCM();
  if (accel_ != nullptr) lcm_unsubscribe(raw, accel_);
  if (batch_ != nullptr) lcm_unsubscribe(raw, batch_);
  if (sensor_ != nullptr) lcm_unsubscribe(raw, sensor_);
}

bool LcmInputSource::start(firmware::MultiWallMonitor& walls, std::string* problem) {
  const firmware::MonitorSettings& settings = walls.wall(0).settings();
  const int capacity = monitor::input_queue_capacity(settings.sample_rate_hz);
  lcm_t* const raw = lcm_.getUnderlyingLCM();
  const auto subscribe = [&](const std::string& channel) {
    lcm_subscription_t* s = lcm_subscribe(raw, monitor::exact_channel_regex(channel).c_str(), &on_raw, this);
    if (s != nullptr) lcm_subscription_set_queue_capacity(s, capacity);
    return s;
  };
  accel_ = subscribe(settings.channels.accel);
  batch_ = subscribe(settings.channels.accel_batch);
  const bool observer = settings.engine.observer_enabled;
  if (observer) sensor_ = subscribe(settings.channels.wall_sensor);
  if (accel_ != nullptr && batch_ != nullptr && (!observer || sensor_ != nullptr)) return true;
  *problem = "LCM refused the subscription to the input channels";
  return false;
}

bool LcmInputSource::set_busy_poll(int /*us*/, std::string* problem) {
  *problem = "liblcm owns its socket";
  return false;
}

monitor::InputPoll LcmInputSource::poll(int timeout_ms, monitor::InputMessageSink& sink) {
  sink_ = &sink;
  return lcm_.handleTimeout(timeout_ms) >= 0 ? monitor::InputPoll::ok : monitor::InputPoll::failed;
}

void LcmInputSource::add_summary(nlohmann::json& summary) const {
  summary["receive_path"] = "liblcm";
  summary["lcm_messages"] = messages_;
}

void LcmInputSource::on_raw(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  LcmInputSource* const self = static_cast<LcmInputSource*>(user);
  ++self->messages_;
  const std::int64_t receive_utime = rbuf->recv_utime > 0 ? rbuf->recv_utime : monitor::realtime_utime();
  const auto size = rbuf->data_size > 0 ? static_cast<std::size_t>(rbuf->data_size) : std::size_t{0};
  self->sink_->on_input_message(channel, static_cast<const std::uint8_t*>(rbuf->data), size, receive_utime);
}

}  // namespace rockwatch::bench
