#include "dashboard/dashboard_store.hpp"

#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/observer_options.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

using nlohmann::json;

constexpr int kCollapsed = static_cast<int>(core::AlarmLevel::collapsed);
constexpr std::uint64_t kNothingDirty = std::numeric_limits<std::uint64_t>::max();

double seconds_of(std::int64_t utime) { return static_cast<double>(utime) * 1e-6; }

// JSON has no NaN or infinity: a value that is not finite is written as null.
json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

// t_to_instability_s: −1 (none) and anything not a time are null.
json time_or_null(double t_s) { return std::isfinite(t_s) && t_s >= 0.0 ? json(t_s) : json(nullptr); }

json transition_json(const rockwatch::alarm_event_t& e) {
  return json{{"utime", e.utime},
              {"t_s", seconds_of(e.utime)},
              {"seq", e.seq},
              {"input_seq", e.input_seq},
              {"level", level_text(e.level)},
              {"previous_level", level_text(e.previous_level)},
              {"reasons", alarm_reason_list(static_cast<std::uint32_t>(e.reasons))},
              {"x_m", number_or_null(e.x_m)},
              {"xd_mps", number_or_null(e.xd_mps)},
              {"energy_ratio", number_or_null(e.energy_ratio)},
              {"t_to_instability_s", time_or_null(e.t_to_instability_s)}};
}

json status_json(const rockwatch::monitor_status_t& s) {
  const char* arithmetic = s.arithmetic == rockwatch::monitor_status_t::ARITH_FIXED    ? "fixed"
                           : s.arithmetic == rockwatch::monitor_status_t::ARITH_DOUBLE ? "double"
                                                                                       : "unknown";
  return json{{"utime", s.utime},
              {"seq", s.seq},
              {"version", std::to_string(s.version_major) + "." + std::to_string(s.version_minor) + "." +
                              std::to_string(s.version_patch)},
              {"arithmetic", arithmetic},
              {"alarm_level", level_text(s.alarm_level)},
              {"data_quality", quality_flag_list(static_cast<std::uint32_t>(s.data_quality))},
              {"counters",
               {{"samples_received", s.samples_received},
                {"samples_processed", s.samples_processed},
                {"samples_bridged", s.samples_bridged},
                {"gaps", s.gaps},
                {"state_resets", s.state_resets},
                {"duplicates", s.duplicates},
                {"out_of_order", s.out_of_order},
                {"late", s.late},
                {"rejected_not_finite", s.rejected_not_finite},
                {"rejected_out_of_range", s.rejected_out_of_range},
                {"lift_off", s.lift_off},
                {"publisher_restarts", s.publisher_restarts},
                {"decode_errors", s.decode_errors},
                {"saturated", s.saturated},
                {"sensor_flags", s.sensor_flags},
                {"messages_ignored", s.messages_ignored},
                {"publish_failures", s.publish_failures},
                {"log_write_failures", s.log_write_failures},
                {"time_untrusted", s.time_untrusted},
                {"datagrams_rejected", s.datagrams_rejected},
                {"datagrams_from_other_sources", s.datagrams_from_other_sources}}},
              {"worst_step_ns", s.worst_step_ns}};
}

// One sensor's fusion status as wall_estimate_t carries it; last_fused_utime null until a reading was accepted.
json sensor_status_json(double innovation, double variance, double test_ratio, bool rejected,
                        std::int64_t last_fused_utime) {
  return json{{"innovation", number_or_null(innovation)},
              {"innovation_variance", number_or_null(variance)},
              {"test_ratio", number_or_null(test_ratio)},
              {"rejected", rejected},
              {"last_fused_utime", last_fused_utime != 0 ? json(last_fused_utime) : json(nullptr)}};
}

json estimate_json(const rockwatch::wall_estimate_t& e) {
  return json{{"utime", e.utime},
              {"x_m", number_or_null(e.x_m)},
              {"sigma_x_m", number_or_null(e.sigma_x_m)},
              {"r_estimate", number_or_null(e.r_estimate)},
              {"sigma_r", number_or_null(e.sigma_r)},
              {"bias_m", number_or_null(e.bias_m)},
              {"x_inst_estimate_m", number_or_null(e.x_inst_estimate_m)},
              {"sigma_x_inst_m", number_or_null(e.sigma_x_inst_m)},
              {"x_inst_alarm_m", number_or_null(e.x_inst_alarm_m)},
              {"sensor_health", observer_flag_list(static_cast<std::uint32_t>(e.sensor_health))},
              {"sensor_samples", e.sensor_samples},
              {"x_updates", e.x_updates},
              {"rejected", e.rejected},
              {"dropouts", e.dropouts},
              // Each sensor's fusion status (wall_estimate_t schema 3): the page's table per sensor.
              {"sensors",
               {{"x", sensor_status_json(e.innovation_x_m, e.x_innovation_var_m2, e.x_test_ratio, e.x_rejected,
                                         e.x_last_fused_utime)},
                {"a", sensor_status_json(e.innovation_a_mps2, e.a_innovation_var_m2ps4, e.a_test_ratio, e.a_rejected,
                                         e.a_last_fused_utime)}}}};
}

json forecast_json(const rockwatch::wall_forecast_t& f) {
  using F = rockwatch::wall_forecast_t;
  const char* status = f.status == F::STATUS_OK        ? "ok"
                       : f.status == F::STATUS_AT_REST ? "at_rest"
                       : f.status == F::STATUS_NO_INPUT ? "no_input"
                       : f.status == F::STATUS_COLLAPSED ? "collapsed"
                                                        : "unknown";
  return json{{"utime", f.utime},
              {"status", status},
              {"fused", f.fused != 0},
              {"horizon_s", number_or_null(f.horizon_s)},
              {"members", f.members},
              {"p_collapse", number_or_null(f.p_collapse)},
              {"p_collapse_se", number_or_null(f.p_collapse_se)},
              {"p_collapse_calibrated", number_or_null(f.p_collapse_calibrated)},
              {"q50_max_x_over_x_inst", number_or_null(f.q50_max_x_over_x_inst)},
              {"q90_max_x_over_x_inst", number_or_null(f.q90_max_x_over_x_inst)},
              {"compute_us", f.compute_us},
              {"rate_hz", number_or_null(f.rate_hz)},
              {"ticks_skipped", f.ticks_skipped}};
}

json limits_json(const WallLimits& l) {
  return json{{"x_inst_m", {l.x_inst_m[0], l.x_inst_m[1]}},
              {"x_collapse_m", {l.x_collapse_m[0], l.x_collapse_m[1]}},
              {"x_warning_m", {l.x_warning_m[0], l.x_warning_m[1]}},
              {"energy_barrier", 1.0},
              {"energy_margin", l.energy_margin}};
}

// Decodes the whole datagram as T: a message that is shorter or longer than T's encoding is not a T.
template <typename T>
bool decode_exactly(const void* data, std::size_t size, T& out) {
  if (size > static_cast<std::size_t>(INT_MAX)) return false;
  const int length = static_cast<int>(size);
  return out.decode(data, 0, length) == length;
}

}  // namespace

void deliver_message(const DashboardChannels& channels, SnapshotStore& store, const std::string& channel,
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
    case ChannelKind::forecast: {
      rockwatch::wall_forecast_t m;
      if ((ok = decode_exactly(data, size, m))) store.on_forecast(match->wall, m);
      break;
    }
  }
  if (!ok) store.count_decode_error();
}

std::string level_text(int level) {
  if (level >= 0 && level <= kCollapsed) return core::alarm_level_name(static_cast<core::AlarmLevel>(level));
  return "LEVEL_" + std::to_string(level);
}

std::vector<std::string> quality_flag_list(std::uint32_t bits) {
  using S = rockwatch::monitor_status_t;
  const struct {
    std::int32_t bit;
    const char* name;
  } kNames[] = {{S::QUALITY_GAP_BRIDGED, "gap_bridged"},
                {S::QUALITY_STATE_UNKNOWN, "state_unknown"},
                {S::QUALITY_NOT_FINITE, "not_finite"},
                {S::QUALITY_OUT_OF_RANGE, "out_of_range"},
                {S::QUALITY_LIFT_OFF, "lift_off"},
                {S::QUALITY_DUPLICATE, "duplicate"},
                {S::QUALITY_OUT_OF_ORDER, "out_of_order"},
                {S::QUALITY_LATE, "late"},
                {S::QUALITY_PUBLISHER_RESTART, "publisher_restart"},
                {S::QUALITY_DECODE_ERROR, "decode_error"},
                {S::QUALITY_SATURATED, "saturated"},
                {S::QUALITY_SENSOR_FLAG, "sensor_flag"},
                {S::QUALITY_MONITOR_RESTARTED, "monitor_restarted"},
                {S::QUALITY_LOG_WRITE_FAILED, "log_write_failed"},
                {S::QUALITY_BAD_DATAGRAM, "bad_datagram"},
                {S::QUALITY_TIME_UNTRUSTED, "time_untrusted"},
                {S::QUALITY_SENSOR_FAULT, "sensor_fault"},
                {S::QUALITY_WORK_SHED, "work_shed"},
                {S::QUALITY_OVER_BUDGET, "over_budget"}};
  std::vector<std::string> names;
  for (int b = 0; b < 32; ++b) {
    const std::uint32_t bit = 1u << b;
    if ((bits & bit) == 0) continue;
    const char* name = nullptr;
    for (const auto& n : kNames) {
      if (static_cast<std::uint32_t>(n.bit) == bit) name = n.name;
    }
    names.push_back(name != nullptr ? std::string(name) : "bit" + std::to_string(b));
  }
  return names;
}

SnapshotStore::SnapshotStore(const StoreSettings& settings) : settings_(settings) {}

SnapshotStore::Wall* SnapshotStore::wall_for(const std::string& name) {
  const auto found = walls_.find(name);
  if (found != walls_.end()) return &found->second;
  if (walls_.size() >= settings_.max_walls) {
    ++walls_refused_;
    return nullptr;
  }
  Wall& w = walls_[name];
  w.name = name;
  return &w;
}

// A fresh monitor for this wall: what the old one said no longer describes the wall.
void SnapshotStore::restart(Wall& w) {
  Wall fresh;
  fresh.name = w.name;
  fresh.monitor_restarts = w.monitor_restarts + 1;
  fresh.predicted.next_id = w.predicted.next_id;  // ids keep growing, so a page never confuses old and new points
  fresh.measured.next_id = w.measured.next_id;
  fresh.forecast_p.next_id = w.forecast_p.next_id;
  fresh.version = w.version + 1;
  fresh.pushed_version = w.pushed_version;
  fresh.pushed_once = w.pushed_once;
  fresh.last_push_ns = w.last_push_ns;
  w = std::move(fresh);
}

void SnapshotStore::add_point(Series& s, double t_s, double x_m, double energy_ratio) {
  if (!std::isfinite(t_s)) return;
  const double per_s = settings_.updates_per_s;  // bins: floor(t · updates_per_s)
  if (!s.points.empty()) {
    const Point& last = s.points.back();
    if (t_s < last.t_s - 1.0) {
      s.points.clear();  // a new time base (another publisher): the old curve would join the new one
    } else if (t_s < last.t_s) {
      return;  // reordered: the curve is drawn in time order
    } else if (std::floor(t_s * per_s) == std::floor(last.t_s * per_s)) {
      // Same bin: keep the larger |x| (NaN never replaces a number).
      if (std::fabs(x_m) > std::fabs(last.x_m) || (!std::isfinite(last.x_m) && std::isfinite(x_m))) {
        s.points.back() = Point{last.id, t_s, x_m, energy_ratio};
        if (last.id < s.dirty_from) s.dirty_from = last.id;
      }
      return;
    }
  }
  const std::uint64_t id = s.next_id++;
  s.points.push_back(Point{id, t_s, x_m, energy_ratio});
  if (id < s.dirty_from) s.dirty_from = id;
  // The window (t - history_s, t]: at most history_s * updates_per_s bins.
  const std::size_t max_points = static_cast<std::size_t>(std::ceil(settings_.history_s * settings_.updates_per_s));
  while (!s.points.empty() && (s.points.front().t_s <= t_s - settings_.history_s || s.points.size() > max_points)) {
    s.points.pop_front();
  }
}

void SnapshotStore::on_state(const std::string& name, const rockwatch::wall_state_t& m) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  Wall* w = wall_for(name);
  if (w == nullptr) return;
  if (m.seq <= w->last_state_seq) {
    if (m.seq == w->last_state_seq) return;  // a duplicate
    restart(*w);
  }
  w->last_state_seq = m.seq;
  ++w->states;
  ++w->version;
  w->state = m;
  if (!w->collapsed_latched) {
    w->level = m.alarm_level;
    w->reasons = static_cast<std::uint32_t>(m.alarm_reasons);
  }
  if (m.alarm_level == kCollapsed) w->collapsed_latched = true;
  add_point(w->predicted, seconds_of(m.utime), m.x_m, m.energy_ratio);
}

void SnapshotStore::on_alarm(const std::string& name, const rockwatch::alarm_event_t& m) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  Wall* w = wall_for(name);
  if (w == nullptr) return;
  if (m.seq <= w->last_alarm_seq) {
    if (m.seq == w->last_alarm_seq) return;
    restart(*w);
  }
  w->last_alarm_seq = m.seq;
  ++w->alarms;
  ++w->version;
  w->transitions.push_back(m);
  ++w->transitions_total;
  while (w->transitions.size() > settings_.max_transitions) w->transitions.pop_front();
  // The event may come before the state of its sample (another channel): the level follows whichever is newer.
  if (!w->collapsed_latched && (!w->state || m.utime >= w->state->utime)) {
    w->level = m.level;
    w->reasons = static_cast<std::uint32_t>(m.reasons);
  }
  if (m.level == kCollapsed) {
    w->collapsed_latched = true;
    w->level = kCollapsed;
    w->reasons = static_cast<std::uint32_t>(m.reasons);
  }
}

void SnapshotStore::on_status(const std::string& name, const rockwatch::monitor_status_t& m) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  Wall* w = wall_for(name);
  if (w == nullptr) return;
  if (m.seq <= w->last_status_seq) {
    if (m.seq == w->last_status_seq) return;
    restart(*w);
  }
  w->last_status_seq = m.seq;
  ++w->statuses;
  ++w->version;
  w->status = m;
}

void SnapshotStore::on_sensor(const std::string& name, const rockwatch::wall_sensor_t& m) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  Wall* w = wall_for(name);
  if (w == nullptr) return;
  ++w->sensor_samples;
  if ((m.valid & rockwatch::wall_sensor_t::VALID_X) == 0) return;
  ++w->version;
  add_point(w->measured, seconds_of(m.utime), m.x_mid_m, std::numeric_limits<double>::quiet_NaN());
}

void SnapshotStore::on_estimate(const std::string& name, const rockwatch::wall_estimate_t& m) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  Wall* w = wall_for(name);
  if (w == nullptr) return;
  ++w->estimates;
  ++w->version;
  w->estimate = m;
}

void SnapshotStore::on_forecast(const std::string& name, const rockwatch::wall_forecast_t& m) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  Wall* w = wall_for(name);
  if (w == nullptr) return;
  if (m.seq <= w->last_forecast_seq) {
    if (m.seq == w->last_forecast_seq) return;  // a duplicate
    w->forecast_p.points.clear();  // the monitor's forecasts started again
  }
  w->last_forecast_seq = m.seq;
  ++w->forecasts;
  ++w->version;
  w->forecast = m;
  using F = rockwatch::wall_forecast_t;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double p = m.status == F::STATUS_OK          ? m.p_collapse
                   : m.status == F::STATUS_AT_REST   ? 0.0
                   : m.status == F::STATUS_COLLAPSED ? 1.0
                                                     : nan;
  // The calibrated P (SPEC §10; NaN where the monitor has no coefficients for its horizon: the page then draws the
  // ensemble's alone), in the point's second value.
  const double p_calibrated = m.status == F::STATUS_OK ? m.p_collapse_calibrated : p;
  if (std::isfinite(p) && m.utime > 0) add_point(w->forecast_p, seconds_of(m.utime), p, p_calibrated);
}

void SnapshotStore::count_decode_error() {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++decode_errors_;
}

json SnapshotStore::wall_json(const Wall& w, bool whole) const {
  json j{{"name", w.name},
         {"level", level_text(w.level)},
         {"level_code", w.level},
         {"reasons", alarm_reason_list(w.reasons)},
         {"collapsed_latched", w.collapsed_latched},
         {"limits", limits_json(settings_.limits)},
         {"transitions_total", w.transitions_total},
         {"counters",
          {{"states", w.states},
           {"alarms", w.alarms},
           {"statuses", w.statuses},
           {"sensor_samples", w.sensor_samples},
           {"estimates", w.estimates},
           {"forecasts", w.forecasts},
           {"monitor_restarts", w.monitor_restarts}}}};
  if (w.state) {
    const rockwatch::wall_state_t& s = *w.state;
    j["utime"] = s.utime;
    j["t_s"] = seconds_of(s.utime);
    j["x_m"] = number_or_null(s.x_m);
    j["xd_mps"] = number_or_null(s.xd_mps);
    j["energy_ratio"] = number_or_null(s.energy_ratio);
    j["t_to_instability_s"] = time_or_null(s.t_to_instability_s);
    j["moving"] = s.moving != 0;
    j["side"] = s.side;
    j["data_quality"] = quality_flag_list(static_cast<std::uint32_t>(s.data_quality));
  } else {
    for (const char* key : {"utime", "t_s", "x_m", "xd_mps", "energy_ratio", "t_to_instability_s"}) j[key] = nullptr;
    j["moving"] = false;
    j["side"] = nullptr;
    j["data_quality"] = json::array();
  }
  j["estimate"] = w.estimate ? estimate_json(*w.estimate) : json(nullptr);
  j["forecast"] = w.forecast ? forecast_json(*w.forecast) : json(nullptr);
  // Points as [id, t_s, x_m, energy_ratio] ([id, t_s, x_m] for the measured x; [id, t_s, P, P calibrated or null]
  // for the forecasts): compact, and the page appends by id.
  const auto series = [whole](const Series& s, bool with_second) {
    json points = json::array();
    for (const Point& p : s.points) {
      if (!whole && p.id < s.dirty_from) continue;
      json point{p.id, p.t_s, number_or_null(p.x_m)};
      if (with_second) point.push_back(number_or_null(p.energy_ratio));
      points.push_back(std::move(point));
    }
    return points;
  };
  j["points"] = series(w.predicted, true);
  j["measured"] = series(w.measured, false);
  j["forecast_points"] = series(w.forecast_p, true);
  if (whole || w.send_everything || w.transitions_total != w.pushed_transitions_total) {
    json transitions = json::array();
    for (const rockwatch::alarm_event_t& e : w.transitions) transitions.push_back(transition_json(e));
    j["transitions"] = std::move(transitions);
  }
  const std::int64_t status_seq = w.status ? w.status->seq : -1;
  if (whole || w.send_everything || status_seq != w.pushed_status_seq) j["status"] = w.status ? status_json(*w.status) : json(nullptr);
  return j;
}

json SnapshotStore::state_json() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  json walls = json::array();
  for (const auto& [name, w] : walls_) walls.push_back(wall_json(w, true));
  return json{{"walls", std::move(walls)},
              {"history_s", settings_.history_s},
              {"updates_per_s", settings_.updates_per_s},
              {"max_transitions", settings_.max_transitions},
              {"receiver",
               {{"messages", messages_}, {"decode_errors", decode_errors_}, {"walls_refused", walls_refused_}}}};
}

std::vector<std::string> SnapshotStore::take_updates(std::int64_t now_ns) {
  const std::lock_guard<std::mutex> lock(mutex_);
  // At most updates_per_s per second: the interval rounded up to whole nanoseconds.
  const std::int64_t interval_ns = (1000000000 + settings_.updates_per_s - 1) / settings_.updates_per_s;
  std::vector<std::string> updates;
  for (auto& [name, w] : walls_) {
    if (w.version == w.pushed_version) continue;
    if (w.pushed_once && now_ns - w.last_push_ns < interval_ns) continue;
    updates.push_back(
        json{{"type", "update"}, {"server_time_s", static_cast<double>(now_ns) * 1e-9}, {"wall", wall_json(w, false)}}
            .dump());
    w.pushed_version = w.version;
    w.pushed_once = true;
    w.last_push_ns = now_ns;
    w.predicted.dirty_from = kNothingDirty;
    w.measured.dirty_from = kNothingDirty;
    w.forecast_p.dirty_from = kNothingDirty;
    w.pushed_transitions_total = w.transitions_total;
    w.pushed_status_seq = w.status ? w.status->seq : -1;
    w.send_everything = false;
  }
  return updates;
}

std::size_t SnapshotStore::wall_count() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return walls_.size();
}

std::int64_t SnapshotStore::walls_refused() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return walls_refused_;
}

}  // namespace rockwatch::cli
