// What `rockwatch study` was asked to do, parsed and validated from its command line. Only the options are checked
// here; the records (the suite's manifest, the --records list) are read when the plan is built (study_records.hpp).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/forecast_evaluation.hpp"

namespace rockwatch::cli {

// Bounds on the work one run may ask for: a typo such as --pga 0.1:30:0.0001 should be an error message, not days
// of computing. The paper's study is 20 levels and 1760 analyses.
inline constexpr std::size_t kMaxStudyLevels = 1000;
inline constexpr std::size_t kMaxStudyRuns = 1000000;
inline constexpr std::size_t kMaxStudyJobs = 1024;

// The paper's study (SPEC section 6): 0.11 to 0.30 g by 0.01 g.
inline constexpr const char* kDefaultStudyPga = "0.11:0.30:0.01";

struct StudyRequest {
  // Records: the shipped suite (found at run time, common/shipped_suite.hpp) unless --suite or --records.
  std::optional<std::string> suite_dir;     // --suite DIR
  std::optional<std::string> records_list;  // --records LIST
  std::optional<std::vector<int>> sets;     // --sets, ascending, without repeats; checked against the manifest later
  std::string sets_text;                    // --sets as given, for messages
  records::ReadOptions read_options;        // --units, --dt, --gain, --channel and the wall's g, for --records files
  std::optional<std::string> vertical_channel;  // --vertical-channel, for the partner files of --records

  WallChoice wall;
  sim::AnalysisOptions analysis;            // model, kappa, max step (restitution is per case)
  std::vector<double> pga_g;                // levels, ascending
  std::string pga_text;                     // --pga as given (or the default)
  std::vector<sim::study::RestitutionCase> restitutions;  // --r, in the order given
  std::vector<bool> vertical;               // --vertical: false = without, true = with, in the order given

  std::size_t jobs = 0;                     // 0: every hardware thread
  bool dt_check = false;
  bool observer = false;                    // --observer: the wall observer's evaluation (with --alarms)
  core::ObserverOptions observer_options;   // --observer-*
  // --forecast: the ensemble forecast's evaluation (issue 29 item 4; study/report/study_forecast.hpp).
  std::optional<sim::study::ForecastEvaluationPlan> forecast;
  bool plots = false;
  bool resume = false;
  bool force = false;
  std::string out_dir;
  std::optional<std::string> walls_file;    // --walls FILE.csv: a portfolio, one wall per row (study_walls.hpp)
  std::size_t shard_index = 0;              // --shard K/N: K (from 1) ...
  std::size_t shard_count = 0;              //   ... and N; 0: the whole plan
  bool mpi = false;                         // --mpi: the plan over the ranks of an MPI job (study_mpi.hpp)
  std::vector<std::string> arguments;       // argv[1] onwards as given: the resume hint repeats them
};

struct StudyParse {
  std::optional<StudyRequest> request;  // empty: print help_text, exit 0
  std::string help_text;
};

// Parses `rockwatch study` arguments (argv[0] is the command name). Throws UsageError naming the option at fault.
StudyParse parse_study_arguments(int argc, const char* const* argv);

// The levels of FROM:TO:STEP [g]: FROM, FROM + STEP, ... up to TO (inclusive, to a tolerance of 1e-9 STEP), each
// rounded to 1e-12 g so 0.11 + 3 x 0.01 is the double nearest 0.14. Throws UsageError naming `option`.
std::vector<double> parse_pga_levels(const std::string& option, const std::string& text);

// "1,2", "1-3", "1,4-6": set numbers >= 1, ascending and without repeats whatever the order given. Throws UsageError.
std::vector<int> parse_set_list(const std::string& option, const std::string& text);

}  // namespace rockwatch::cli
