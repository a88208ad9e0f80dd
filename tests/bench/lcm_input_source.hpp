// liblcm's receive path as an input of the monitor loop (host_tools/monitor/monitor_input_source.hpp), for the
// benchmark only: rockwatch-monitor-liblcm (monitor_liblcm_main.cpp) is the monitor with this input behind
// --receive-path liblcm, so bench_monitor_latency measures liblcm's receive thread against the monitor's own path
// in one session (docs/BENCHMARKS.md, "The monitor's own receive path against liblcm's"). It stays out of the
// monitor's program: liblcm 1.3.1's fragment reassembly crashes on two crafted datagrams (docs/RELIABILITY.md).
#pragma once

#include <cstdint>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "monitor_input_source.hpp"

namespace rockwatch::bench {

// Subscribes the monitor's two input channels (and the wall-sensor channel with the observer; only those, exactly)
// and hands every message's raw bytes to the loop's sink with the receive time LCM stamped on it (CLOCK_REALTIME µs;
// now when LCM gave none). Each subscription holds up to input_queue_capacity(the sample rate) unhandled messages
// (not LCM's 30). Any other subscription of the same LCM instance to an input channel needs the same capacity:
// liblcm keeps a message when one matching subscription has room, then hands it to each subscription that has
// messages counted. Messages arrive while poll() runs lcm.handleTimeout(). One wall only (the settings refuse
// `walls` with --receive-path liblcm). Unsubscribes on destruction.
class LcmInputSource final : public monitor::LiveInput {
 public:
  explicit LcmInputSource(lcm::LCM& lcm) : lcm_(lcm) {}
  ~LcmInputSource() override;
  LcmInputSource(const LcmInputSource&) = delete;
  LcmInputSource& operator=(const LcmInputSource&) = delete;

  bool start(firmware::MultiWallMonitor& walls, std::string* problem) override;
  bool set_busy_poll(int us, std::string* problem) override;
  monitor::InputPoll poll(int timeout_ms, monitor::InputMessageSink& sink) override;
  // "receive_path": "liblcm", "lcm_messages": the messages liblcm handed over.
  void add_summary(nlohmann::json& summary) const override;

 private:
  static void on_raw(const lcm_recv_buf_t* rbuf, const char* channel, void* self);

  lcm::LCM& lcm_;
  monitor::InputMessageSink* sink_ = nullptr;  // the loop's, named at each poll
  // The C API: lcm-cpp's callbacks take the channel as a std::string, a heap allocation per message for names over
  // 15 characters (ROCKWATCH_ACCEL_BATCH) — the soak's allocation count found its twin on the publishing side.
  lcm_subscription_t* accel_ = nullptr;
  lcm_subscription_t* batch_ = nullptr;
  lcm_subscription_t* sensor_ = nullptr;  // the wall-sensor channel, with the observer only
  std::int64_t messages_ = 0;
};

}  // namespace rockwatch::bench
