// What `rockwatch simulate` prints: the JSON object for scripts, the summary for engineers.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "common/records_in/input_motion.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "simulate/simulate_request.hpp"

namespace rockwatch::cli {

// Exactly the documented keys, in a fixed order; times that did not happen are null. The record-selection keys
// (add_selection_json) follow only when --suite, --component, --channel, --vertical-channel or --gain was used.
nlohmann::ordered_json result_json(const SimulateRequest& request, const sim::AnalysisResult& result);

// Multi-line, human-readable summary ending with a newline.
std::string summary_text(const SimulateRequest& request, const InputMotion& input, const sim::AnalysisResult& result);

// "COLLAPSED", "COLLAPSED AFTER THE RECORD", "SURVIVED" or "UNDECIDED".
const char* verdict_word(const sim::AnalysisResult& result);

}  // namespace rockwatch::cli
