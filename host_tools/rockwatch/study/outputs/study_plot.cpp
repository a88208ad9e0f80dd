#include "study/outputs/study_plot.hpp"

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "study/outputs/study_files.hpp"
#include "study/outputs/study_runs_csv.hpp"

namespace rockwatch::cli {

namespace {

std::string fig6_name(const CaseOutcome& c) { return "fig6_collapse_map_" + c.tag + ".png"; }
std::string fig7_name(const CaseOutcome& c) { return "fig7_max_displacement_" + c.tag + ".png"; }

}  // namespace

std::vector<std::string> study_figure_names(const StudyOutcome& o) {
  std::vector<std::string> names;
  for (const CaseOutcome& c : o.cases) {
    names.push_back(fig6_name(c));
    names.push_back(fig7_name(c));
  }
  return names;
}

PlotOutcome plot_study_figures(const StudyRequest& q, const sim::study::StudyPlan& plan, const StudyOutcome& o) {
  remove_study_figures(q);
  std::vector<std::string> args{study_file(q, kRunsCsvName), study_file(q, kSummaryJsonName)};
  for (std::size_t i = 0; i < o.cases.size(); ++i) {
    const CaseOutcome& c = o.cases[i];
    args.push_back(std::to_string(i));
    args.push_back(plan.vertical[c.study_case.vertical_index] ? "true" : "false");
    args.push_back(plan.restitutions[c.study_case.restitution_index].label);
    args.push_back(study_file(q, fig6_name(c)));
    args.push_back(study_file(q, fig7_name(c)));
    args.push_back(c.title + " (" + std::to_string(plan.records.size()) + " records)");
  }
  return run_plot_script("study_figures", args);
}

PlotOutcome plot_forecast_reliability(const StudyRequest& q, const sim::study::ForecastEvaluationPlan& e,
                                      const sim::study::ForecastOutcome& o) {
  const std::string png = study_file(q, kForecastReliabilityName);
  std::remove(png.c_str());
  const std::string title = "Reliability: " + std::to_string(o.forecasts) + " forecasts of " + std::to_string(o.runs) +
                            " runs, " + std::to_string(e.settings.members) + " members";
  return run_plot_script("forecast_reliability", {study_file(q, kSummaryJsonName), png, title});
}

}  // namespace rockwatch::cli
