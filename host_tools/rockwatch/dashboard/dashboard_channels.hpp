// Which walls the dashboard shows, found from the LCM channel names alone: the monitor publishes each wall's state,
// alarm events and status (and, with the wall observer, its sensors' samples and the fused estimate; with --forecast
// the ensemble forecast) on channels
// named BASE (the single wall of a one-wall monitor, shown as wall "wall") or BASE_NAME (wall NAME of a many-wall
// monitor). BASE is the monitor's default channel name (firmware/include/rockwatch/firmware/monitor_loop.hpp:
// ROCKWATCH_WALL_STATE, ...) unless the dashboard is told another one (--state-channel, ...). Nothing has to be
// configured per wall: a wall appears when its first message arrives.
#pragma once

#include <optional>
#include <string>

namespace rockwatch::cli {

enum class ChannelKind { state, alarm, status, sensor, estimate, forecast };

inline constexpr const char* kDefaultWallName = "wall";  // the wall of the unsuffixed channels
// LCM channel names of the monitor are at most 63 bytes (firmware::kChannelNameMax, with the NUL).
inline constexpr std::size_t kMaxChannelLength = 63;
inline constexpr std::size_t kMaxWallNameLength = 40;

struct DashboardChannels {
  std::string state = "ROCKWATCH_WALL_STATE";        // wall_state_t
  std::string alarm = "ROCKWATCH_ALARM";             // alarm_event_t
  std::string status = "ROCKWATCH_STATUS";           // monitor_status_t
  std::string sensor = "ROCKWATCH_WALL_SENSOR";      // wall_sensor_t (measured x), when the wall has sensors
  std::string estimate = "ROCKWATCH_WALL_ESTIMATE";  // wall_estimate_t, when the monitor runs the observer
  std::string forecast = "ROCKWATCH_WALL_FORECAST";  // wall_forecast_t, when the monitor runs --forecast

  const std::string& base(ChannelKind kind) const;
};

struct ChannelMatch {
  ChannelKind kind;
  std::string wall;  // kDefaultWallName for BASE, NAME for BASE_NAME
};

// A base is 1 to 40 characters of [A-Za-z0-9_] (so it needs no escaping in a regular expression and leaves room for a
// suffix); throws UsageError naming `option` otherwise.
void check_channel_base(const std::string& option, const std::string& base);

// A wall name is 1 to kMaxWallNameLength characters of [A-Za-z0-9_-].
bool valid_wall_name(const std::string& name);

// The kind and wall of `channel`, or nothing when it is none of the bases with or without a valid suffix. When two
// bases could both claim a channel (ROCKWATCH_WALL and ROCKWATCH_WALL_STATE), the longer base wins.
std::optional<ChannelMatch> match_channel(const DashboardChannels& channels, const std::string& channel);

// The LCM subscription of one base: "BASE(_[A-Za-z0-9_-]+)?" (liblcm matches the whole channel name).
std::string subscription_regex(const std::string& base);

const char* channel_kind_name(ChannelKind kind);  // "state", "alarm", ...

}  // namespace rockwatch::cli
