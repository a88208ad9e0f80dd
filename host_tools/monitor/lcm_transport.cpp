#include "lcm_transport.hpp"

#include <time.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
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

int input_queue_capacity(double sample_rate_hz) {
  const double seconds_of_input = std::ceil(kInputQueueSeconds * sample_rate_hz);
  if (!(seconds_of_input > kMinInputQueueMessages)) return kMinInputQueueMessages;  // also NaN
  return seconds_of_input >= static_cast<double>(INT_MAX) ? INT_MAX : static_cast<int>(seconds_of_input);
}

namespace {

constexpr const char* kUdpmScheme = "udpm://";
constexpr const char* kReceiveBufferOption = "recv_buf_size";

bool is_udpm(const std::string& url) { return url.rfind(kUdpmScheme, 0) == 0; }

// The value of option `name` in the query of `url` ("...?a=1&name=2"), or none.
bool find_option(const std::string& url, const std::string& name, std::string& value) {
  const std::size_t query = url.find('?');
  if (query == std::string::npos) return false;
  std::size_t at = query + 1;
  while (at <= url.size()) {
    const std::size_t end = std::min(url.find('&', at), url.size());
    const std::string item = url.substr(at, end - at);
    const std::size_t eq = item.find('=');
    if (item.substr(0, eq) == name) {
      value = eq == std::string::npos ? std::string() : item.substr(eq + 1);
      return true;
    }
    at = end + 1;
  }
  return false;
}

}  // namespace

std::string with_receive_buffer(const std::string& url, int bytes) {
  std::string value;
  if (!is_udpm(url) || bytes <= 0 || find_option(url, kReceiveBufferOption, value)) return url;
  std::string out = url;
  if (out.find('?') == std::string::npos) out += '?';
  else if (out.back() != '?' && out.back() != '&') out += '&';
  return out + kReceiveBufferOption + "=" + std::to_string(bytes);
}

long long requested_receive_buffer(const std::string& url) {
  std::string value;
  if (!is_udpm(url) || !find_option(url, kReceiveBufferOption, value)) return 0;
  return std::max(0LL, std::strtoll(value.c_str(), nullptr, 0));  // as liblcm reads it (strtol, base 0)
}

long long kernel_rmem_max() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  long long bytes = -1;
  if (!(in >> bytes)) return -1;
  return bytes;
}

std::string receive_buffer_warning(const std::string& url) {
  const long long requested = requested_receive_buffer(url);
  const long long rmem_max = kernel_rmem_max();
  if (requested <= 0 || rmem_max < 0 || requested <= rmem_max) return {};
  return "the kernel caps the LCM receive buffer (recv_buf_size=" + std::to_string(requested) +
         ") at net.core.rmem_max = " + std::to_string(rmem_max) +
         " bytes; for bursts at high sample rates raise it as root: sysctl -w net.core.rmem_max=" +
         std::to_string(requested);
}

bool LcmTransport::publish(const char* channel, const std::uint8_t* data, std::size_t size) {
  if (size > static_cast<std::size_t>(UINT_MAX)) return false;
  // The C call: lcm::LCM::publish takes a std::string channel, one heap allocation per message for names longer than
  // the string's inline buffer (ROCKWATCH_WALL_STATE) — found by the soak's allocation count.
  return lcm_publish(lcm_.getUnderlyingLCM(), channel, data, static_cast<unsigned int>(size)) == 0;
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
