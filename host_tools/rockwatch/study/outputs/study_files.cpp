#include "study/outputs/study_files.hpp"

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/process/output_file.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "study/outputs/study_runs_csv.hpp"

namespace rockwatch::cli {

namespace {

namespace fs = std::filesystem;

bool is_study_figure(const std::string& name) {
  const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
  return png && (name.rfind("fig6_", 0) == 0 || name.rfind("fig7_", 0) == 0 || name == kForecastReliabilityName);
}

void remove_file(const std::string& path) {
  std::error_code ec;
  fs::remove(path, ec);
  if (ec) throw UsageError("--out: cannot replace " + path + ": " + ec.message());
}

}  // namespace

std::string study_file(const StudyRequest& q, const std::string& name) { return (fs::path(q.out_dir) / name).string(); }

void prepare_study_directory(const StudyRequest& q) {
  std::error_code ec;
  if (fs::exists(q.out_dir, ec) && !fs::is_directory(q.out_dir, ec)) {
    throw UsageError("--out " + quoted(q.out_dir) + " exists and is not a directory");
  }
  const std::string state = study_file(q, kStudyStateName);
  const bool holds_study = fs::exists(state, ec);
  if (q.resume) {
    if (!holds_study) {
      throw UsageError("--resume: --out " + quoted(q.out_dir) + " holds no study to continue (no " + state +
                       "); run without --resume to start one");
    }
    return;
  }
  if (holds_study && !q.force) {
    throw UsageError("--out " + quoted(q.out_dir) + " already holds a study (" + state +
                     "): give --resume to continue it, --force to replace it, or choose another directory");
  }
  fs::create_directories(q.out_dir, ec);
  if (ec) throw UsageError("--out " + quoted(q.out_dir) + ": cannot create the directory: " + ec.message());
  if (!holds_study) return;
  // --force: the old study goes first, state file first, so an interrupted removal leaves no study.json that
  // describes files of a study that is gone.
  for (const char* name : {kStudyStateName, kRunsCsvName, kSummaryJsonName, kTable3Name, kObserverRunsCsvName,
                           kForecastCsvName}) {
    remove_file(study_file(q, name));
  }
  remove_study_figures(q);
}

void remove_study_figures(const StudyRequest& q) {
  std::error_code ec;
  std::vector<std::string> figures;
  for (fs::directory_iterator it(q.out_dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (is_study_figure(name)) figures.push_back(it->path().string());
  }
  for (const std::string& figure : figures) remove_file(figure);
}

void write_study_file(const std::string& path, const std::function<void(std::ostream&)>& write_content) {
  const std::string partial = path + ".partial";
  write_output_file(partial, write_content, path);
  std::error_code ec;
  fs::rename(partial, path, ec);
  if (ec) {
    std::remove(partial.c_str());
    throw UsageError("--out: cannot put " + path + " in place: " + ec.message());
  }
}

}  // namespace rockwatch::cli
