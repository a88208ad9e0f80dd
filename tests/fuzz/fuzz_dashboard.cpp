// `rockwatch dashboard`'s inputs from outside: LCM messages on the channels it subscribes to (any bytes, any wall
// name) into the snapshot store, and HTTP request lines (method, target, Host) into route_request. The input is a
// sequence of records: [kind byte] [length byte] [bytes]. Kind < 200: a message on channel kChannels[kind % n] (the
// bytes, or a valid message of the channel's type with fuzzed fields when the length is odd); 200..249: take the
// WebSocket updates at a clock advanced by the kind (ms); 250..255: a request, the bytes split at NUL into method,
// target and Host. After every record the store's JSON must serialise; a reply must have a documented status.
// Nothing may crash, hang or grow without bound. Seeds: none needed (libFuzzer finds the structure quickly).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "dashboard/dashboard_assets.hpp"
#include "dashboard/dashboard_channels.hpp"
#include "dashboard/dashboard_http.hpp"
#include "dashboard/dashboard_store.hpp"

namespace {

const char* const kChannels[] = {"ROCKWATCH_WALL_STATE",   "ROCKWATCH_ALARM",          "ROCKWATCH_STATUS",
                                 "ROCKWATCH_WALL_SENSOR",  "ROCKWATCH_WALL_ESTIMATE",  "ROCKWATCH_WALL_STATE_east",
                                 "ROCKWATCH_ALARM_east",   "ROCKWATCH_STATUS_east",    "ROCKWATCH_WALL_SENSOR_w-2",
                                 "ROCKWATCH_ACCEL",        "ROCKWATCH_WALL_STATE_a.b", "ROCKWATCH_WALL_STATE_"};
constexpr std::size_t kChannelCount = sizeof kChannels / sizeof kChannels[0];

const unsigned char kPage[] = "page";
const rockwatch::cli::EmbeddedAsset kAssets[] = {
    {"/index.html", "text/html", kPage, 4, true, "index.html"},
    {"/uPlot.iife.min.js", "text/javascript", kPage, 0, false, "node_modules/uplot/dist/uPlot.iife.min.js"},
    {nullptr, nullptr, nullptr, 0, false, nullptr},
};

// A message of the channel's type whose fields are the fuzzer's bytes (so decoding succeeds and the store sees
// arbitrary values: NaN, huge times, sequence numbers going back), encoded as the monitor would.
template <typename T>
std::vector<std::uint8_t> encode_with_fields(const std::uint8_t* bytes, std::size_t n) {
  T m{};
  std::memcpy(&m, bytes, n < sizeof m ? n : sizeof m);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(m.getEncodedSize()));
  if (m.encode(out.data(), 0, static_cast<int>(out.size())) < 0) out.clear();
  return out;
}

std::vector<std::uint8_t> structured(std::size_t channel, const std::uint8_t* bytes, std::size_t n) {
  const std::string name = kChannels[channel];
  if (name.rfind("ROCKWATCH_WALL_STATE", 0) == 0) return encode_with_fields<rockwatch::wall_state_t>(bytes, n);
  if (name.rfind("ROCKWATCH_ALARM", 0) == 0) return encode_with_fields<rockwatch::alarm_event_t>(bytes, n);
  if (name.rfind("ROCKWATCH_STATUS", 0) == 0) return encode_with_fields<rockwatch::monitor_status_t>(bytes, n);
  if (name.rfind("ROCKWATCH_WALL_SENSOR", 0) == 0) return encode_with_fields<rockwatch::wall_sensor_t>(bytes, n);
  return encode_with_fields<rockwatch::wall_estimate_t>(bytes, n);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rockwatch::cli::StoreSettings settings;
  settings.max_walls = 4;
  rockwatch::cli::SnapshotStore store(settings);
  const rockwatch::cli::DashboardChannels channels;
  rockwatch::cli::RouteContext context;
  context.assets = kAssets;
  context.state_json = [&store] { return store.state_json().dump(); };
  std::int64_t now_ns = 0;
  std::size_t at = 0;
  while (at + 2 <= size) {
    const std::uint8_t kind = data[at], length = data[at + 1];
    at += 2;
    const std::size_t n = length < size - at ? length : size - at;
    const std::uint8_t* bytes = data + at;
    at += n;
    if (kind < 200) {
      const std::size_t channel = kind % kChannelCount;
      if (length % 2 == 1) {
        const std::vector<std::uint8_t> message = structured(channel, bytes, n);
        rockwatch::cli::deliver_message(channels, store, kChannels[channel], message.data(), message.size());
      } else {
        rockwatch::cli::deliver_message(channels, store, kChannels[channel], bytes, n);
      }
    } else if (kind < 250) {
      now_ns += static_cast<std::int64_t>(kind - 200) * 1000000;
      for (const std::string& update : store.take_updates(now_ns)) {
        if (update.empty()) std::abort();
      }
    } else {
      std::string fields[3];
      std::size_t f = 0;
      for (std::size_t i = 0; i < n && f < 3; ++i) {
        if (bytes[i] == 0) {
          ++f;
        } else {
          fields[f] += static_cast<char>(bytes[i]);
        }
      }
      const rockwatch::cli::HttpReply r =
          rockwatch::cli::route_request(fields[0], fields[1], fields[2], (kind & 1) != 0, context);
      const int s = r.status;
      if (s != 101 && s != 200 && s != 400 && s != 404 && s != 405 && s != 421 && s != 426) std::abort();
      if (r.upgrade != (s == 101)) std::abort();
    }
  }
  if (store.wall_count() > settings.max_walls) std::abort();
  (void)store.state_json().dump();
  return 0;
}
