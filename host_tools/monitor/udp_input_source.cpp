#include "udp_input_source.hpp"

#include <cerrno>

#include "lcm_transport.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

UdpInputSource::UdpInputSource(const MonitorConfig& config)
    : channels_(config.settings.channels),
      accept_(config.accept_from),
      wall_sensors_(config.settings.engine.observer_enabled) {}

bool UdpInputSource::start(firmware::MultiWallMonitor& walls, std::string* /*problem*/) {
  walls_ = &walls;
  input_ = std::make_unique<DatagramInput>(channels_, accept_, forward_, wall_sensors_);
  input_->set_input_channels(&walls);
  return true;
}

InputPoll UdpInputSource::poll(int timeout_ms, InputMessageSink& sink) {
  forward_.to = &sink;
  const int received = receiver_.receive(*input_, timeout_ms, &realtime_utime);
  const int receive_errno = errno;
  // The walls' statuses count the datagrams refused before any wall saw them.
  walls_->note_datagram_counts(input_->datagram_counters().rejected, input_->counters().from_other_sources);
  errno = receive_errno;
  return received >= 0 ? InputPoll::ok : InputPoll::failed;
}

void UdpInputSource::add_summary(json& summary) const {
  const firmware::DatagramCounters& d = input_->datagram_counters();
  static const char* const kReasons[firmware::kDatagramRejectReasons] = {
      "truncated_header", "bad_magic", "channel_unterminated", "channel_length", "(retired)",
      "fragment_count", "fragment_bounds", "fragment_mismatch", "fragment_duplicate"};
  json reasons = json::object();
  for (int k = 0; k < firmware::kDatagramRejectReasons; ++k) reasons[kReasons[k]] = d.rejected_by_reason[k];
  summary["receive_path"] = "own";
  summary["lcm_messages"] = input_->counters().input_messages;
  summary["datagrams"] = {{"received", receiver_.datagrams()},
                          {"from_other_sources", input_->counters().from_other_sources},
                          {"short_messages", d.short_messages},
                          {"fragments", d.fragments},
                          {"messages_reassembled", d.messages_reassembled},
                          {"skipped_too_large", d.skipped_too_large},
                          {"rejected", d.rejected},
                          {"rejected_by_reason", reasons},
                          {"abandoned", d.abandoned},
                          {"evicted", d.evicted},
                          {"expired", d.expired},
                          {"input_messages", input_->counters().input_messages},
                          {"other_channels", input_->counters().other_channels}};
}

}  // namespace rockwatch::monitor
