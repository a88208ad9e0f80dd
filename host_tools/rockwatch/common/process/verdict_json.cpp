#include "common/process/verdict_json.hpp"

#include "common/process/text_report.hpp"

namespace rockwatch::cli {

void add_verdict_json(nlohmann::ordered_json& j, const sim::AnalysisResult& r) {
  j["max_abs_x_m"] = r.max_abs_x_m;
  // A wall that never moved has no time of maximum.
  j["t_max_abs_x_s"] = r.max_abs_x_m > 0.0 ? nlohmann::ordered_json(r.t_max_abs_x_s) : nlohmann::ordered_json(nullptr);
  j["collapsed"] = r.collapsed;
  j["t_collapse_s"] = number_or_null(r.t_collapse_s);
  j["t_exceed_s"] = number_or_null(r.t_exceed_s);
  j["collapse_after_end"] = r.collapse_after_end;
  j["n_impacts"] = r.n_impacts;
}

}  // namespace rockwatch::cli
