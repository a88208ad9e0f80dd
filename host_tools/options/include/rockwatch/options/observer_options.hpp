// The wall observer's settings on a command line (core::ObserverOptions, core/wall_observer.hpp): --observer-x-noise-m,
// --observer-a-noise-mps2, --observer-process-mps2, --observer-gate-chi2, --observer-capacity-sigmas and
// --observer-accel-inform-peak-noises, --observer-doubt-nis, --observer-quiet-motion-noises, --observer-model-form-sigma,
// --observer-doubt-model-form-sigma, --observer-capacity-min-x, --observer-doubt-capacity-min-x,
// --observer-capacity-correlation, with the defaults of
// core::ObserverOptions in their help and one range check each, whose message names the option. `rockwatch simulate
// --wall-sensors` and `rockwatch study --observer` use them; the monitor can register the same options.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rockwatch/options/cli11_fwd.hpp"

#include "rockwatch/core/wall_observer.hpp"

namespace rockwatch::options {

struct ObserverOptionTexts {
  std::string x_noise, a_noise, process, gate, capacity_sigmas, accel_inform_peak_noises, doubt_nis, quiet_motion_noises;
  std::string model_form_sigma, doubt_model_form_sigma, capacity_min_x, doubt_capacity_min_x, capacity_correlation;
  std::string noise_learn_readings;
};

// The ranges core::validate_observer_options accepts: its table's (core::kObserverParameters), not a copy.
inline constexpr const core::ObserverParameter& observer_range(const char* field) {
  return *core::observer_parameter(field);  // a name not in the table does not compile (null dereference)
}
inline constexpr double kMinObserverXNoise_m = observer_range("x_noise_m").min,
                        kMaxObserverXNoise_m = observer_range("x_noise_m").max;
inline constexpr double kMinObserverANoise_mps2 = observer_range("a_noise_mps2").min,
                        kMaxObserverANoise_mps2 = observer_range("a_noise_mps2").max;
inline constexpr double kMinObserverProcess_mps2 = observer_range("process_accel_mps2").min,
                        kMaxObserverProcess_mps2 = observer_range("process_accel_mps2").max;
inline constexpr double kMinObserverGateChi2 = observer_range("gate_chi2").min,
                        kMaxObserverGateChi2 = observer_range("gate_chi2").max;
inline constexpr double kMinObserverCapacitySigmas = observer_range("alarm_capacity_sigmas").min,
                        kMaxObserverCapacitySigmas = observer_range("alarm_capacity_sigmas").max;
inline constexpr double kMinObserverAccelInformPeakNoises = observer_range("accel_inform_peak_noises").min,
                        kMaxObserverAccelInformPeakNoises = observer_range("accel_inform_peak_noises").max;
// 0 = off (zero_allowed); values in (0, 1) pass here and are refused by the core's own check, naming the range.
inline constexpr double kMinObserverDoubtNis = 0.0, kMaxObserverDoubtNis = observer_range("doubt_nis").max;
static_assert(observer_range("doubt_nis").zero_allowed, "--observer-doubt-nis 0 turns model doubt off");
inline constexpr double kMinObserverQuietMotionNoises = observer_range("quiet_motion_spread_noises").min,
                        kMaxObserverQuietMotionNoises = observer_range("quiet_motion_spread_noises").max;
inline constexpr double kMinObserverModelFormSigma = observer_range("model_form_sigma").min,
                        kMaxObserverModelFormSigma = observer_range("model_form_sigma").max;
static_assert(observer_range("doubt_model_form_sigma").min == kMinObserverModelFormSigma &&
                  observer_range("doubt_model_form_sigma").max == kMaxObserverModelFormSigma,
              "--observer-doubt-model-form-sigma shares --observer-model-form-sigma's range");
inline constexpr double kMinObserverCapacityMinX = observer_range("capacity_min_x_fraction").min,
                        kMaxObserverCapacityMinX = observer_range("capacity_min_x_fraction").max;
static_assert(observer_range("doubt_capacity_min_x_fraction").min == kMinObserverCapacityMinX &&
                  observer_range("doubt_capacity_min_x_fraction").max == kMaxObserverCapacityMinX,
              "--observer-doubt-capacity-min-x shares --observer-capacity-min-x's range");
// 0 = off (zero_allowed); 1 to 7 pass here and are refused by the core's own check, naming the range.
inline constexpr double kMinObserverNoiseLearnReadings = 0.0,
                        kMaxObserverNoiseLearnReadings = observer_range("noise_learn_readings").max;
static_assert(observer_range("noise_learn_readings").zero_allowed, "--observer-noise-learn-readings 0 turns it off");
inline constexpr double kMinObserverCapacityCorrelation = observer_range("capacity_correlation").min,
                        kMaxObserverCapacityCorrelation = observer_range("capacity_correlation").max;

// The option names, in registration order.
inline constexpr const char* kObserverOptionNames[] = {"--observer-x-noise-m", "--observer-a-noise-mps2",
                                                       "--observer-process-mps2", "--observer-gate-chi2",
                                                       "--observer-capacity-sigmas",
                                                       "--observer-accel-inform-peak-noises",
                                                       "--observer-doubt-nis", "--observer-quiet-motion-noises",
                                                       "--observer-model-form-sigma",
                                                       "--observer-doubt-model-form-sigma",
                                                       "--observer-capacity-min-x",
                                                       "--observer-doubt-capacity-min-x",
                                                       "--observer-capacity-correlation",
                                                       "--observer-noise-learn-readings"};

// Registers the options; each help starts with `help_prefix` (e.g. "With --wall-sensors: ").
void add_observer_options(CLI::App& app, ObserverOptionTexts& texts, const std::string& help_prefix);

// True when any of them was given.
bool observer_option_given(const CLI::App& app);

// core::ObserverOptions with the given settings replaced. Throws UsageError "OPTION must be in [LOW, HIGH] UNIT
// (got VALUE)" naming the option at fault.
core::ObserverOptions parse_observer_options(const CLI::App& app, const ObserverOptionTexts& texts);

// The core::observer_flag bits by name, in bit order ("x_active", "sensor_lost", ...; "bitN" for a bit this tool does
// not know), and the same joined with ", " ("none" for 0).
std::vector<std::string> observer_flag_list(std::uint32_t flags);
std::string observer_flag_names(std::uint32_t flags);

}  // namespace rockwatch::options
