#include "simulate/engine_input_file.hpp"

#include <cstdint>
#include <cstring>

#include "rockwatch/firmware/engine_input_format.hpp"

namespace rockwatch::cli {

namespace {

void put_u64(std::ostream& out, std::uint64_t v) {
  char bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<char>((v >> (8 * i)) & 0xFFu);
  out.write(bytes, sizeof bytes);
}

void put_double(std::ostream& out, double v) {
  std::uint64_t bits = 0;
  static_assert(sizeof bits == sizeof v, "IEEE binary64 expected");
  std::memcpy(&bits, &v, sizeof bits);
  put_u64(out, bits);
}

}  // namespace

core::WallEngineConfig engine_config_of(const SimulateRequest& q, const sim::AnalysisResult& result) {
  core::WallEngineConfig c;
  c.wall = q.wall;
  c.r_energy = result.r;
  c.kappa = q.analysis.kappa;
  c.model = q.analysis.model;
  c.dt_s = result.sample_dt_s;             // one exported input per record sample,
  c.max_step_s = q.analysis.max_step_s;    // integrated in the same sub-steps as the host's analysis
  c.alarm = q.analysis.evaluate_alarm ? q.analysis.alarm : core::AlarmSettings{};  // as the analysis' chain
  c.observer_enabled = q.wall_sensors_path.has_value();
  c.observer = q.analysis.observer;
  c.work_overflow = q.analysis.work_overflow;  // the budget is the firmware's default (as the analysis' publication)
  return c;
}

void write_engine_input(std::ostream& out, const core::WallEngineConfig& config,
                        const std::vector<std::array<double, 2>>& inputs,
                        const std::vector<core::WallSensorSample>& wall_sensors) {
  out.write(firmware::kEngineInputMagic, sizeof firmware::kEngineInputMagic);
  std::uint64_t n_config = 0;
  firmware::for_each_engine_input_key(config, [&n_config](firmware::EngineInputKey, double) { ++n_config; });
  put_u64(out, n_config);
  firmware::for_each_engine_input_key(config, [&out](firmware::EngineInputKey key, double value) {
    put_u64(out, static_cast<std::uint64_t>(key));
    put_double(out, value);
  });
  put_u64(out, inputs.size());
  for (const std::array<double, 2>& in : inputs) {
    put_double(out, in[0]);
    put_double(out, in[1]);
  }
  put_u64(out, wall_sensors.size());
  for (const core::WallSensorSample& s : wall_sensors) {
    put_u64(out, static_cast<std::uint64_t>(s.utime_us));
    put_double(out, s.x_mid_m);
    put_double(out, s.a_mid_mps2);
    put_u64(out, (s.x_valid ? firmware::kEngineInputSensorValidX : 0) |
                     (s.a_valid ? firmware::kEngineInputSensorValidA : 0));
    put_u64(out, static_cast<std::uint64_t>(static_cast<std::int64_t>(s.sensor_status)));
  }
}

}  // namespace rockwatch::cli
