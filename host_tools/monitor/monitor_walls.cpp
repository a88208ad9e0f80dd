#include "monitor_walls.hpp"

#include <cstddef>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::monitor {

namespace {

using options::UsageError;
using nlohmann::json;

constexpr std::size_t kMaxWallNameLength = 24;

struct WallKey {
  const char* key;
  double core::WallParameters::*member;
};
constexpr WallKey kWallKeys[8] = {
    {"b", &core::WallParameters::b_m},       {"h1", &core::WallParameters::h1_m},
    {"h2", &core::WallParameters::h2_m},     {"rho", &core::WallParameters::rho_kgpm3},
    {"fp", &core::WallParameters::fp_npm},   {"a", &core::WallParameters::a},
    {"a_prime", &core::WallParameters::a_prime}, {"g", &core::WallParameters::g_mps2},
};

bool wall_name_ok(const std::string& name) {
  if (name.empty() || name.size() > kMaxWallNameLength) return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

bool wall_channel_ok(const std::string& name) {
  if (name.empty() || name.size() >= firmware::kChannelNameMax) return false;
  for (const char c : name) {
    if (c <= ' ' || c > '~') return false;
  }
  return true;
}

class WallsReader {
 public:
  explicit WallsReader(std::string label) : label_(std::move(label)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw UsageError(label_ + key + ": " + what);
  }

  void keys(const json& o, const std::string& key, const std::vector<std::string>& allowed) const {
    if (!o.is_object()) fail(key, "expected an object {...}");
    for (auto it = o.begin(); it != o.end(); ++it) {
      bool known = false;
      for (const std::string& a : allowed) known = known || a == it.key();
      if (!known) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(key, "unknown key " + options::quoted(it.key()) + " (expected " + list + ")");
      }
    }
  }

  double number(const json& v, const std::string& key) const {
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(key, "expected a finite number, got " + v.dump());
    return v.get<double>();
  }

  std::string channel(const json& v, const std::string& key) const {
    if (!v.is_string() || !wall_channel_ok(v.get<std::string>())) {
      fail(key, "expected a channel name of 1 to " + std::to_string(firmware::kChannelNameMax - 1) +
                    " printable ASCII characters without spaces, got " + v.dump());
    }
    return v.get<std::string>();
  }

 private:
  std::string label_;
};

void set_name(char (&field)[firmware::kChannelNameMax], const std::string& name) {
  std::memset(field, 0, sizeof field);
  std::memcpy(field, name.data(), name.size());
}

}  // namespace

void expand_monitor_walls(MonitorConfig& config, const json& walls, const std::string& label) {
  const WallsReader r(label);
  if (!walls.is_array() || walls.empty()) {
    r.fail("", "expected an array of 1 to " + std::to_string(firmware::kMaxMonitorWalls) +
                   " walls [{\"name\": ..., \"wall\": {...}}, ...]");
  }
  if (walls.size() > firmware::kMaxMonitorWalls) {
    r.fail("", std::to_string(walls.size()) + " walls: one monitor follows at most " +
                   std::to_string(firmware::kMaxMonitorWalls) + " (run another monitor for the others)");
  }
  std::set<std::string> names;
  const firmware::MonitorSettings& base = config.settings;
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const std::string at = "[" + std::to_string(i) + "]";
    const json& w = walls[i];
    r.keys(w, at, {"name", "wall", "r", "channels"});
    if (!w.contains("name") || !w.at("name").is_string() || !wall_name_ok(w.at("name").get<std::string>())) {
      r.fail(at + ".name", "expected a name of 1 to " + std::to_string(kMaxWallNameLength) +
                               " letters, digits, '_' or '-' (it suffixes the wall's channels), got " +
                               (w.contains("name") ? w.at("name").dump() : std::string("none")));
    }
    WallMonitorConfig wall;
    wall.name = w.at("name").get<std::string>();
    if (!names.insert(wall.name).second) r.fail(at + ".name", "\"" + wall.name + "\" is the name of an earlier wall");
    wall.settings = base;
    wall.restitution = config.restitution;
    wall.wall_origin = config.wall_origin;
    core::WallParameters& p = wall.settings.engine.wall;
    if (w.contains("wall")) {
      const json& fields = w.at("wall");
      std::vector<std::string> allowed;
      for (const WallKey& k : kWallKeys) allowed.emplace_back(k.key);
      r.keys(fields, at + ".wall", allowed);
      std::string given;
      for (const WallKey& k : kWallKeys) {
        if (!fields.contains(k.key)) continue;
        p.*k.member = r.number(fields.at(k.key), at + ".wall." + k.key);
        given += std::string(given.empty() ? "" : ", ") + k.key;
      }
      wall.wall_origin = "walls" + at + " (" + wall.name + "): " + config.wall_origin + " with " + given;
    }
    const core::WallCheck check = core::validate_wall(p);
    if (!check.ok()) r.fail(at + ".wall." + check.field, check.message);
    if (w.contains("r")) {
      const json& rv = w.at("r");
      try {
        wall.restitution = rv.is_number() ? options::parse_restitution("r", options::number_text(rv.get<double>()))
                                          : options::parse_restitution("r", rv.is_string() ? rv.get<std::string>() : rv.dump());
      } catch (const UsageError&) {
        r.fail(at + ".r", "expected \"ana\", \"exp\", \"impulse\" or a number in [0, 1], got " + rv.dump());
      }
    }
    sim::AnalysisOptions options;
    options.restitution = wall.restitution;
    options.model = wall.settings.engine.model;
    try {
      options::check_computable(p, options);
    } catch (const UsageError& e) {
      r.fail(at + ".wall", e.what());
    }
    wall.settings.engine.r_energy = core::restitution_energy_ratio(p, wall.restitution);

    // Channels: outputs suffixed with the name (none for "wall"); inputs shared unless the wall names its own.
    const std::string suffix = wall.name == "wall" ? std::string() : "_" + wall.name;
    firmware::MonitorChannels& ch = wall.settings.channels;
    for (char(*field)[firmware::kChannelNameMax] : {&ch.wall_state, &ch.alarm, &ch.status, &ch.wall_estimate}) {
      const std::string name = std::string(*field) + suffix;
      if (!wall_channel_ok(name)) {
        r.fail(at + ".name", "the channel " + options::quoted(name) + " is longer than " +
                                 std::to_string(firmware::kChannelNameMax - 1) + " characters: use a shorter name");
      }
      set_name(*field, name);
    }
    const std::string sensor = std::string(base.channels.wall_sensor) + suffix;
    if (wall_channel_ok(sensor)) set_name(ch.wall_sensor, sensor);
    if (w.contains("channels")) {
      const json& c = w.at("channels");
      r.keys(c, at + ".channels", {"accel", "accel_batch", "wall_sensor"});
      if (c.contains("accel")) set_name(ch.accel, r.channel(c.at("accel"), at + ".channels.accel"));
      if (c.contains("accel_batch")) set_name(ch.accel_batch, r.channel(c.at("accel_batch"), at + ".channels.accel_batch"));
      if (c.contains("wall_sensor")) set_name(ch.wall_sensor, r.channel(c.at("wall_sensor"), at + ".channels.wall_sensor"));
    }
    config.walls.push_back(wall);
  }
}

json walls_json(const std::vector<WallMonitorConfig>& walls) {
  json out = json::array();
  for (const WallMonitorConfig& w : walls) {
    const core::WallParameters& p = w.settings.engine.wall;
    const firmware::MonitorChannels& c = w.settings.channels;
    json r = w.restitution.kind == core::RestitutionKind::value ? json(w.restitution.value)
                                                                 : json(core::restitution_name(w.restitution.kind));
    json entry{{"name", w.name},
               {"wall", {{"b", p.b_m}, {"h1", p.h1_m}, {"h2", p.h2_m}, {"rho", p.rho_kgpm3}, {"fp", p.fp_npm},
                         {"a", p.a}, {"a_prime", p.a_prime}, {"g", p.g_mps2}}},
               {"r", r},
               {"r_energy_ratio", w.settings.engine.r_energy},
               {"channels",
                {{"accel", c.accel}, {"accel_batch", c.accel_batch}, {"wall_state", c.wall_state}, {"alarm", c.alarm},
                 {"status", c.status}}}};
    if (w.settings.engine.observer_enabled) {
      entry["channels"]["wall_sensor"] = c.wall_sensor;
      entry["channels"]["wall_estimate"] = c.wall_estimate;
    }
    out.push_back(entry);
  }
  return out;
}

}  // namespace rockwatch::monitor
