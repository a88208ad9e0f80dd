#include "dashboard/dashboard_receiver.hpp"

#include <climits>
#include <string>

#include "common/lcm_multicast.hpp"
#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::cli {

namespace {

constexpr int kPollMs = 100;  // how often the thread looks at the stop flag

// Decodes the whole datagram as T: a message that is shorter or longer than T's encoding is not a T.
template <typename T>
bool decode_exactly(const void* data, std::size_t size, T& out) {
  if (size > static_cast<std::size_t>(INT_MAX)) return false;
  const int length = static_cast<int>(size);
  return out.decode(data, 0, length) == length;
}

}  // namespace

LcmReceiver::LcmReceiver(const std::string& url, const DashboardChannels& channels, SnapshotStore& store)
    : channels_(channels), store_(store) {
  std::string problem;
  lcm_ = open_lcm(url, problem);
  if (!lcm_) throw UsageError(problem);
  for (const ChannelKind kind : {ChannelKind::state, ChannelKind::alarm, ChannelKind::status, ChannelKind::sensor,
                                 ChannelKind::estimate}) {
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
      if (lcm_->handleTimeout(kPollMs) < 0) break;  // LCM failed (the socket went away): nothing more to receive
    }
  });
}

void LcmReceiver::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void LcmReceiver::deliver(const DashboardChannels& channels, SnapshotStore& store, const std::string& channel,
                          const void* data, std::size_t size) {
  const std::optional<ChannelMatch> match = match_channel(channels, channel);
  if (!match) return;  // the subscriptions' regular expressions and match_channel agree; this is a safeguard
  bool ok = false;
  switch (match->kind) {
    case ChannelKind::state: {
      rockwatch::wall_state_t m;
      if ((ok = decode_exactly(data, size, m))) store.on_state(match->wall, m);
      break;
    }
    case ChannelKind::alarm: {
      rockwatch::alarm_event_t m;
      if ((ok = decode_exactly(data, size, m))) store.on_alarm(match->wall, m);
      break;
    }
    case ChannelKind::status: {
      rockwatch::monitor_status_t m;
      if ((ok = decode_exactly(data, size, m))) store.on_status(match->wall, m);
      break;
    }
    case ChannelKind::sensor: {
      rockwatch::wall_sensor_t m;
      if ((ok = decode_exactly(data, size, m))) store.on_sensor(match->wall, m);
      break;
    }
    case ChannelKind::estimate: {
      rockwatch::wall_estimate_t m;
      if ((ok = decode_exactly(data, size, m))) store.on_estimate(match->wall, m);
      break;
    }
  }
  if (!ok) store.count_decode_error();
}

}  // namespace rockwatch::cli
