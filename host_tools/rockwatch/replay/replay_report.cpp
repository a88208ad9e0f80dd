#include "replay/replay_report.hpp"

#include <cstdio>
#include <optional>
#include <string>

#include "common/replay_out/lcm_multicast.hpp"
#include "common/replay_out/replay_lateness.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/verdict_json.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

std::string decimals(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

std::string six_digits(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string rate_text(double rate_hz) { return number_text(rate_hz) + " Hz"; }

std::string sensor_text(const SensorModel& s, std::size_t dropped) {
  if (!s.active()) return "none (the record's values)";
  std::string text;
  const auto add = [&text](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
  if (s.bias_mps2 != 0.0) add("bias " + number_text(s.bias_mps2) + " m/s2");
  if (s.noise_sd_mps2 > 0.0) add("noise SD " + number_text(s.noise_sd_mps2) + " m/s2");
  if (s.quantum_mps2 > 0.0) add("quantum " + number_text(s.quantum_mps2) + " m/s2");
  if (s.dropout > 0.0) add("dropout " + number_text(s.dropout) + " (" + std::to_string(dropped) + " samples not sent)");
  if (s.noise_sd_mps2 > 0.0 || s.dropout > 0.0) add("seed " + std::to_string(s.seed));
  return text;
}

std::string vertical_text(const InputMotion& in) {
  if (in.vertical_from_third_column) return "third column of " + in.horizontal.path;
  if (in.vertical) return in.vertical->path + (in.vertical->source.empty() ? "" : " (" + in.vertical->source + ")");
  return {};
}

nlohmann::ordered_json number_or_null(const std::optional<double>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

// What the engine concluded about the plant, in the words of `rockwatch simulate`'s summary.
std::string plant_verdict_text(const sim::AnalysisResult& a) {
  const std::string peak = "max |x| " + six_digits(a.max_abs_x_m) + " m = " +
                           decimals(a.max_abs_x_m / a.x_inst_m, 3) + " x_inst";
  if (a.collapsed) return "collapsed at t = " + decimals(*a.t_collapse_s, 3) + " s";
  if (a.collapse_after_end) {
    return "collapsed in the free rocking after the record, at t = " + decimals(*a.t_collapse_s, 3) + " s (" + peak +
           " before)";
  }
  return "survived, " + peak;
}

std::string plant_text(const ReplayRequest& q, const PlantRun& p, std::size_t sent) {
  const ReplayPlant& plant = *q.plant;
  std::string t = "  plant: " + plant.wall_file_path;
  for (const std::string& option : plant.wall_options_given) t += " " + option;
  t += " (r " + six_digits(p.result.r) + ", x_inst " + six_digits(p.result.x_inst_m) + " m): " +
       plant_verdict_text(p.result) + "\n";
  t += "  plant sensors: " + std::to_string(sent) + " of " + std::to_string(p.sensor_samples.size()) +
       " wall_sensor_t on " + q.wall_sensor_channel +
       (sent < p.sensor_samples.size() ? " (none after the record's last sample)" : "") + "\n";
  return t;
}

nlohmann::ordered_json plant_json(const ReplayRequest& q, const PlantRun& p, std::size_t sent) {
  using nlohmann::ordered_json;
  const ReplayPlant& plant = *q.plant;
  const sim::AnalysisResult& a = p.result;
  ordered_json j;
  j["wall_file"] = plant.wall_file_path;
  j["wall_options"] = plant.wall_options_given;
  j["r"] = a.r;
  j["model"] = model_name(plant.analysis.model);
  j["kappa"] = plant.analysis.kappa;
  add_verdict_json(j, a);  // simulate's keys: max_abs_x_m, t_max_abs_x_s, collapsed, … n_impacts
  j["x_inst_m"] = a.x_inst_m;
  j["t_final_s"] = a.t_final_s;
  const sim::SensorModel& m = plant.sensor_model;
  ordered_json dropouts = ordered_json::array();
  for (const sim::SensorDropout& d : m.dropouts) dropouts.push_back({d.from_s, d.to_s});
  j["sensor"] = {{"x_noise_m", m.x_noise_m},
                 {"x_bias_m", m.x_bias_m},
                 {"x_quantum_m", m.x_quantum_m},
                 {"rate_hz", m.rate_hz > 0.0 ? m.rate_hz : 1.0 / a.sample_dt_s},
                 {"a_noise_mps2", number_or_null(m.a_noise_mps2)},
                 {"dropouts", dropouts},
                 {"seed", m.seed}};
  j["sensor_samples"] = p.sensor_samples.size();
  j["sensor_samples_sent"] = sent;
  j["channel"] = q.wall_sensor_channel;
  return j;
}

}  // namespace

const char* message_type_name(int batch) { return batch > 0 ? "ground_accel_batch_t" : "ground_accel_t"; }

std::string replay_summary_text(const ReplayReport& r) {
  const ReplayRequest& q = r.request;
  const ReplayStream& s = r.stream;
  const ReplayOutcome& o = r.outcome;
  std::string t = "rockwatch replay: " + r.input.horizontal.path;
  if (!r.input.horizontal.source.empty()) t += " (" + r.input.horizontal.source + ")";
  t += "\n";
  t += "  record: " + std::to_string(r.input.horizontal.samples) + " samples at dt " +
       number_text(r.input.horizontal.dt_s) + " s, " + decimals(r.input.motion.duration_s(), 3) + " s";
  const std::string vertical = vertical_text(r.input);
  t += vertical.empty() ? "; no vertical (v'' = 0)\n" : "; vertical " + vertical + "\n";
  if (q.scale_pga_g) {
    t += "  scaled by " + six_digits(r.input.scale_factor) + " to PGA " + number_text(*q.scale_pga_g) + " g\n";
  }
  t += "  samples: " + std::to_string(s.size()) + " at " + rate_text(s.rate_hz) +
       (s.resampled ? " (resampled from " + number_text(1.0 / s.source_dt_s) + " Hz by linear interpolation)"
                    : " (the record's own samples)") +
       ", seq 0-" + std::to_string(s.size() == 0 ? 0 : s.size() - 1) + "\n";
  t += "  sensor model: " + sensor_text(q.sensor, s.dropped) + "\n";
  const std::string what = std::to_string(o.messages) + " " + message_type_name(q.batch) +
                           (q.batch > 0 ? " (up to " + std::to_string(q.batch) + " samples each)" : "") + " on " +
                           q.channel;
  if (q.publish) {
    t += "  published: " + what + " to " + q.lcm_url + "; " + std::to_string(o.samples_sent) + " samples sent, " +
         std::to_string(o.samples_dropped) + " dropped\n";
    if (q.wall_sensors_path) {
      t += "  wall sensors: " + std::to_string(o.wall_sensor_samples_sent) + " wall_sensor_t on " +
           q.wall_sensor_channel + " from " + *q.wall_sensors_path + "\n";
    }
    if (o.paced) {
      t += "  pacing: " + (q.speed == 1.0 ? std::string("real time") : "speed " + number_text(q.speed)) +
           ", absolute deadlines on CLOCK_MONOTONIC; " + decimals(o.elapsed_s, 3) + " s\n";
    } else {
      t += "  pacing: none (--speed 0, as fast as possible); " + decimals(o.elapsed_s, 3) + " s\n";
    }
  }
  if (r.plant) t += plant_text(q, *r.plant, o.wall_sensor_samples_sent);
  if (q.log_path) {
    t += "  log: " + *q.log_path + ": " + (q.publish ? "the same " : "") + what +
         ", stamped with the sample times (lcm-logplayer plays it)\n";
  }
  if (q.samples_out_path) t += "  samples out: " + *q.samples_out_path + " (t_s, ug_mps2, vg_mps2)\n";
  if (o.paced) t += lateness_text(o.lateness, "  ");
  if (o.publish_failures > 0) {
    t += "  publish failures: " + std::to_string(o.publish_failures) + " (" + o.first_failure + ")\n";
  }
  if (o.interrupted) {
    t += "  interrupted after " + std::to_string(o.samples_done) + " of " + std::to_string(s.size()) + " samples\n";
  }
  return t;
}

nlohmann::ordered_json replay_summary_json(const ReplayReport& r) {
  using nlohmann::ordered_json;
  const ReplayRequest& q = r.request;
  const ReplayStream& s = r.stream;
  const ReplayOutcome& o = r.outcome;
  ordered_json j;
  ordered_json record;
  record["path"] = r.input.horizontal.path;
  record["format"] = r.input.horizontal.format;
  record["dt_s"] = r.input.horizontal.dt_s;
  record["samples"] = r.input.horizontal.samples;
  record["duration_s"] = r.input.motion.duration_s();
  j["record"] = record;
  const std::string vertical = vertical_text(r.input);
  j["vertical"] = vertical.empty() ? ordered_json(nullptr) : ordered_json(vertical);
  add_selection_json(j, q.record);
  j["scale_factor"] = r.input.scale_factor;
  j["pga_mps2"] = sim::peak_abs(r.input.motion.ug_mps2);
  j["rate_hz"] = s.rate_hz;
  j["resampled"] = s.resampled;
  j["samples"] = s.size();
  j["samples_done"] = o.samples_done;
  j["samples_sent"] = o.samples_sent;
  j["samples_dropped"] = o.samples_dropped;
  j["messages"] = o.messages;
  if (q.wall_sensors_path) {
    j["wall_sensors"] = {{"file", *q.wall_sensors_path},
                         {"channel", q.wall_sensor_channel},
                         {"samples_sent", o.wall_sensor_samples_sent}};
  }
  if (r.plant) j["plant"] = plant_json(q, *r.plant, o.wall_sensor_samples_sent);
  j["message_type"] = message_type_name(q.batch);
  j["channel"] = q.channel;
  j["lcm_url"] = q.publish ? ordered_json(q.lcm_url) : ordered_json(nullptr);
  j["batch"] = q.batch > 0 ? ordered_json(q.batch) : ordered_json(nullptr);
  j["speed"] = q.speed;
  j["paced"] = o.paced;
  j["start_utime"] = o.start_utime;
  j["elapsed_s"] = o.elapsed_s;
  ordered_json sensor;
  sensor["noise_sd_mps2"] = q.sensor.noise_sd_mps2;
  sensor["seed"] = q.sensor.seed;
  sensor["bias_mps2"] = q.sensor.bias_mps2;
  sensor["quantum_mps2"] = q.sensor.quantum_mps2;
  sensor["dropout"] = q.sensor.dropout;
  j["sensor"] = sensor;
  if (q.log_path) {
    j["log"] = ordered_json{{"path", *q.log_path}, {"events", o.messages}};
  } else {
    j["log"] = nullptr;
  }
  j["samples_out"] = q.samples_out_path ? ordered_json(*q.samples_out_path) : ordered_json(nullptr);
  j["lateness"] = o.paced ? lateness_json(o.lateness) : ordered_json(nullptr);
  j["publish_failures"] = o.publish_failures;
  j["interrupted"] = o.interrupted;
  return j;
}

}  // namespace rockwatch::cli
