#include "study/scale/study_scaled.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <csignal>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/progress_line.hpp"
#include "common/plots/python_plot.hpp"
#include "common/process/signal_interrupt.hpp"
#include "common/process/text_report.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "study/outputs/study_files.hpp"
#include "study/outputs/study_plot.hpp"
#include "study/run/study_progress.hpp"
#include "study/outputs/study_runs_csv.hpp"
#include "study/outputs/study_state.hpp"
#include "rockwatch/sim/study/quantile.hpp"
#include "study/report/study_summary.hpp"
#include "study/report/study_table3.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;
namespace fs = std::filesystem;

constexpr CommandErrors kScaledErrors{"rockwatch study: error: ", "out of memory (too many walls or records?)"};

nlohmann::ordered_json wall_parameters_json(const core::WallParameters& w) {
  return {{"b_m", w.b_m},       {"h1_m", w.h1_m}, {"h2_m", w.h2_m},       {"rho_kgpm3", w.rho_kgpm3},
          {"fp_npm", w.fp_npm}, {"a", w.a},       {"a_prime", w.a_prime}, {"g_mps2", w.g_mps2}};
}

double h_over_b(const core::WallParameters& w) { return (w.h1_m + w.h2_m) / w.b_m; }

std::string optional_field(bool ok, double value) { return ok ? number_text(value) : std::string(); }
std::string optional_field(const std::optional<double>& value) { return value ? number_text(*value) : std::string(); }

void remove_if_present(const std::string& path) {
  std::error_code ec;
  fs::remove(path, ec);
  if (ec) throw UsageError("--out: cannot replace " + path + ": " + ec.message());
}

// The arguments a shard's merge parses again: the study's options without those of one run (where it writes, how
// many threads, which shard, resuming or replacing).
std::vector<std::string> plan_arguments(const std::vector<std::string>& arguments) {
  std::vector<std::string> kept;
  for (std::size_t i = 0; i < arguments.size(); ++i) {
    const std::string& a = arguments[i];
    if (a == "--resume" || a == "--force" || a == "--mpi") continue;
    if (a == "--out" || a == "--jobs" || a == "--shard") {
      ++i;  // and its value
      continue;
    }
    if (a.rfind("--out=", 0) == 0 || a.rfind("--jobs=", 0) == 0 || a.rfind("--shard=", 0) == 0) continue;
    kept.push_back(a);
  }
  return kept;
}

void write_shard_state(const ScaledStudy& s, const std::string& state) {
  nlohmann::ordered_json j;
  j["format"] = "rockwatch-study-shard";
  j["version"] = 1;
  j["shard"] = s.request.shard_index;
  j["shards"] = s.request.shard_count;
  j["state"] = state;
  j["plan_digest"] = plan_digest(s.plan_description);
  j["runs_total"] = s.total();
  j["runs_in_shard"] = runs_in_shard(s);
  j["runs_done"] = runs_done(s);
  j["arguments"] = plan_arguments(s.request.arguments);
  write_study_file(study_file(s.request, kShardStateName), [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

// --walls: one row per wall and case.
void write_walls_summary(const ScaledStudy& s, const std::vector<StudyOutcome>& outcomes) {
  write_study_file(study_file(s.request, kWallsSummaryName), [&](std::ostream& out) {
    out << "id,r,vertical,fit_mean_g,fit_std_g,lognormal_median_g,lognormal_beta,p_collapse_ntc2008,"
           "p_collapse_nzsee2016,allowable_pga_ntc2008_g,allowable_pga_nzsee2016_g\n";
    for (std::size_t w = 0; w < s.walls.size(); ++w) {
      for (const CaseOutcome& c : outcomes[w].cases) {
        const study::CaseStatistics empty;
        const study::CaseStatistics& st = c.statistics ? *c.statistics : empty;
        out << s.walls[w].id << ',' << s.plan.restitutions[c.study_case.restitution_index].label << ','
            << (s.plan.vertical[c.study_case.vertical_index] ? "true" : "false") << ','
            << optional_field(st.normal.ok, st.normal.mean_g) << ',' << optional_field(st.normal.ok, st.normal.std_g)
            << ',' << optional_field(st.lognormal.ok, st.lognormal.median_g) << ','
            << optional_field(st.lognormal.ok, st.lognormal.beta) << ',' << optional_field(st.at_ntc2008.normal_fit)
            << ',' << optional_field(st.at_nzsee2016.normal_fit) << ','
            << number_text(outcomes[w].capacities.ntc2008_g) << ',' << number_text(outcomes[w].capacities.nzsee2016_g)
            << '\n';
      }
    }
  });
}

std::string portfolio_text(const ScaledStudy& s, const std::vector<StudyOutcome>& outcomes,
                           const std::vector<std::string>& files) {
  std::string out = "rockwatch study: collapse probability of a portfolio of walls (SPEC 6, per wall as the design "
                    "paper's Table 3)\n\n";
  line(out, "records", records_text(s.records));
  double lo = h_over_b(s.walls.front().wall), hi = lo;
  for (const PortfolioWall& w : s.walls) {
    lo = std::min(lo, h_over_b(w.wall));
    hi = std::max(hi, h_over_b(w.wall));
  }
  line(out, "walls", format("%zu from %s (h/b %.1f to %.1f)", s.walls.size(), s.request.walls_file->c_str(), lo, hi));
  line(out, "PGA levels",
       number_text(s.plan.pga_g.front()) + " to " + number_text(s.plan.pga_g.back()) + " g (" +
           std::to_string(s.plan.pga_g.size()) + " levels)");
  line(out, "analyses", format("%zu (%zu per wall, model %s, kappa %s, max step %s s)", s.total(), s.runs_per_wall,
                               model_name(s.plan.analysis.model), number_text(s.plan.analysis.kappa).c_str(),
                               number_text(s.plan.analysis.max_step_s).c_str()));
  std::size_t errors = 0;
  for (const StudyOutcome& o : outcomes) errors += o.runs_with_error;
  if (errors > 0) line(out, "refused runs", format("%zu (no verdict; the error column of runs.csv)", errors));
  out += "\n";
  const std::vector<StudyCase> cases = study_cases(s.plan);
  for (std::size_t c = 0; c < cases.size(); ++c) {
    std::vector<double> medians;
    std::size_t over_ntc = 0, over_nzsee = 0, undetermined = 0;
    for (const StudyOutcome& o : outcomes) {
      const CaseOutcome& co = o.cases[c];
      if (!co.statistics || !co.statistics->lognormal.ok) {
        ++undetermined;
      } else {
        medians.push_back(co.statistics->lognormal.median_g);
      }
      if (co.statistics && co.statistics->at_ntc2008.normal_fit && *co.statistics->at_ntc2008.normal_fit > 0.1) {
        ++over_ntc;
      }
      if (co.statistics && co.statistics->at_nzsee2016.normal_fit && *co.statistics->at_nzsee2016.normal_fit > 0.1) {
        ++over_nzsee;
      }
    }
    std::sort(medians.begin(), medians.end());
    std::string text = "lognormal median ";
    if (medians.empty()) {
      text += "undetermined for every wall";
    } else {
      text += format("%.3f to %.3f g (median over walls %.3f g)", medians.front(), medians.back(),
                     *study::quantile_type7(medians, 0.5));
      if (undetermined > 0) text += format(", undetermined for %zu", undetermined);
    }
    text += format("; P(collapse) > 0.1 at the NTC 2008 capacity: %zu walls, at NZSEE 2016: %zu", over_ntc, over_nzsee);
    line(out, ("case " + case_title(s.plan, cases[c])).c_str(), text);
  }
  out += "\n";
  std::string file_list;
  for (const std::string& f : files) file_list += (file_list.empty() ? "" : ", ") + f;
  line(out, "files", file_list);
  return out;
}

int finish_portfolio(ScaledStudy& s) {
  const StudyRequest& q = s.request;
  std::vector<StudyOutcome> outcomes;
  outcomes.reserve(s.walls.size());
  nlohmann::ordered_json walls = nlohmann::ordered_json::array();
  std::size_t with_error = 0;
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    set_wall(s, w);
    outcomes.push_back(summarise_study(s.plan, s.results[w], s.walls[w].capacities));
    with_error += outcomes.back().runs_with_error;
    nlohmann::ordered_json one = summary_json(s.plan, s.records, s.results[w], outcomes.back());
    nlohmann::ordered_json entry;
    entry["id"] = s.walls[w].id;
    entry["wall"] = wall_parameters_json(s.walls[w].wall);
    entry["h_over_b"] = h_over_b(s.walls[w].wall);
    for (const char* key : {"capacities", "runs", "dt_check", "cases", "alarm", "fixed_vs_double"}) {
      if (one.contains(key)) entry[key] = one[key];
    }
    walls.push_back(std::move(entry));
  }
  write_scaled_runs(s);
  nlohmann::ordered_json summary;
  summary["format"] = "rockwatch-study-summary";
  summary["version"] = 1;
  const nlohmann::ordered_json first = summary_json(s.plan, s.records, s.results.back(), outcomes.back());
  summary["records_source"] = first["records_source"];
  summary["plan"] = s.plan_description;
  summary["runs"] = {{"total", s.total()}, {"with_error", with_error}};
  summary["walls"] = std::move(walls);
  write_study_file(study_file(q, kSummaryJsonName), [&](std::ostream& out) { out << summary.dump(2) << '\n'; });
  write_walls_summary(s, outcomes);
  std::vector<std::string> files{study_file(q, kRunsCsvName), study_file(q, kSummaryJsonName),
                                 study_file(q, kWallsSummaryName), study_file(q, kStudyStateName)};
  int status = kExitOk;
  std::string plot_failure;
  if (q.plots) {
    remove_if_present(study_file(q, kWallsFigureName));
    const PlotOutcome plot = run_plot_script(
        "walls_fragility", {study_file(q, kSummaryJsonName), study_file(q, kWallsFigureName),
                            std::to_string(s.walls.size()) + " walls, " + std::to_string(s.plan.records.size()) +
                                " records"});
    if (plot.ok) {
      files.push_back(study_file(q, kWallsFigureName));
    } else {
      plot_failure = plot.message;
    }
  }
  write_study_state(q, s.plan_description, StudyState::complete, s.total(), s.total());
  std::cout << portfolio_text(s, outcomes, files);
  if (!plot_failure.empty()) {
    std::cout.flush();
    status = fail(kScaledErrors, "plots not written: " + plot_failure, kExitInternalError);
  }
  const int written = finish_stdout(kScaledErrors);
  return written != kExitOk ? written : status;
}

// The single-process study's outputs, in its order (study_command.cpp run()), for one wall without --walls.
int finish_one_wall(ScaledStudy& s) {
  const StudyRequest& q = s.request;
  set_wall(s, 0);
  const std::vector<study::RunResult>& results = s.results[0];
  const StudyOutcome outcome = summarise_study(s.plan, results, s.walls[0].capacities);
  write_scaled_runs(s);
  const nlohmann::ordered_json summary = summary_json(s.plan, s.records, results, outcome);
  write_study_file(study_file(q, kSummaryJsonName), [&](std::ostream& out) { out << summary.dump(2) << '\n'; });
  write_study_file(study_file(q, kTable3Name),
                   [&](std::ostream& out) { out << table3_markdown(s.plan, s.records, outcome); });
  std::vector<std::string> files{study_file(q, kRunsCsvName), study_file(q, kSummaryJsonName),
                                 study_file(q, kTable3Name), study_file(q, kStudyStateName)};
  int status = kExitOk;
  std::string plot_failure;
  if (q.plots) {
    const PlotOutcome plot = plot_study_figures(q, s.plan, outcome);
    if (plot.ok) {
      for (const std::string& name : study_figure_names(outcome)) files.push_back(study_file(q, name));
    } else {
      plot_failure = plot.message;
    }
  }
  write_study_state(q, s.plan_description, StudyState::complete, s.total(), s.total());
  std::cout << study_summary_text(q, s.plan, s.records, outcome, files);
  if (!plot_failure.empty()) {
    std::cout.flush();
    status = fail(kScaledErrors, "plots not written: " + plot_failure, kExitInternalError);
  }
  const int written = finish_stdout(kScaledErrors);
  return written != kExitOk ? written : status;
}

}  // namespace

nlohmann::ordered_json ScaledStudy::state_plan() const {
  if (!sharded()) return plan_description;
  nlohmann::ordered_json j = plan_description;
  j["shard"] = {{"index", request.shard_index}, {"count", request.shard_count}};
  return j;
}

ScaledStudy load_scaled_study(const StudyRequest& q, bool print_notes) {
  ScaledStudy s;
  s.request = q;
  s.records = load_study_records(q);
  if (print_notes) {
    for (const std::string& note : s.records.notes) std::cerr << "note: " << note << '\n';
  }
  s.plan = build_study_plan(q, s.records);
  study::validate_plan(s.plan);
  s.runs_per_wall = study::run_count(s.plan);
  s.portfolio = q.walls_file.has_value();
  if (s.portfolio) {
    s.walls = read_wall_portfolio(*q.walls_file, q.wall.wall.g_mps2, q.analysis, q.restitutions);
    if (s.total() > kMaxPortfolioRuns || s.total() / s.walls.size() != s.runs_per_wall) {
      throw UsageError(std::to_string(s.walls.size()) + " walls x " + std::to_string(s.runs_per_wall) +
                       " analyses are more than the " + std::to_string(kMaxPortfolioRuns) +
                       " one study may take: split the portfolio (--walls) into several studies");
    }
  } else {
    if (s.runs_per_wall > kMaxStudyRuns) {
      throw UsageError(std::to_string(s.runs_per_wall) + " analyses are more than the " +
                       std::to_string(kMaxStudyRuns) +
                       " a study may take: use fewer records (--sets) or levels (--pga)");
    }
    PortfolioWall w;
    w.wall = s.plan.wall;
    w.capacities = static_capacities(s.plan.wall);
    s.walls.push_back(w);
  }
  s.plan_description = plan_json(s.plan);
  if (s.portfolio) {
    nlohmann::ordered_json walls = nlohmann::ordered_json::array();
    for (const PortfolioWall& w : s.walls) {
      nlohmann::ordered_json entry;
      entry["id"] = w.id;
      entry["wall"] = wall_parameters_json(w.wall);
      walls.push_back(std::move(entry));
    }
    s.plan_description.erase("wall");  // each wall's is in "walls"
    s.plan_description["walls"] = std::move(walls);
  }
  s.results.assign(s.walls.size(), std::vector<study::RunResult>(s.runs_per_wall));
  return s;
}

void set_wall(ScaledStudy& s, std::size_t wall) { s.plan.wall = s.walls[wall].wall; }

std::size_t prepare_scaled_directory(ScaledStudy& s) {
  const StudyRequest& q = s.request;
  prepare_study_directory(q);
  if (q.force) {
    for (const char* name : {kWallsSummaryName, kWallsFigureName, kShardStateName}) {
      remove_if_present(study_file(q, name));
    }
  }
  if (!q.resume) return 0;
  check_same_plan(q, s.state_plan());
  const std::string runs = study_file(q, kRunsCsvName);
  std::error_code ec;
  if (!fs::exists(runs, ec)) {
    std::cerr << "note: --resume: " << runs << " does not exist: no analysis was finished, running them all\n";
    return 0;
  }
  const std::string why = s.sharded() ? "the run belongs to another shard than " +
                                            std::to_string(q.shard_index) + "/" + std::to_string(q.shard_count)
                                      : std::string();
  return read_scaled_runs(s, runs, [&s](std::size_t g) { return s.in_shard(g); }, why);
}

std::vector<std::size_t> runs_to_do(const ScaledStudy& s) {
  std::vector<std::size_t> todo;
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    for (std::size_t i = 0; i < s.runs_per_wall; ++i) {
      const std::size_t g = w * s.runs_per_wall + i;
      if (s.in_shard(g) && !s.results[w][i].done) todo.push_back(g);
    }
  }
  return todo;
}

std::size_t runs_done(const ScaledStudy& s) {
  std::size_t done = 0;
  for (const std::vector<study::RunResult>& wall : s.results) {
    for (const study::RunResult& r : wall) done += r.done ? 1 : 0;
  }
  return done;
}

std::size_t runs_in_shard(const ScaledStudy& s) {
  if (!s.sharded()) return s.total();
  const std::size_t n = s.request.shard_count, k = s.request.shard_index - 1;
  return s.total() > k ? (s.total() - k + n - 1) / n : 0;
}

void run_wall_chunk(const study::StudyPlan& plan, std::size_t runs_per_wall, std::size_t wall,
                    const std::vector<std::size_t>& indices, std::vector<study::RunResult>& out, std::size_t jobs,
                    const std::function<void()>& one_done, const std::atomic<bool>* cancel) {
  // run_study runs the runs not marked done: every other run of the wall is marked done for the call.
  std::vector<study::RunResult> scratch(runs_per_wall);
  for (study::RunResult& r : scratch) r.done = true;
  for (const std::size_t g : indices) scratch[g - wall * runs_per_wall].done = false;
  study::run_study(
      plan, scratch, jobs, [&one_done](std::size_t, std::size_t) { if (one_done) one_done(); }, cancel);
  out.resize(indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k) out[k] = std::move(scratch[indices[k] - wall * runs_per_wall]);
}

void run_scaled_local(ScaledStudy& s, const std::vector<std::size_t>& todo, std::size_t jobs,
                      const std::function<void(std::size_t)>& progress, const std::atomic<bool>* cancel,
                      const std::function<void()>& between_chunks) {
  std::size_t done = 0;
  std::vector<study::RunResult> out;
  for (std::size_t begin = 0; begin < todo.size();) {
    if (begin > 0 && between_chunks) between_chunks();
    const std::size_t wall = todo[begin] / s.runs_per_wall;
    std::size_t end = begin;
    std::size_t wall_end = begin;
    while (wall_end < todo.size() && todo[wall_end] / s.runs_per_wall == wall) ++wall_end;
    // A sixteenth of the wall's runs (at least 4 per thread, at most kLocalChunkRuns): chunks long enough that
    // starting the threads costs nothing, short enough for checkpoints within one wall's study.
    const std::size_t chunk =
        std::max<std::size_t>(4 * std::max<std::size_t>(jobs, 1), std::min(kLocalChunkRuns, (wall_end - begin) / 16));
    while (end < wall_end && end - begin < chunk) ++end;
    const std::vector<std::size_t> indices(todo.begin() + static_cast<std::ptrdiff_t>(begin),
                                           todo.begin() + static_cast<std::ptrdiff_t>(end));
    set_wall(s, wall);
    run_wall_chunk(s.plan, s.runs_per_wall, wall, indices, out, jobs,
                   [&] {
                     ++done;
                     if (progress) progress(done);
                   },
                   cancel);
    for (std::size_t k = 0; k < indices.size(); ++k) {
      if (out[k].done) s.results[wall][indices[k] - wall * s.runs_per_wall] = std::move(out[k]);
    }
    if (cancel && cancel->load()) return;
    begin = end;
  }
}

void write_scaled_runs(ScaledStudy& s) {
  const StudyRequest& q = s.request;
  if (!s.portfolio) {
    set_wall(s, 0);
    write_study_file(study_file(q, kRunsCsvName), [&](std::ostream& out) { write_runs_csv(out, s.plan, s.results[0]); });
    return;
  }
  write_study_file(study_file(q, kRunsCsvName), [&](std::ostream& out) {
    out << "wall," << runs_csv_header(s.plan) << '\n';
    std::ostringstream rows;
    std::string line;
    for (std::size_t w = 0; w < s.walls.size(); ++w) {
      set_wall(s, w);
      rows.str(std::string());
      rows.clear();
      write_runs_csv(rows, s.plan, s.results[w]);
      std::istringstream in(rows.str());
      std::getline(in, line);  // the header, written once above
      while (std::getline(in, line)) out << s.walls[w].id << ',' << line << '\n';
    }
  });
}

std::size_t read_scaled_runs(ScaledStudy& s, const std::string& path, const std::function<bool(std::size_t)>& accept,
                             const std::string& why_refused) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("cannot open " + path + system_reason());
  const std::string expected_header = (s.portfolio ? "wall," : "") + runs_csv_header(s.plan);
  std::string line;
  if (!std::getline(in, line) || line != expected_header) {
    throw UsageError(path + ":1: expected the header " + expected_header + " (got " + options::quoted(line) +
                     "): the file belongs to another study");
  }
  std::map<std::string, std::size_t> wall_of;
  for (std::size_t w = 0; w < s.walls.size(); ++w) wall_of[s.walls[w].id] = w;
  std::size_t read = 0;
  std::vector<std::string> fields;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(number);
    if (!split_runs_csv_line(line, fields) || fields.empty()) {
      throw UsageError(where + ": expected comma-separated fields (" + expected_header + ")");
    }
    std::size_t wall = 0;
    if (s.portfolio) {
      const auto it = wall_of.find(fields.front());
      if (it == wall_of.end()) {
        throw UsageError(where + ": wall " + options::quoted(fields.front()) + " is not in " + *s.request.walls_file);
      }
      wall = it->second;
      fields.erase(fields.begin());
    }
    // The run column (the eleventh) first: a run of another shard is named as such, not as a repeat.
    if (fields.size() > 10) {
      const std::optional<std::uint64_t> index = whole_number(fields[10], 0, s.runs_per_wall - 1);
      if (index && !accept(wall * s.runs_per_wall + *index)) {
        throw UsageError(where + ": run " + fields[10] + ": " + why_refused);
      }
    }
    set_wall(s, wall);
    const std::size_t index = read_runs_csv_row(where, fields, s.plan, s.results[wall]);
    if (!accept(wall * s.runs_per_wall + index)) throw UsageError(where + ": run " + std::to_string(index) + ": " + why_refused);
    ++read;
  }
  if (in.bad()) throw UsageError("reading " + path + " failed");
  return read;
}

void write_scaled_state_running(const ScaledStudy& s) {
  write_study_state(s.request, s.state_plan(), StudyState::running, runs_done(s), runs_in_shard(s));
  if (s.sharded()) write_shard_state(s, "running");
}

double checkpoint_interval_s() {
  const char* text = std::getenv("ROCKWATCH_STUDY_CHECKPOINT_S");
  if (text == nullptr || *text == '\0') return kCheckpointInterval_s;
  try {
    const double value = parse_finite_number("ROCKWATCH_STUDY_CHECKPOINT_S", text);
    if (value >= 0.0) return value;
  } catch (const UsageError&) {
  }
  throw UsageError("ROCKWATCH_STUDY_CHECKPOINT_S must be a number of seconds >= 0 (got " + options::quoted(text) + ")");
}

void write_scaled_checkpoint(ScaledStudy& s) {
  write_scaled_runs(s);
  write_scaled_state_running(s);
}

int finish_scaled_study(ScaledStudy& s, int signal_number) {
  const StudyRequest& q = s.request;
  const std::size_t done = runs_done(s), total = runs_in_shard(s);
  if (done < total) {
    write_scaled_runs(s);
    write_study_state(q, s.state_plan(), StudyState::interrupted, done, total);
    if (s.sharded()) write_shard_state(s, "interrupted");
    std::cout.flush();
    std::cerr << kScaledErrors.prefix << "interrupted by " << (signal_number == SIGTERM ? "SIGTERM" : "SIGINT")
              << ": " << done << " of " << total << " analyses done, written to " << study_file(q, kRunsCsvName)
              << "\nresume with" << (q.mpi ? " (under mpirun, with any number of ranks)" : "") << ":\n  "
              << (q.mpi ? "mpirun -np N " : "") << resume_command(q) << '\n';
    return kExitInterrupted;
  }
  if (s.sharded()) {
    write_scaled_runs(s);
    write_study_state(q, s.state_plan(), StudyState::complete, done, total);
    write_shard_state(s, "complete");
    std::cout << "rockwatch study: shard " << q.shard_index << " of " << q.shard_count << ": " << done << " of "
              << s.total() << " analyses, written to " << study_file(q, kRunsCsvName)
              << "\nmerge the shards with:\n  rockwatch study merge --out DIR SHARD_DIR...\n";
    return finish_stdout(kScaledErrors);
  }
  return s.portfolio ? finish_portfolio(s) : finish_one_wall(s);
}

int run_scaled_study(const StudyRequest& q) {
  ScaledStudy s = load_scaled_study(q);
  const std::size_t resumed = prepare_scaled_directory(s);
  const std::vector<std::size_t> todo = runs_to_do(s);
  const std::size_t in_shard = runs_in_shard(s);
  if (q.resume) {
    std::cerr << "study: resuming: " << resumed << " of " << in_shard << " analyses done, running the other "
              << todo.size() << '\n';
  }
  if (s.portfolio || s.sharded()) {
    std::cerr << "study: " << in_shard << " analyses";
    if (s.portfolio) std::cerr << " (" << s.walls.size() << " walls x " << s.runs_per_wall << ")";
    if (s.sharded()) std::cerr << ", shard " << q.shard_index << " of " << q.shard_count << " (" << s.total() << " in all)";
    std::cerr << '\n';
  }
  write_scaled_state_running(s);
  const double interval_s = checkpoint_interval_s();
  auto last_checkpoint = std::chrono::steady_clock::now();
  int signal_number = 0;
  {
    const SignalInterrupt interrupt;
    StudyProgress progress(std::cerr, stderr_is_terminal(), resumed, in_shard, interrupt.flag());
    run_scaled_local(
        s, todo, q.jobs, [&](std::size_t done) { progress.report(done, todo.size()); }, interrupt.flag(), [&] {
          // A checkpoint now and then, so even SIGKILL (a batch job over its time) loses at most an interval.
          const auto now = std::chrono::steady_clock::now();
          if (std::chrono::duration<double>(now - last_checkpoint).count() < interval_s) return;
          write_scaled_checkpoint(s);
          last_checkpoint = now;
        });
    progress.finish();
    signal_number = interrupt.signal_number();
  }
  return finish_scaled_study(s, signal_number);
}

}  // namespace rockwatch::cli
