#include "rockwatch/options/sensor_model_options.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::options {

namespace {

// T0:T1 with finite T0 < T1 [s].
sim::SensorDropout parse_dropout(const std::string& text) {
  const std::vector<std::string> fields = split_fields(text, ':');
  if (fields.size() != 2) {
    throw UsageError("--sensor-dropout must be T0:T1 in seconds (got " + quoted(text) + ")");
  }
  sim::SensorDropout d;
  d.from_s = parse_finite_number("--sensor-dropout", fields[0]);
  d.to_s = parse_finite_number("--sensor-dropout", fields[1]);
  if (!(d.from_s < d.to_s)) {
    throw UsageError("--sensor-dropout T0:T1 needs T0 < T1 (got " + quoted(text) + ")");
  }
  return d;
}

}  // namespace

void add_sensor_model_options(CLI::App& app, SensorModelOptionTexts& texts, const std::string& help_prefix) {
  const sim::SensorModel d{};
  app.add_option("--sensor-noise-m", texts.noise,
                 help_prefix + "Gaussian noise of the displacement [m] (default " + number_text(d.x_noise_m) + ")")
      ->type_name("S");
  app.add_option("--sensor-bias-m", texts.bias,
                 help_prefix + "zero offset of the displacement [m] (default " + number_text(d.x_bias_m) + ")")
      ->type_name("B");
  app.add_option("--sensor-quantum-m", texts.quantum,
                 help_prefix + "resolution, readings rounded to multiples of Q [m] (default 0: none)")
      ->type_name("Q");
  app.add_option("--sensor-rate-hz", texts.rate, help_prefix + "samples per second (default: the record's rate)")
      ->type_name("F");
  app.add_option("--sensor-dropout", texts.dropouts, help_prefix + "no samples from T0 to T1 [s] (repeatable)")
      ->type_name("T0:T1");
  app.add_option("--sensor-accel-noise-mps2", texts.accel_noise,
                 help_prefix + "also write a_mid_mps2 with this Gaussian noise [m/s2] (default: no column)")
      ->type_name("A");
  app.add_option("--sensor-seed", texts.seed,
                 help_prefix + "seed of the noise, 0 to 2^64-1 (default " + std::to_string(d.seed) + ")")
      ->type_name("N");
}

const char* first_sensor_model_option_given(const CLI::App& app) {
  for (const char* name : kSensorModelOptionNames) {
    if (given(app, name)) return name;
  }
  return nullptr;
}

sim::SensorModel parse_sensor_model_options(const CLI::App& app, const SensorModelOptionTexts& texts) {
  sim::SensorModel m;
  if (given(app, "--sensor-noise-m")) m.x_noise_m = parse_number_in("--sensor-noise-m", texts.noise, 0.0, 1.0, " m");
  if (given(app, "--sensor-bias-m")) m.x_bias_m = parse_number_in("--sensor-bias-m", texts.bias, -1.0, 1.0, " m");
  if (given(app, "--sensor-quantum-m")) {
    m.x_quantum_m = parse_number_in("--sensor-quantum-m", texts.quantum, 0.0, 1.0, " m");
  }
  if (given(app, "--sensor-rate-hz")) {
    m.rate_hz = parse_number_in("--sensor-rate-hz", texts.rate, 0.0, 1e5, " Hz");
    if (!(m.rate_hz > 0.0)) throw UsageError("--sensor-rate-hz must be > 0 Hz (got 0)");
  }
  for (const std::string& text : texts.dropouts) m.dropouts.push_back(parse_dropout(text));
  if (given(app, "--sensor-accel-noise-mps2")) {
    m.a_noise_mps2 = parse_number_in("--sensor-accel-noise-mps2", texts.accel_noise, 0.0, 1000.0, " m/s2");
  }
  if (given(app, "--sensor-seed")) {
    const std::optional<std::uint64_t> seed = whole_number(texts.seed, 0, UINT64_MAX);
    if (!seed) throw UsageError("--sensor-seed must be a whole number from 0 to 2^64-1 (got " + quoted(texts.seed) + ")");
    m.seed = *seed;
  }
  return m;
}

}  // namespace rockwatch::options
