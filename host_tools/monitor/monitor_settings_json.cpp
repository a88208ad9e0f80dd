// The monitor's settings as --print-config shows them and as their digest is computed: the normalised settings, the
// FNV-1a digest and the channel names' copy into the firmware's fixed fields.
#include <cstdint>
#include <cstring>
#include <string>

#include "monitor_command_line.hpp"
#include "monitor_config.hpp"
#include "monitor_walls.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/options/option_values.hpp"

namespace rockwatch::monitor {

using nlohmann::json;
using config_detail::arith_name;

bool set_channel(char (&field)[firmware::kChannelNameMax], const std::string& name) {
  if (name.size() >= firmware::kChannelNameMax) return false;
  std::memset(field, 0, sizeof field);
  std::memcpy(field, name.data(), name.size());
  return true;
}

std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t hash) {
  for (const char c : bytes) {
    hash ^= static_cast<std::uint8_t>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string digest_hex(std::int64_t digest) {
  static const char* const kDigits = "0123456789abcdef";
  const auto u = static_cast<std::uint64_t>(digest);
  std::string text = "0x";
  for (int shift = 60; shift >= 0; shift -= 4) text += kDigits[(u >> shift) & 0xFu];
  return text;
}

json normalised_settings(const MonitorConfig& config) {
  const firmware::MonitorSettings& s = config.settings;
  const core::WallParameters& w = s.engine.wall;
  json r;
  if (config.restitution.kind == core::RestitutionKind::value) {
    r = config.restitution.value;
  } else {
    r = core::restitution_name(config.restitution.kind);
  }
  json out{
      {"format", "rockwatch-monitor settings 1"},
      {"arith", arith_name(s.arithmetic)},
      {"wall", {{"b", w.b_m}, {"h1", w.h1_m}, {"h2", w.h2_m}, {"rho", w.rho_kgpm3}, {"fp", w.fp_npm}, {"a", w.a},
                {"a_prime", w.a_prime}, {"g", w.g_mps2}}},
      {"r", r},
      {"r_energy_ratio", s.engine.r_energy},
      {"model", s.engine.model == core::ModelKind::full ? "full" : "linear"},
      {"kappa", s.engine.kappa},
      {"alarm",
       {{"lambda_w", s.engine.alarm.lambda_warning}, {"hold_s", s.engine.alarm.hold_s},
        {"energy_margin", s.engine.alarm.energy_margin}}},
      {"sample_rate_hz", s.sample_rate_hz},
      {"max_step_s", s.engine.max_step_s},
      {"substeps", core::substeps_per_sample(1.0 / s.sample_rate_hz, s.engine.max_step_s)},
      {"max_bridge_samples", s.max_bridge_samples},
      {"sensor_range_mps2", s.sensor_range_mps2},
      {"late_limit_s", s.late_limit_s},
      {"restart_window", s.restart_window},
      {"channels",
       {{"accel", s.channels.accel}, {"accel_batch", s.channels.accel_batch}, {"wall_state", s.channels.wall_state},
        {"alarm", s.channels.alarm}, {"status", s.channels.status}}},
  };
  // The horizon and energy_min_x: named when not 0, their value before they became defaults (2026-12-01), so that
  // the digest of a configuration written before says what ran then and today's defaults are named in it.
  if (s.engine.alarm.imminent_horizon_s != 0.0) {
    out["alarm"]["imminent_horizon_s"] = s.engine.alarm.imminent_horizon_s;
  }
  if (s.engine.alarm.energy_min_x != 0.0) {
    out["alarm"]["energy_min_x"] = s.engine.alarm.energy_min_x;
  }
  // The observer changes every output; absent when off, so that the digest of a configuration without it stays.
  if (s.engine.observer_enabled) {
    const core::ObserverOptions& o = s.engine.observer;
    out["observer"] = {{"enabled", true},
                       {"x_noise_m", o.x_noise_m},
                       {"a_noise_mps2", o.a_noise_mps2},
                       {"process_accel_mps2", o.process_accel_mps2},
                       {"gate_chi2", o.gate_chi2},
                       {"dropout_s", o.dropout_s},
                       {"max_age_s", o.max_age_s}};
    // Only when changed: the digest of a configuration written before the key existed stays.
    if (o.alarm_capacity_sigmas != core::ObserverOptions{}.alarm_capacity_sigmas) {
      out["observer"]["capacity_sigmas"] = o.alarm_capacity_sigmas;
    }
    if (o.accel_inform_peak_noises != core::ObserverOptions{}.accel_inform_peak_noises) {
      out["observer"]["accel_inform_peak_noises"] = o.accel_inform_peak_noises;
    }
    if (o.doubt_nis != core::ObserverOptions{}.doubt_nis) out["observer"]["doubt_nis"] = o.doubt_nis;
    if (o.quiet_motion_spread_noises != core::ObserverOptions{}.quiet_motion_spread_noises) {
      out["observer"]["quiet_motion_spread_noises"] = o.quiet_motion_spread_noises;
    }
    if (o.model_form_sigma != core::ObserverOptions{}.model_form_sigma) {
      out["observer"]["model_form_sigma"] = o.model_form_sigma;
    }
    if (o.doubt_model_form_sigma != core::ObserverOptions{}.doubt_model_form_sigma) {
      out["observer"]["doubt_model_form_sigma"] = o.doubt_model_form_sigma;
    }
    if (o.capacity_min_x_fraction != core::ObserverOptions{}.capacity_min_x_fraction) {
      out["observer"]["capacity_min_x"] = o.capacity_min_x_fraction;
    }
    if (o.doubt_capacity_min_x_fraction != core::ObserverOptions{}.doubt_capacity_min_x_fraction) {
      out["observer"]["doubt_capacity_min_x"] = o.doubt_capacity_min_x_fraction;
    }
    if (o.capacity_correlation != core::ObserverOptions{}.capacity_correlation) {
      out["observer"]["capacity_correlation"] = o.capacity_correlation;
    }
    if (o.noise_learn_readings != core::ObserverOptions{}.noise_learn_readings) {
      out["observer"]["noise_learn_readings"] = o.noise_learn_readings;
    }
    out["channels"]["wall_sensor"] = s.channels.wall_sensor;
    out["channels"]["wall_estimate"] = s.channels.wall_estimate;
  }
  // Many walls: each one's own settings; absent with one wall (the digest of such a configuration stays).
  if (!config.walls.empty()) out["walls"] = walls_json(config.walls);
  // The clock tolerance decides which times are trusted; absent at the default (the digest of existing configurations
  // stays).
  if (s.engine.work_budget_units != 0) out["work_budget_units"] = s.engine.work_budget_units;  // absent when off
  if (s.engine.work_overflow != core::WorkOverflow::shed) {  // absent at the default
    out["work_overflow"] = options::work_overflow_name(s.engine.work_overflow);
  }
  if (s.clock_tolerance_us != firmware::kDefaultClockTolerance_us) {
    out["clock_tolerance_s"] = static_cast<double>(s.clock_tolerance_us) * 1e-6;
  }
  // The live forecast adds an output; absent when off (the digest of every configuration without it stays).
  if (config.forecast.enabled) {
    const ForecastConfig& f = config.forecast;
    out["forecast"] = {{"members", f.members}, {"horizon_s", f.horizon_s}, {"rate_hz", f.rate_hz},
                       {"seed", f.seed},       {"channel", f.channel}};
    // Given coefficients only (the shipped ones leave the digest of a forecast configuration as it was); four when c4
    // is 0 (the first calibration's model: the digest of a configuration that gave four numbers stays).
    if (f.calibration) {
      const auto& k = *f.calibration;
      out["forecast"]["calibration"] =
          k[4] == 0.0 ? json::array({k[0], k[1], k[2], k[3]}) : json(k);
    }
  }
  // Which sources are accepted changes what the monitor processes; absent when any is (the default digest stays).
  if (!config.accept_from.empty()) {
    json a = json::array();
    for (const SourceNetwork& n : config.accept_from) a.push_back(source_network_text(n));
    out["accept_from"] = a;
  }
  return out;
}

}  // namespace rockwatch::monitor
