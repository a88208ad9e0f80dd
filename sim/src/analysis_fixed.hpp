// The fixed-point path of sim::analyse (AnalysisOptions::arithmetic == fixed_point): the same record handling,
// post-record energy verdict and summary as the double engine, run on core::FixedRockingStepper.
#pragma once

#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim::detail {

// Called by analyse() after the options and input have been validated. Throws AnalysisError when the wall or
// record does not fit the fixed-point formats (the message names the quantity and its range).
AnalysisResult analyse_fixed(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o);

}  // namespace rockwatch::sim::detail
