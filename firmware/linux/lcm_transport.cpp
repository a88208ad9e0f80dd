#include "lcm_transport.hpp"

#include <time.h>

#include <climits>
#include <cstring>
#include <string>

namespace rockwatch::monitor {

std::int64_t realtime_utime() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000 + static_cast<std::int64_t>(ts.tv_nsec) / 1000;
}

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + static_cast<std::int64_t>(ts.tv_nsec);
}

std::string exact_channel_regex(const std::string& channel) {
  // Every character that means something outside brackets in a GLib (PCRE) expression, which liblcm uses, is
  // escaped; a backslash before punctuation always means the character itself.
  static const char* const kSpecial = ".^$|()[]{}*+?\\";
  std::string regex;
  for (const char c : channel) {
    if (std::strchr(kSpecial, c) != nullptr) regex += '\\';
    regex += c;
  }
  return regex;
}

bool LcmTransport::publish(const char* channel, const std::uint8_t* data, std::size_t size) {
  if (size > static_cast<std::size_t>(UINT_MAX)) return false;
  return lcm_.publish(channel, data, static_cast<unsigned int>(size)) == 0;
}

LcmInput::LcmInput(lcm::LCM& lcm, firmware::MonitorLoop& loop) : lcm_(lcm), loop_(loop) {
  const firmware::MonitorChannels& c = loop.settings().channels;
  accel_ = lcm_.subscribeFunction(exact_channel_regex(c.accel), &LcmInput::on_raw, this);
  batch_ = lcm_.subscribeFunction(exact_channel_regex(c.accel_batch), &LcmInput::on_raw, this);
}

LcmInput::~LcmInput() {
  if (accel_ != nullptr) lcm_.unsubscribe(accel_);
  if (batch_ != nullptr) lcm_.unsubscribe(batch_);
}

void LcmInput::on_raw(const lcm::ReceiveBuffer* rbuf, const std::string& channel, LcmInput* self) {
  ++self->messages_;
  const std::int64_t receive_utime = rbuf->recv_utime > 0 ? rbuf->recv_utime : realtime_utime();
  const auto size = rbuf->data_size > 0 ? static_cast<std::size_t>(rbuf->data_size) : std::size_t{0};
  self->loop_.on_message(channel.c_str(), static_cast<const std::uint8_t*>(rbuf->data), size, receive_utime);
}

bool LogTransport::publish(const char* channel, const std::uint8_t* data, std::size_t size) {
  if (size > static_cast<std::size_t>(INT32_MAX)) {
    ++failures_;
    return false;
  }
  lcm::LogEvent event{};
  event.eventnum = 0;  // set by the writer
  event.timestamp = event_utime_;
  event.channel = channel;
  event.datalen = static_cast<std::int32_t>(size);
  event.data = const_cast<std::uint8_t*>(data);  // lcm's C API takes void*; it only reads
  if (log_.writeEvent(&event) != 0) {
    ++failures_;
    return false;
  }
  ++written_;
  return true;
}

}  // namespace rockwatch::monitor
