// The dashboard's LCM side: one thread receiving the monitor's output channels (every wall's, by regular-expression
// subscriptions: dashboard_channels.hpp), decoding each message as its channel's type and handing it to the
// SnapshotStore. A message that does not decode (another type on the channel, a truncated datagram) is counted and
// dropped. The monitor is another process: the dashboard only listens, so it cannot slow the monitor down.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include <lcm/lcm-cpp.hpp>

#include "dashboard/dashboard_channels.hpp"
#include "dashboard/dashboard_store.hpp"

namespace rockwatch::cli {

class LcmReceiver {
 public:
  // Opens LCM on `url` and subscribes. Throws UsageError when LCM cannot start there.
  LcmReceiver(const std::string& url, const DashboardChannels& channels, SnapshotStore& store);
  ~LcmReceiver();  // stops
  LcmReceiver(const LcmReceiver&) = delete;
  LcmReceiver& operator=(const LcmReceiver&) = delete;

  void start();
  void stop();  // within about 100 ms; idempotent
  // True once LCM failed while receiving (the thread has ended): the page would only show stale values.
  bool failed() const { return failed_.load(); }

  // Hands one raw message to the store, as the receive thread does (the unit tests call it directly).
  static void deliver(const DashboardChannels& channels, SnapshotStore& store, const std::string& channel,
                      const void* data, std::size_t size);

 private:
  DashboardChannels channels_;
  SnapshotStore& store_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> failed_{false};
};

}  // namespace rockwatch::cli
