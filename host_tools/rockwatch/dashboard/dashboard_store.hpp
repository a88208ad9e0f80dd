// The dashboard's picture of every wall, between the LCM receive thread (which writes it, one decoded message at a
// time) and the HTTP/WebSocket server (which reads it). Bounded whatever the monitor sends: per wall, x(t) over the
// last history_s seconds at decimated resolution (at most updates_per_s points per second of sample time: in each
// bin of 1/updates_per_s s the sample with the largest |x| is kept, so the peaks stay), the last max_transitions
// alarm transitions, the last status and estimate; at most max_walls walls (more are counted and ignored).
//
// Levels follow the monitor's messages, with one rule of the dashboard's own: once a wall is COLLAPSED it stays
// COLLAPSED (as the monitor's alarm latches it) until that wall's monitor restarts — a message whose sequence number
// goes back (a fresh monitor counts from 0), which clears the wall's history. So a page opened after the collapse
// shows the collapse, even when a late or reordered message says otherwise.
//
// take_updates() is the WebSocket stream's decimation: a wall that changed gets at most one update per
// 1/updates_per_s seconds of the caller's clock (the time is an argument, so tests need no sleeping).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dashboard/dashboard_channels.hpp"

#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/monitor_status_t.hpp"
#include "rockwatch/wall_estimate_t.hpp"
#include "rockwatch/wall_forecast_t.hpp"
#include "rockwatch/wall_sensor_t.hpp"
#include "rockwatch/wall_state_t.hpp"

namespace rockwatch::cli {

// The lines drawn with x(t) and E/E_barrier, from the wall the dashboard was told the monitor runs (per side: index
// 0 = x < 0, 1 = x > 0; magnitudes).
struct WallLimits {
  double x_inst_m[2] = {0.0, 0.0};      // static instability displacement (SPEC §1)
  double x_collapse_m[2] = {0.0, 0.0};  // κ·x_inst
  double x_warning_m[2] = {0.0, 0.0};   // λ_w·x_inst (the WARNING threshold)
  double energy_margin = 1.5;           // IMMINENT by energy at E ≥ margin·E_barrier
};

struct StoreSettings {
  double history_s = 30.0;
  int updates_per_s = 30;
  std::size_t max_transitions = 50;
  std::size_t max_walls = 64;
  WallLimits limits;
};

class SnapshotStore {
 public:
  explicit SnapshotStore(const StoreSettings& settings);

  // One decoded message of wall `wall` (a name from match_channel). Thread-safe.
  void on_state(const std::string& wall, const rockwatch::wall_state_t& m);
  void on_alarm(const std::string& wall, const rockwatch::alarm_event_t& m);
  void on_status(const std::string& wall, const rockwatch::monitor_status_t& m);
  void on_sensor(const std::string& wall, const rockwatch::wall_sensor_t& m);
  void on_estimate(const std::string& wall, const rockwatch::wall_estimate_t& m);
  // P(collapse) over time: one point per forecast (0 at rest; none without input), at the state's time.
  void on_forecast(const std::string& wall, const rockwatch::wall_forecast_t& m);
  // A message on a subscribed channel that did not decode as its type.
  void count_decode_error();

  // GET /api/state: {"walls": [...], "receiver": {...}, "history_s", "updates_per_s", "max_transitions"}. Each wall
  // as wall_json with its whole history.
  nlohmann::json state_json() const;

  // The WebSocket updates due at `now_ns` (any monotonic clock): one message {"type": "update", "server_time_s":
  // now_ns in s, "wall": {...}} per
  // wall that changed since its last update and whose last update is at least 1/updates_per_s s old. An update holds
  // the wall's current values, the points added or changed since the previous update, and the transitions and status
  // only when they changed.
  std::vector<std::string> take_updates(std::int64_t now_ns);

  std::size_t wall_count() const;
  std::int64_t walls_refused() const;

 private:
  struct Point {
    std::uint64_t id;
    double t_s;
    double x_m;
    double energy_ratio;  // NaN for a measured point
  };
  struct Series {
    std::deque<Point> points;
    std::uint64_t next_id = 0;
    std::uint64_t dirty_from = 0;  // the first id added or changed since the last update
  };
  struct Wall {
    std::string name;
    std::optional<rockwatch::wall_state_t> state;
    int level = 0;
    std::uint32_t reasons = 0;
    bool collapsed_latched = false;
    Series predicted, measured, forecast_p;  // forecast_p: [id, t_s, P(collapse)]
    std::deque<rockwatch::alarm_event_t> transitions;
    std::int64_t transitions_total = 0;
    std::optional<rockwatch::monitor_status_t> status;
    std::optional<rockwatch::wall_estimate_t> estimate;
    std::optional<rockwatch::wall_forecast_t> forecast;
    std::int64_t states = 0, alarms = 0, statuses = 0, sensor_samples = 0, estimates = 0, monitor_restarts = 0;
    std::int64_t forecasts = 0, last_forecast_seq = -1;
    std::int64_t last_state_seq = -1, last_alarm_seq = -1, last_status_seq = -1;
    // The WebSocket stream's bookkeeping.
    std::uint64_t version = 0, pushed_version = 0;
    bool pushed_once = false;
    std::int64_t last_push_ns = 0;
    std::int64_t pushed_transitions_total = -1, pushed_status_seq = -1;
    bool send_everything = true;  // the next update carries the transitions and status even when unchanged
  };

  Wall* wall_for(const std::string& name);  // nullptr when max_walls are known already
  void restart(Wall& w);
  void add_point(Series& s, double t_s, double x_m, double energy_ratio);
  nlohmann::json wall_json(const Wall& w, bool whole) const;

  StoreSettings settings_;
  mutable std::mutex mutex_;
  std::map<std::string, Wall> walls_;
  std::int64_t walls_refused_ = 0;
  std::int64_t decode_errors_ = 0;
  std::int64_t messages_ = 0;
};

// One raw LCM message: its channel's kind and wall (match_channel), decoded as that kind's type (the whole datagram,
// or it is counted as a decode error) and handed to `store`. Channels that match nothing are ignored.
void deliver_message(const DashboardChannels& channels, SnapshotStore& store, const std::string& channel,
                     const void* data, std::size_t size);

// "QUIET" ... "COLLAPSED", or "LEVEL_<n>" for a code this dashboard does not know.
std::string level_text(int level);
// The monitor_status_t QUALITY_* bits by name ("gap_bridged", ...; "bitN" for an unknown bit), in bit order.
std::vector<std::string> quality_flag_list(std::uint32_t bits);

}  // namespace rockwatch::cli
