// The monitor's receive path from raw UDP datagrams to MonitorLoop::on_message, without the socket (udp_receiver.hpp
// owns that), so that tests and the fuzzer drive exactly what the live monitor runs:
//   datagram → source filter (--accept-from) → firmware::LcmDatagramReassembler (LC02/LC03, checked) →
//   channel filter (the two input channels, and the wall-sensor channel with the observer) → the sink (the traffic log, then the loop).
// Nothing here trusts a length, offset or name in the datagram; every datagram is accounted for:
//   datagrams = from_other_sources + rejected + fragments_stored + messages (input + other channels).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rockwatch/firmware/lcm_datagram.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"

namespace rockwatch::monitor {

// An IPv4 network ADDR/PREFIX (host byte order) from which datagrams are accepted.
struct SourceNetwork {
  std::uint32_t address = 0;
  int prefix_bits = 32;
  bool contains(std::uint32_t ipv4) const;
};

// Parses "A.B.C.D" or "A.B.C.D/N" (N in 0..32). Returns false (and leaves *out alone) on anything else.
bool parse_source_network(const std::string& text, SourceNetwork* out);
std::string source_network_text(const SourceNetwork& n);

// Where complete messages on the input channels go (the traffic log and the loop).
class InputMessageSink {
 public:
  virtual ~InputMessageSink() = default;
  virtual void on_input_message(const char* channel, const std::uint8_t* data, std::size_t size,
                                std::int64_t receive_utime) = 0;
};

struct DatagramInputCounters {
  std::int64_t from_other_sources = 0;  // dropped: the source is not in the accept list
  std::int64_t input_messages = 0;      // complete messages on the input channels, handed to the sink
  std::int64_t other_channels = 0;      // complete messages on other channels (the monitor's own outputs among them)
};

class DatagramInput {
 public:
  // channels: the loop's settings (only accel and accel_batch are read). accept: empty = every source.
  // wall_sensors: the wall-sensor channel is an input too (the monitor runs the observer).
  DatagramInput(const firmware::MonitorChannels& channels, std::vector<SourceNetwork> accept, InputMessageSink& sink,
                bool wall_sensors = false);

  // One datagram as received from `source`; receive_utime: the monitor's clock [µs since 1970-01-01 UTC].
  void on_datagram(const std::uint8_t* data, std::size_t size, firmware::DatagramSource source,
                   std::int64_t receive_utime);

  // Many walls: the input channels are those some wall of `monitor` reads (instead of the channels given above).
  void set_input_channels(const firmware::MultiWallMonitor* monitor) { monitor_ = monitor; }

  const firmware::DatagramCounters& datagram_counters() const { return reassembler_.counters(); }
  const DatagramInputCounters& counters() const { return counters_; }

 private:
  firmware::MonitorChannels channels_;
  std::vector<SourceNetwork> accept_;
  InputMessageSink& sink_;
  bool wall_sensors_ = false;
  const firmware::MultiWallMonitor* monitor_ = nullptr;
  firmware::LcmDatagramReassembler reassembler_{};
  DatagramInputCounters counters_{};
};

}  // namespace rockwatch::monitor
