// The directory of a `rockwatch study` (--out): which files a study owns, the checks before any work (a directory
// that already holds a study is only continued with --resume or replaced with --force), and how files are written
// (complete or not at all, so an interrupted or failed write never leaves a half file that looks like a result).
#pragma once

#include <functional>
#include <ostream>
#include <string>

#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

inline constexpr const char* kStudyStateName = "study.json";
inline constexpr const char* kSummaryJsonName = "summary.json";
inline constexpr const char* kTable3Name = "table3.md";
inline constexpr const char* kObserverRunsCsvName = "observer_runs.csv";  // --observer
inline constexpr const char* kForecastCsvName = "forecast.csv";           // --forecast
inline constexpr const char* kForecastReliabilityName = "forecast_reliability.png";  // --forecast

// "DIR/NAME".
std::string study_file(const StudyRequest& request, const std::string& name);

// Creates --out (and its parents) if missing; refuses a path that is not a directory. Without --resume, refuses a
// directory that holds a study (study.json) unless --force, which removes the old study's files (runs.csv,
// summary.json, table3.md, study.json, observer_runs.csv, forecast.csv and its figures) so the directory never mixes two studies. With --resume,
// requires study.json. Throws UsageError naming --out.
void prepare_study_directory(const StudyRequest& request);

// Removes the figures of an earlier run (fig6_*.png, fig7_*.png, forecast_reliability.png), so a failed plot never leaves one that looks
// like this study's.
void remove_study_figures(const StudyRequest& request);

// Writes `path` through a temporary file renamed over it when complete. Throws UsageError naming --out and the
// file when it cannot be written.
void write_study_file(const std::string& path, const std::function<void(std::ostream&)>& write_content);

}  // namespace rockwatch::cli
