// `rockwatch simulate --engine-input-out FILE`: the fixed-point engine's configuration and every input it was given,
// in the engine-input format (firmware/include/rockwatch/firmware/engine_input_format.hpp) that the Cortex-M4 replay
// image reads (scripts/m4-replay.sh), so that the image runs exactly the steps this analysis ran.
#pragma once

#include <array>
#include <ostream>
#include <vector>

#include "rockwatch/core/sample_engine.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "simulate/simulate_request.hpp"

namespace rockwatch::cli {

// The WallEngine configuration equivalent to the analysis that ran: the wall, r as used, κ, the model, the
// integration step as the sample interval, the alarm settings the analysis' chain ran with, and the observer's
// settings when it ran (--wall-sensors).
core::WallEngineConfig engine_config_of(const SimulateRequest& q, const sim::AnalysisResult& result);

// The file's bytes (little-endian whatever the host); `wall_sensors` are the samples the observer was given (none
// without --wall-sensors).
void write_engine_input(std::ostream& out, const core::WallEngineConfig& config,
                        const std::vector<std::array<double, 2>>& inputs,
                        const std::vector<core::WallSensorSample>& wall_sensors);

}  // namespace rockwatch::cli
