// The wall observer's settings on a command line (core::ObserverOptions, core/wall_observer.hpp): --observer-x-noise-m,
// --observer-a-noise-mps2, --observer-process-mps2, --observer-gate-chi2, --observer-capacity-sigmas and
// --observer-accel-inform-peak-noises, --observer-doubt-nis, --observer-quiet-motion-noises, --observer-model-form-sigma,
// --observer-doubt-model-form-sigma, with the defaults of core::ObserverOptions in their help and one range check
// each, whose message names the option. `rockwatch simulate --wall-sensors` and `rockwatch study --observer` use them;
// the monitor can register the same options.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/core/wall_observer.hpp"

namespace rockwatch::options {

struct ObserverOptionTexts {
  std::string x_noise, a_noise, process, gate, capacity_sigmas, accel_inform_peak_noises, doubt_nis, quiet_motion_noises;
  std::string model_form_sigma, doubt_model_form_sigma;
};

// The ranges core::validate_observer_options accepts.
inline constexpr double kMinObserverXNoise_m = 1e-6, kMaxObserverXNoise_m = 0.1;
inline constexpr double kMinObserverANoise_mps2 = 1e-4, kMaxObserverANoise_mps2 = 10.0;
inline constexpr double kMinObserverProcess_mps2 = 1e-4, kMaxObserverProcess_mps2 = 100.0;
inline constexpr double kMinObserverGateChi2 = 1.0, kMaxObserverGateChi2 = 1000.0;
inline constexpr double kMinObserverCapacitySigmas = 0.0, kMaxObserverCapacitySigmas = 10.0;
inline constexpr double kMinObserverAccelInformPeakNoises = 0.0, kMaxObserverAccelInformPeakNoises = 1000.0;
inline constexpr double kMinObserverDoubtNis = 0.0, kMaxObserverDoubtNis = 1000.0;  // 0 = off; else ≥ 1 (core)
inline constexpr double kMinObserverQuietMotionNoises = 0.0, kMaxObserverQuietMotionNoises = 1000.0;
inline constexpr double kMinObserverModelFormSigma = 0.0, kMaxObserverModelFormSigma = 1.0;

// The option names, in registration order.
inline constexpr const char* kObserverOptionNames[] = {"--observer-x-noise-m", "--observer-a-noise-mps2",
                                                       "--observer-process-mps2", "--observer-gate-chi2",
                                                       "--observer-capacity-sigmas",
                                                       "--observer-accel-inform-peak-noises",
                                                       "--observer-doubt-nis", "--observer-quiet-motion-noises",
                                                       "--observer-model-form-sigma",
                                                       "--observer-doubt-model-form-sigma"};

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
