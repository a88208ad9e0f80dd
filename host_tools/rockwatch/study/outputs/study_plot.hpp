// `rockwatch study --plots`: the design paper's Figures 6-8 per case, drawn from the study's own runs.csv and
// summary.json by the embedded host_tools/plots/study_figures.py in one Python run (matplotlib's start-up is most
// of a plot's time).
#pragma once

#include <string>
#include <vector>

#include "common/plots/python_plot.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "study/plan/study_request.hpp"
#include "study/report/study_forecast.hpp"
#include "study/report/study_summary.hpp"

namespace rockwatch::cli {

// Per case: "fig6_collapse_map_TAG.png" (record x PGA: collapsed or survived) and "fig7_max_displacement_TAG.png"
// (max |x| per run, survival rate per PGA and the fitted normal survival curve), TAG as case_tag() ("exp_HV").
std::vector<std::string> study_figure_names(const StudyOutcome& outcome);

// Runs the script on DIR/runs.csv and DIR/summary.json (both written already). Old figures are removed first
// (study_files.hpp), so a failed plot never leaves one that looks like this study's.
PlotOutcome plot_study_figures(const StudyRequest& request, const sim::study::StudyPlan& plan,
                               const StudyOutcome& outcome);

// --forecast: DIR/forecast_reliability.png from DIR/summary.json's "forecast" (written already) by the embedded
// host_tools/plots/forecast_reliability.py; an old one is removed first.
PlotOutcome plot_forecast_reliability(const StudyRequest& request, const sim::study::ForecastEvaluationPlan& evaluation,
                                      const sim::study::ForecastOutcome& outcome);

}  // namespace rockwatch::cli
