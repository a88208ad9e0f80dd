// The engine seam of the monitor loop lives in core (rockwatch/core/sample_engine.hpp), so that the firmware's
// fixed-point engine and the host's double engine (sim::DoubleWallEngine) implement it without either depending on
// the other's layer. The firmware uses the names in its own namespace.
#pragma once

#include "rockwatch/core/sample_engine.hpp"

namespace rockwatch::firmware {

using core::EngineSample;
using core::MonitorArithmetic;
using core::SampleEngine;
using core::validate_wall_engine_config;
using core::WallEngineConfig;
using core::WallEngineError;

const char* wall_engine_error_message(WallEngineError e);  // defined in wall_engine.cpp

}  // namespace rockwatch::firmware
