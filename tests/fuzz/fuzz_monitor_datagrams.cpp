// The monitor's receive path from raw UDP datagrams: monitor::DatagramInput (source filter, the checked LC02/LC03
// reassembler, channel filter) into firmware::MonitorLoop, exactly as the live monitor runs it minus the socket.
// Several datagrams per input, from several sources, with the receive clock advancing (reassembly expiry):
//
//   input    := settings-byte datagram*
//   datagram := selector-byte length(2 bytes, little-endian) bytes(length; fewer if the input ends)
//   settings-byte: bit 0 accept only 127.0.0.1/32 (--accept-from); bit 1 the batch channel is "A" and the single
//     channel "B" (short names the fuzzer finds easily) instead of the defaults.
//   selector-byte: bits 0-1 the source (127.0.0.1:7001, 127.0.0.1:7002, 10.0.0.1:7001, 10.0.0.2:7003);
//     bits 2-7 receive clock advance, in 50 ms steps (0 … 3.15 s).
// Checked after every datagram: every datagram is accounted for exactly once, at most kSlots messages in flight,
// the loop's counters are consistent. Seeds: tests/fuzz/corpus/monitor_datagrams (make_datagram_seeds.py).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "datagram_input.hpp"
#include "fuzz_support.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

using namespace rockwatch;
namespace fw = rockwatch::firmware;

namespace {

class NullTransport : public fw::Transport {
 public:
  bool publish(const char*, const std::uint8_t*, std::size_t) override { return true; }
};

class CountingSink : public monitor::InputMessageSink {
 public:
  explicit CountingSink(fw::MonitorLoop& loop) : loop_(loop) {}
  void on_input_message(const char* channel, const std::uint8_t* data, std::size_t size,
                        std::int64_t receive_utime) override {
    ROCKWATCH_FUZZ_CHECK(channel != nullptr && std::strlen(channel) <= fw::LcmDatagramReassembler::kMaxChannelLength);
    ROCKWATCH_FUZZ_CHECK(size <= 65536);
    if (size > 0) ROCKWATCH_FUZZ_CHECK(data != nullptr);
    ++messages;
    loop_.on_message(channel, data, size, receive_utime);
  }
  std::int64_t messages = 0;

 private:
  fw::MonitorLoop& loop_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t settings_byte = data[0];
  fw::MonitorSettings settings;
  settings.engine.wall = core::paper_wall();
  settings.engine.r_energy = core::restitution_energy_ratio(settings.engine.wall, core::Restitution{});
  if ((settings_byte & 2) != 0) {
    std::strcpy(settings.channels.accel, "B");
    std::strcpy(settings.channels.accel_batch, "A");
  }
  NullTransport transport;
  const auto loop = std::make_unique<fw::MonitorLoop>();
  const auto engine = std::make_unique<fw::WallEngine>();
  ROCKWATCH_FUZZ_CHECK(loop->init(settings, *engine, transport) == fw::MonitorError::ok);
  CountingSink sink(*loop);
  std::vector<monitor::SourceNetwork> accept;
  if ((settings_byte & 1) != 0) accept.push_back(monitor::SourceNetwork{0x7f000001u, 32});
  const auto input = std::make_unique<monitor::DatagramInput>(settings.channels, accept, sink);

  static const fw::DatagramSource kSources[4] = {
      {0x7f000001u, 7001}, {0x7f000001u, 7002}, {0x0a000001u, 7001}, {0x0a000002u, 7003}};
  std::int64_t now_us = 1700000000000000;
  std::int64_t fed = 0;
  std::size_t at = 1;
  while (at < size) {
    const std::uint8_t selector = data[at++];
    std::size_t length = 0;
    for (int k = 0; k < 2 && at < size; ++k) length |= static_cast<std::size_t>(data[at++]) << (8 * k);
    length = std::min(length, size - at);
    // A copy of exactly `length` bytes on the heap, so ASan sees any read past the datagram.
    const std::unique_ptr<std::uint8_t[]> datagram(new std::uint8_t[length == 0 ? 1 : length]);
    if (length > 0) std::memcpy(datagram.get(), data + at, length);
    at += length;
    now_us += static_cast<std::int64_t>(selector >> 2) * 50000;
    input->on_datagram(datagram.get(), length, kSources[selector & 3], now_us);
    ++fed;

    const fw::DatagramCounters& d = input->datagram_counters();
    const monitor::DatagramInputCounters& c = input->counters();
    ROCKWATCH_FUZZ_CHECK(c.from_other_sources + d.datagrams == fed);
    ROCKWATCH_FUZZ_CHECK(d.datagrams == d.short_messages + d.fragments + d.rejected + d.skipped_too_large);
    ROCKWATCH_FUZZ_CHECK(c.input_messages + c.other_channels == d.short_messages + d.messages_reassembled);
    ROCKWATCH_FUZZ_CHECK(d.messages_reassembled <= d.fragments);
    std::int64_t by_reason = 0;
    for (const std::int64_t n : d.rejected_by_reason) by_reason += n;
    ROCKWATCH_FUZZ_CHECK(by_reason >= d.rejected);  // one or more reasons per rejection
    ROCKWATCH_FUZZ_CHECK(c.input_messages == sink.messages);
    if (accept.empty()) ROCKWATCH_FUZZ_CHECK(c.from_other_sources == 0);
    const fw::MonitorCounters& m = loop->counters();
    ROCKWATCH_FUZZ_CHECK(m.samples_received >= m.duplicates + m.out_of_order);
    ROCKWATCH_FUZZ_CHECK(m.samples_processed == m.samples_received - m.duplicates - m.out_of_order + m.samples_bridged);
    ROCKWATCH_FUZZ_CHECK(m.decode_errors <= sink.messages);
  }
  loop->publish_status(now_us);
  return 0;
}
