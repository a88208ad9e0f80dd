#include "datagram_input.hpp"

#include <cstring>
#include <utility>

namespace rockwatch::monitor {

bool SourceNetwork::contains(std::uint32_t ipv4) const {
  if (prefix_bits <= 0) return true;
  const std::uint32_t mask = prefix_bits >= 32 ? 0xffffffffu : ~(0xffffffffu >> prefix_bits);
  return (ipv4 & mask) == (address & mask);
}

bool parse_source_network(const std::string& text, SourceNetwork* out) {
  std::uint32_t octets[4] = {};
  std::size_t at = 0;
  for (int k = 0; k < 4; ++k) {
    if (at >= text.size() || text[at] < '0' || text[at] > '9') return false;
    std::uint32_t v = 0;
    std::size_t digits = 0;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') {
      v = v * 10u + static_cast<std::uint32_t>(text[at] - '0');
      ++at;
      if (++digits > 3 || v > 255) return false;
    }
    octets[k] = v;
    if (k < 3) {
      if (at >= text.size() || text[at] != '.') return false;
      ++at;
    }
  }
  int prefix = 32;
  if (at < text.size()) {
    if (text[at] != '/') return false;
    ++at;
    if (at >= text.size()) return false;
    prefix = 0;
    std::size_t digits = 0;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') {
      prefix = prefix * 10 + (text[at] - '0');
      ++at;
      if (++digits > 2) return false;
    }
    if (at != text.size() || digits == 0 || prefix > 32) return false;
  }
  out->address = (octets[0] << 24) | (octets[1] << 16) | (octets[2] << 8) | octets[3];
  out->prefix_bits = prefix;
  return true;
}

std::string source_network_text(const SourceNetwork& n) {
  std::string s;
  for (int k = 3; k >= 0; --k) {
    s += std::to_string((n.address >> (8 * k)) & 0xffu);
    if (k > 0) s += '.';
  }
  return s + "/" + std::to_string(n.prefix_bits);
}

DatagramInput::DatagramInput(const firmware::MonitorChannels& channels, std::vector<SourceNetwork> accept,
                             InputMessageSink& sink, bool wall_sensors)
    : channels_(channels), accept_(std::move(accept)), sink_(sink), wall_sensors_(wall_sensors) {}

void DatagramInput::on_datagram(const std::uint8_t* data, std::size_t size, firmware::DatagramSource source,
                                std::int64_t receive_utime) {
  if (!accept_.empty()) {
    bool accepted = false;
    for (const SourceNetwork& n : accept_) accepted = accepted || n.contains(source.ipv4);
    if (!accepted) {
      ++counters_.from_other_sources;
      return;
    }
  }
  firmware::LcmMessageView message;
  if (reassembler_.accept(data, size, source, receive_utime, &message, nullptr) != firmware::DatagramOutcome::message) {
    return;
  }
  const bool input = monitor_ != nullptr
                         ? monitor_->reads(message.channel)
                         : std::strcmp(message.channel, channels_.accel) == 0 ||
                               std::strcmp(message.channel, channels_.accel_batch) == 0 ||
                               (wall_sensors_ && std::strcmp(message.channel, channels_.wall_sensor) == 0);
  if (input) {
    ++counters_.input_messages;
    sink_.on_input_message(message.channel, message.payload, message.size, receive_utime);
  } else {
    ++counters_.other_channels;
  }
}

}  // namespace rockwatch::monitor
