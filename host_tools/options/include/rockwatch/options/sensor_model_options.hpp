// The model of a simulated wall's sensors on a command line (sim::SensorModel, sim/wall_sensor_synthesis.hpp):
// --sensor-noise-m, --sensor-bias-m, --sensor-quantum-m, --sensor-rate-hz, --sensor-dropout (repeatable),
// --sensor-accel-noise-mps2 and --sensor-seed, with sim::SensorModel's defaults in their help and one check each,
// whose message names the option. `rockwatch simulate --sensors-out` and `rockwatch replay --wall-file` (the wall as
// a plant) use them, so both make the same samples from the same options.
#pragma once

#include <string>
#include <vector>

#include "rockwatch/options/cli11_fwd.hpp"

#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::options {

// The options as typed; parse_sensor_model_options converts and checks them.
struct SensorModelOptionTexts {
  std::string noise, bias, quantum, rate, accel_noise, seed;
  std::vector<std::string> dropouts;  // T0:T1 each
};

// The option names, in registration order.
inline constexpr const char* kSensorModelOptionNames[] = {"--sensor-noise-m",          "--sensor-bias-m",
                                                          "--sensor-quantum-m",        "--sensor-rate-hz",
                                                          "--sensor-dropout",          "--sensor-accel-noise-mps2",
                                                          "--sensor-seed"};

// Registers the options; each help starts with `help_prefix` (e.g. "With --sensors-out: ").
void add_sensor_model_options(CLI::App& app, SensorModelOptionTexts& texts, const std::string& help_prefix);

// The first of them given, or nullptr: for "OPTION sets ...: give --X too" messages.
const char* first_sensor_model_option_given(const CLI::App& app);

// sim::SensorModel{} with the given settings replaced. Throws UsageError naming the option at fault: "OPTION must be
// in [LOW, HIGH] UNIT (got VALUE)", "--sensor-dropout must be T0:T1 in seconds", "--sensor-seed must be a whole
// number from 0 to 2^64-1".
sim::SensorModel parse_sensor_model_options(const CLI::App& app, const SensorModelOptionTexts& texts);

}  // namespace rockwatch::options
