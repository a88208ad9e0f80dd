// `rockwatch study`: the collapse-probability study of the design paper (SPEC §6, Table 3) through sim::study's
// batch engine and statistics. This file wires the parts together (records, plan, directory, resume, progress,
// interruption, outputs) and maps failures to messages and exit statuses; the analyses and statistics are sim's.
#include <csignal>
#include <cstddef>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/progress_line.hpp"
#include "common/process/signal_interrupt.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "study/outputs/study_files.hpp"
#include "study/run/study_observer.hpp"
#include "study/plan/study_plan.hpp"
#include "study/outputs/study_plot.hpp"
#include "study/run/study_progress.hpp"
#include "study/plan/study_records.hpp"
#include "study/plan/study_request.hpp"
#include "study/scale/study_mpi.hpp"
#include "study/outputs/study_runs_csv.hpp"
#include "study/scale/study_scaled.hpp"
#include "study/outputs/study_state.hpp"
#include "study/report/study_forecast.hpp"
#include "study/report/study_summary.hpp"
#include "study/report/study_table3.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

constexpr CommandErrors kErrors{"rockwatch study: error: ", "out of memory (too many or too long records?)"};

std::size_t count_done(const std::vector<study::RunResult>& results) {
  std::size_t done = 0;
  for (const study::RunResult& r : results) done += r.done ? 1 : 0;
  return done;
}

void write_runs(const StudyRequest& q, const study::StudyPlan& plan, const std::vector<study::RunResult>& results) {
  write_study_file(study_file(q, kRunsCsvName), [&](std::ostream& out) { write_runs_csv(out, plan, results); });
}

// --resume: the finished runs of the earlier run(s), from runs.csv (none when the study stopped before writing it).
std::size_t load_finished_runs(const StudyRequest& q, const study::StudyPlan& plan,
                               const nlohmann::ordered_json& plan_description,
                               std::vector<study::RunResult>& results) {
  check_same_plan(q, plan_description);
  const std::string runs = study_file(q, kRunsCsvName);
  std::error_code ec;
  if (!std::filesystem::exists(runs, ec)) {
    std::cerr << "note: --resume: " << runs << " does not exist: no analysis was finished, running them all\n";
    return 0;
  }
  return read_runs_csv(runs, plan, results);
}

int interrupted(const StudyRequest& q, const study::StudyPlan& plan, const nlohmann::ordered_json& plan_description,
                const std::vector<study::RunResult>& results, int signal_number) {
  const std::size_t done = count_done(results), total = results.size();
  write_runs(q, plan, results);
  write_study_state(q, plan_description, StudyState::interrupted, done, total);
  std::cout.flush();
  std::cerr << kErrors.prefix << "interrupted by " << (signal_number == SIGTERM ? "SIGTERM" : "SIGINT") << ": "
            << done << " of " << total << " analyses done, written to " << study_file(q, kRunsCsvName)
            << "\nresume with:\n  " << resume_command(q) << '\n';
  return kExitInterrupted;
}

int run(const StudyRequest& q) {
  StudyRecords records = load_study_records(q);
  for (const std::string& note : records.notes) std::cerr << "note: " << note << '\n';
  study::StudyPlan plan = build_study_plan(q, records);
  study::validate_plan(plan);
  const std::size_t total = study::run_count(plan);
  if (total > kMaxStudyRuns) {
    throw UsageError(std::to_string(total) + " analyses (" + std::to_string(plan.records.size()) + " records x " +
                     std::to_string(plan.pga_g.size()) + " PGA levels x " + std::to_string(plan.restitutions.size()) +
                     " --r x " + std::to_string(plan.vertical.size()) + " --vertical) are more than the " +
                     std::to_string(kMaxStudyRuns) + " a study may take: use fewer records (--sets) or levels (--pga)");
  }
  const StaticCapacities capacities = static_capacities(plan.wall);
  nlohmann::ordered_json plan_description = plan_json(plan);
  std::optional<study::ObserverEvaluationPlan> evaluation;
  if (q.observer) {
    evaluation = observer_evaluation_plan(plan, q.observer_options);
    plan_description["observer"] = observer_plan_json(*evaluation);
  }
  if (q.forecast) plan_description["forecast"] = forecast_plan_json(*q.forecast);

  prepare_study_directory(q);
  std::vector<study::RunResult> results(total);
  const std::size_t resumed = q.resume ? load_finished_runs(q, plan, plan_description, results) : 0;
  if (q.resume) {
    std::cerr << "study: resuming: " << resumed << " of " << total << " analyses done, running the other "
              << total - resumed << '\n';
  }
  write_study_state(q, plan_description, StudyState::running, resumed, total);

  {
    const SignalInterrupt interrupt;
    StudyProgress progress(std::cerr, stderr_is_terminal(), resumed, total, interrupt.flag());
    study::run_study(
        plan, results, q.jobs, [&progress](std::size_t done, std::size_t in_call) { progress.report(done, in_call); },
        interrupt.flag());
    progress.finish();
    if (count_done(results) < total) {
      return interrupted(q, plan, plan_description, results, interrupt.signal_number());
    }
  }

  // --observer: the evaluation after the study (not checkpointed: --resume runs it again).
  std::optional<sim::study::ObserverOutcome> observed;
  std::vector<study::ObserverRunResult> observer_results;
  if (evaluation) {
    const std::size_t runs = study::observer_run_count(plan, *evaluation);
    std::cerr << "study: wall observer evaluation: " << runs << " runs of 3 analyses ("
              << evaluation->cases.size() << " mismatch cases)\n";
    const SignalInterrupt interrupt;
    StudyProgress progress(std::cerr, stderr_is_terminal(), 0, runs, interrupt.flag());
    study::run_observer_evaluation(
        plan, *evaluation, observer_results, q.jobs,
        [&progress](std::size_t done, std::size_t in_call) { progress.report(done, in_call); }, interrupt.flag());
    progress.finish();
    std::size_t done = 0;
    for (const study::ObserverRunResult& r : observer_results) done += r.done ? 1 : 0;
    if (done < runs) return interrupted(q, plan, plan_description, results, interrupt.signal_number());
    observed = sim::study::observer_outcome(plan, *evaluation, observer_results);
  }

  // --forecast: the ensemble forecast's evaluation (not checkpointed either).
  std::optional<sim::study::ForecastOutcome> forecasted;
  std::vector<study::ForecastRunResult> forecast_results;
  if (q.forecast) {
    const std::size_t runs = study::forecast_run_count(plan);
    std::cerr << "study: forecast evaluation: " << runs << " runs (horizontal only), " << q.forecast->settings.members
              << " members over " << q.forecast->settings.horizon_s << " s every " << q.forecast->every_s << " s\n";
    const SignalInterrupt interrupt;
    StudyProgress progress(std::cerr, stderr_is_terminal(), 0, runs, interrupt.flag());
    study::run_forecast_evaluation(
        plan, *q.forecast, forecast_results, q.jobs,
        [&progress](std::size_t done, std::size_t in_call) { progress.report(done, in_call); }, interrupt.flag());
    progress.finish();
    std::size_t done = 0;
    for (const study::ForecastRunResult& r : forecast_results) done += r.done ? 1 : 0;
    if (done < runs) return interrupted(q, plan, plan_description, results, interrupt.signal_number());
    forecasted = sim::study::forecast_outcome(plan, forecast_results, q.forecast->settings.members);
  }

  const StudyOutcome outcome = summarise_study(plan, results, capacities);
  write_runs(q, plan, results);
  nlohmann::ordered_json summary = summary_json(plan, records, results, outcome);
  if (observed) summary["observer"] = observer_summary_json(*evaluation, *observed);
  if (forecasted) summary["forecast"] = forecast_summary_json(*q.forecast, *forecasted);
  write_study_file(study_file(q, kSummaryJsonName), [&](std::ostream& out) { out << summary.dump(2) << '\n'; });
  write_study_file(study_file(q, kTable3Name),
                   [&](std::ostream& out) { out << table3_markdown(plan, records, outcome); });

  std::vector<std::string> files{study_file(q, kRunsCsvName), study_file(q, kSummaryJsonName),
                                 study_file(q, kTable3Name), study_file(q, kStudyStateName)};
  if (evaluation) {
    write_study_file(study_file(q, kObserverRunsCsvName), [&](std::ostream& out) {
      write_observer_runs_csv(out, plan, *evaluation, observer_results);
    });
    files.push_back(study_file(q, kObserverRunsCsvName));
  }
  if (forecasted) {
    write_study_file(study_file(q, kForecastCsvName), [&](std::ostream& out) {
      write_forecast_csv(out, plan, forecast_results, *forecasted);
    });
    files.push_back(study_file(q, kForecastCsvName));
  }
  int status = kExitOk;
  std::string plot_failure;
  if (q.plots) {
    const PlotOutcome plot = plot_study_figures(q, plan, outcome);
    if (plot.ok) {
      for (const std::string& name : study_figure_names(outcome)) files.push_back(study_file(q, name));
    } else {
      plot_failure = plot.message;
    }
  }
  if (forecasted) {  // after the study's figures (their call clears every figure of an earlier run)
    const PlotOutcome plot = plot_forecast_reliability(q, *q.forecast, *forecasted);
    if (plot.ok) {
      files.push_back(study_file(q, kForecastReliabilityName));
    } else if (plot_failure.empty()) {
      plot_failure = plot.message;
    }
  }
  // The state last: a study.json that says complete means every file above is this study's.
  write_study_state(q, plan_description, StudyState::complete, total, total);

  std::cout << study_summary_text(q, plan, records, outcome, files,
                                  (observed ? observer_summary_text(*evaluation, *observed) : std::string()) +
                                      (forecasted ? forecast_summary_text(*q.forecast, *forecasted) : std::string()));
  if (!plot_failure.empty()) {
    std::cout.flush();
    status = fail(kErrors, "plots not written: " + plot_failure, kExitInternalError);
  }
  const int written = finish_stdout(kErrors);
  return written != kExitOk ? written : status;
}

}  // namespace

int study_main(int argc, const char* const* argv) {
  if (argc > 1 && std::string(argv[1]) == "merge") return study_merge_main(argc - 1, argv + 1);
  return run_command(kErrors, [&] {
    const StudyParse parsed = parse_study_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    // At scale (study_scaled.hpp): a portfolio, a shard, MPI ranks.
    if (parsed.request->mpi) return run_mpi_study(*parsed.request);
    if (parsed.request->walls_file || parsed.request->shard_count > 0) return run_scaled_study(*parsed.request);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
