#include "monitor_output.hpp"

#include <string>

#include "rockwatch/options/alarm_options.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

std::string level_name(std::int64_t level) {
  if (level >= 0 && level <= static_cast<std::int64_t>(core::AlarmLevel::collapsed)) {
    return core::alarm_level_name(static_cast<core::AlarmLevel>(level));
  }
  return "LEVEL" + std::to_string(level);
}

json alarm_json(const rockwatch::alarm_event_t& e) {
  const auto bits = static_cast<std::uint32_t>(e.reasons);
  json j;
  j["utime"] = e.utime;
  j["seq"] = e.seq;
  j["input_seq"] = e.input_seq;
  j["level"] = level_name(e.level);
  j["previous"] = level_name(e.previous_level);
  j["reason"] = options::alarm_reason_list(bits);
  j["reason_bits"] = bits;
  j["x_m"] = e.x_m;
  j["xd_mps"] = e.xd_mps;
  j["energy_ratio"] = e.energy_ratio;
  j["t_to_instability_s"] = e.t_to_instability_s < 0.0 ? json(nullptr) : json(e.t_to_instability_s);
  return j;
}

json counters_json(const firmware::MonitorCounters& c) {
  return json{{"samples_received", c.samples_received},
              {"samples_processed", c.samples_processed},
              {"samples_bridged", c.samples_bridged},
              {"gaps", c.gaps},
              {"state_resets", c.state_resets},
              {"duplicates", c.duplicates},
              {"out_of_order", c.out_of_order},
              {"late", c.late},
              {"rejected_not_finite", c.rejected_not_finite},
              {"rejected_out_of_range", c.rejected_out_of_range},
              {"lift_off", c.lift_off},
              {"publisher_restarts", c.publisher_restarts},
              {"decode_errors", c.decode_errors},
              {"saturated", c.saturated},
              {"sensor_flags", c.sensor_flags},
              {"publish_failures", c.publish_failures},
              {"messages_ignored", c.messages_ignored},
              {"log_write_failures", c.log_write_failures},
              {"time_untrusted", c.time_untrusted},
              {"worst_step_ns", c.worst_step_ns},
              {"alarm_events", c.alarm_events},
              {"states_published", c.states_published},
              {"samples_late", c.samples_late},
              {"max_late_calls", c.max_late_calls},
              {"samples_work_shed", c.samples_work_shed},
              {"samples_over_budget", c.samples_over_budget}};
}

json observer_json(const core::ObserverOptions& o, const core::ObserverSample& last, const core::ObserverCounters& c,
                  const firmware::MonitorCounters& loop) {
  json counters = json::object();
  core::visit_observer_counters(c, [&counters](const char* name, std::int64_t value) { counters[name] = value; });
  json out{{"settings",
            {{"x_noise_m", o.x_noise_m},
             {"a_noise_mps2", o.a_noise_mps2},
             {"process_accel_mps2", o.process_accel_mps2},
             {"gate_chi2", o.gate_chi2},
             {"dropout_s", o.dropout_s},
             {"max_age_s", o.max_age_s},
             {"capacity_sigmas", o.alarm_capacity_sigmas},
             {"accel_inform_peak_noises", o.accel_inform_peak_noises}}},
           {"r_estimate", last.r_estimate},
           {"x_inst_estimate_m", last.x_inst_estimate_m},
           {"sigma_x_inst_m", last.sigma_x_inst_m},
           {"x_inst_alarm_m", last.x_inst_alarm_m},
           {"sigma_r", last.sigma_r},
           {"bias_estimate_m", last.bias_m},
           {"sigma_x_m", last.sigma_x_m},
           {"sensor_health", last.flags},
           {"sensor_samples_received", loop.sensor_samples_received},
           {"sensor_time_untrusted", loop.sensor_time_untrusted},
           {"sensor_duplicates", loop.sensor_duplicates},
           {"estimates_published", loop.estimates_published},
           {"counters", counters}};
  // The capacity from the decline of the restoring force (SPEC §11): named only when not 0 (capacity_min_x is off by
  // default, doubt_capacity_min_x 0.25).
  if (o.capacity_min_x_fraction != 0.0) out["settings"]["capacity_min_x"] = o.capacity_min_x_fraction;
  if (o.doubt_capacity_min_x_fraction != 0.0) {
    out["settings"]["doubt_capacity_min_x"] = o.doubt_capacity_min_x_fraction;
  }
  if (o.capacity_correlation != 0.0) out["settings"]["capacity_correlation"] = o.capacity_correlation;  // opt-in
  if (o.noise_learn_readings != core::ObserverOptions{}.noise_learn_readings) {
    out["settings"]["noise_learn_readings"] = o.noise_learn_readings;  // SPEC §11 "The transducer's noise"
  }
  return out;
}

void AlarmPrinter::on_alarm(const rockwatch::alarm_event_t& event) {
  ++events_;
  if (event.level > max_level_) max_level_ = event.level;
  nlohmann::json line = alarm_json(event);
  if (!wall_.empty()) line["wall"] = wall_;
  out_ << line.dump() << '\n' << std::flush;
}

}  // namespace rockwatch::monitor
