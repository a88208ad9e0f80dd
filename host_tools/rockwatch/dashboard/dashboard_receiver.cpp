#include "dashboard/dashboard_receiver.hpp"

#include <string>

#include "common/replay_out/lcm_multicast.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

constexpr int kPollMs = 100;  // how often the thread looks at the stop flag

}  // namespace

LcmReceiver::LcmReceiver(const std::string& url, const DashboardChannels& channels, SnapshotStore& store)
    : channels_(channels), store_(store) {
  std::string problem;
  lcm_ = open_lcm(url, problem);
  if (!lcm_) throw UsageError(problem);
  for (const ChannelKind kind : {ChannelKind::state, ChannelKind::alarm, ChannelKind::status, ChannelKind::sensor,
                                 ChannelKind::estimate, ChannelKind::forecast}) {
    lcm_->subscribeFunction(
        subscription_regex(channels_.base(kind)),
        +[](const lcm::ReceiveBuffer* rbuf, const std::string& channel, LcmReceiver* self) {
          deliver(self->channels_, self->store_, channel, rbuf->data, rbuf->data_size);
        },
        this);
  }
}

LcmReceiver::~LcmReceiver() { stop(); }

void LcmReceiver::start() {
  thread_ = std::thread([this] {
    while (!stop_.load()) {
      if (lcm_->handleTimeout(kPollMs) < 0) {  // LCM failed (the socket went away): nothing more to receive
        failed_ = true;
        break;
      }
    }
  });
}

void LcmReceiver::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void LcmReceiver::deliver(const DashboardChannels& channels, SnapshotStore& store, const std::string& channel,
                          const void* data, std::size_t size) {
  deliver_message(channels, store, channel, data, size);
}

}  // namespace rockwatch::cli
