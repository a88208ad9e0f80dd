// The live monitor's input: its own checked UDP receive path (udp_receiver.hpp: the socket; datagram_input.hpp:
// source filter, reassembly, channel filter) as an InputSource of the monitor loop. liblcm never reads a datagram
// here (liblcm 1.3.1 crashes on two crafted ones); it only publishes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "datagram_input.hpp"
#include "monitor_config.hpp"
#include "monitor_input_source.hpp"
#include "udp_receiver.hpp"

namespace rockwatch::monitor {

class UdpInputSource final : public LiveInput {
 public:
  // The receive-side settings of `config` (channels, --accept-from, the observer's wall-sensor channel).
  explicit UdpInputSource(const MonitorConfig& config);
  // Binds and joins the group of `endpoint`. False with *problem.
  bool open(const UdpmEndpoint& endpoint, std::string* problem) { return receiver_.open(endpoint, problem); }

  bool start(firmware::MultiWallMonitor& walls, std::string* problem) override;
  bool set_busy_poll(int us, std::string* problem) override { return receiver_.set_busy_poll(us, problem); }
  InputPoll poll(int timeout_ms, InputMessageSink& sink) override;
  // "receive_path": "own", "lcm_messages", and "datagrams": every datagram the socket received and where it went.
  void add_summary(nlohmann::json& summary) const override;

 private:
  // DatagramInput keeps its sink; the loop names the sink at each poll.
  struct ForwardingSink final : InputMessageSink {
    InputMessageSink* to = nullptr;
    void on_input_message(const char* channel, const std::uint8_t* data, std::size_t size,
                          std::int64_t receive_utime) override {
      to->on_input_message(channel, data, size, receive_utime);
    }
  };

  firmware::MonitorChannels channels_;
  std::vector<SourceNetwork> accept_;
  bool wall_sensors_ = false;
  UdpReceiver receiver_;
  ForwardingSink forward_;
  std::unique_ptr<DatagramInput> input_;  // from start()
  firmware::MultiWallMonitor* walls_ = nullptr;
};

}  // namespace rockwatch::monitor
