// What `rockwatch static` prints: JSON for scripts, a table per code for engineers, and the labels the results
// must carry (back-calculated spectrum, virtual-work derivation).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/core/static_check.hpp"
#include "static/static_request.hpp"

namespace rockwatch::cli {

// One case: exactly the keys T_s, x_eq_max_m, allowable_pga_g, K, X_m, lambda, spectrum, in that order.
nlohmann::ordered_json static_case_json(const StaticRequest& request, const StaticCase& c,
                                        const core::StaticResult& result);

// An object for one case, an array (in case order) for several. `results` is parallel to request.cases.
nlohmann::ordered_json static_json(const StaticRequest& request, const std::vector<core::StaticResult>& results);

// Multi-line table ending with a newline. `results` is parallel to request.cases.
std::string static_summary_text(const StaticRequest& request, const std::vector<core::StaticResult>& results);

// The labels, one sentence each, for stderr in --json mode and for the sweep's report.
std::vector<std::string> static_labels(const core::StaticInputs& inputs, bool general_case);

// "NTC 2008" / "NZSEE 2016" / "given lambda".
std::string case_title(const StaticCase& c);

// Which branch of the spectrum shape the period falls on, e.g. "TC < T <= TD (p TC/T)".
std::string spectrum_branch_text(const core::SpectrumShape& s, double period_s);

}  // namespace rockwatch::cli
