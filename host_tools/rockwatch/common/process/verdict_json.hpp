// The engine's verdict on one wall as the commands' --json states it (simulate's top level, replay's plant): written
// once, so that a monitor's tester comparing `replay --wall-file --json` with `simulate --wall-file --json` compares
// the same keys computed by the same code.
#pragma once

#include <nlohmann/json.hpp>

#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

// Adds max_abs_x_m, t_max_abs_x_s (null when the wall never moved), collapsed, t_collapse_s, t_exceed_s,
// collapse_after_end and n_impacts to j, in that order.
void add_verdict_json(nlohmann::ordered_json& j, const sim::AnalysisResult& result);

}  // namespace rockwatch::cli
