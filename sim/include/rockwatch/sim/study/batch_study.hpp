// The collapse-probability study's batch engine (SPEC §6, paper §3 / Table 3): every (vertical setting,
// restitution, record, PGA level) combination of a plan analysed with the verified engine (sim::analyse), on
// `jobs` threads, each result stored at its run index so the output is the same whatever the thread count.
//
// Run order (the run index), outermost first: vertical setting, restitution case, record, PGA level:
//   index = ((v · n_r + r) · n_records + record) · n_pga + pga
// A record is scaled so its peak |ü| equals the PGA level (times g of the wall), its vertical partner by the
// same factor (as `rockwatch simulate --scale-pga` does).
//
// No per-run heap churn: each worker owns one scaled-input buffer, sized once, and analyses keep no history,
// impact list or alarm transitions (keep_history = false, max_impacts_kept = 0, max_alarm_transitions_kept = 0).
//
// Arithmetic: the plan's engine (AnalysisOptions::arithmetic) gives each run's results. With fixed point, every run
// is also analysed by the double engine on the same input (RunResult::reference): the double verdict is the verdict
// of record, against which the fixed engine and its alarm are judged; the --dt-check half-step run is then also
// the double engine's (it tells whether the double verdict itself is sensitive to the step).
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::sim::study {

// One horizontal record and its optional vertical partner, on one time grid, as read (not scaled).
struct StudyRecord {
  std::string name;               // what reports call it, e.g. "set03" or a file name
  std::string component;          // "X", "Y" for suite records; "" for files
  double dt_s = 0.0;              // sample interval [s]
  std::vector<double> ug_mps2;    // horizontal out-of-plane ü [m/s²]
  std::vector<double> vg_mps2;    // vertical partner v̈ [m/s², up +], same length; empty when none
  double peak_ug_mps2 = 0.0;      // max |ü| (the base of the PGA scaling) [m/s²]
};

// A restitution case and the label reports use for it ("ana", "exp", "impulse" or the number).
struct RestitutionCase {
  core::Restitution restitution;
  std::string label;
};

struct StudyPlan {
  core::WallParameters wall = core::paper_wall();
  std::vector<StudyRecord> records;
  std::vector<double> pga_g;                  // PGA levels [g], ascending
  std::vector<RestitutionCase> restitutions;  // e.g. ana, exp
  std::vector<bool> vertical;                 // false = horizontal only, true = with the vertical partner
  AnalysisOptions analysis;                   // arithmetic, model, kappa, max step, alarm (restitution, history,
                                              // impacts and transitions kept are set per run)
  bool dt_check = false;                      // also run every analysis on the double engine at the reference step
                                              // (dt_check_step_s)
};

struct RunKey {
  std::size_t vertical_index = 0;
  std::size_t restitution_index = 0;
  std::size_t record_index = 0;
  std::size_t pga_index = 0;
};

std::size_t run_count(const StudyPlan& plan);
RunKey run_key(const StudyPlan& plan, std::size_t index);
std::size_t run_index(const StudyPlan& plan, const RunKey& key);

// The double engine's results for a run of a fixed-point study.
struct DoubleReference {
  bool collapsed = false;                    // AnalysisResult::verdict_collapse()
  std::optional<double> t_collapse_s;        // [s]
  double max_abs_x_m = 0.0;                  // [m]
  std::optional<double> t_first_imminent_s;  // with evaluate_alarm [s]
};

struct RunResult {
  bool done = false;                    // false: not run yet (a resumed study runs only these)
  bool collapsed = false;               // AnalysisResult::verdict_collapse() of the plan's engine
  std::optional<double> t_collapse_s;   // [s]
  std::optional<double> t_exceed_s;     // [s]
  double max_abs_x_m = 0.0;             // [m]
  int n_impacts = 0;
  std::optional<double> t_first_imminent_s;  // with evaluate_alarm: first step end at IMMINENT or above [s]
  // Fixed point with evaluate_alarm: as the monitor publishes it (AlarmSummary::published): the first IMMINENT's
  // publication [s], the most samples a sample waited, samples shed, calls that worked beyond the budget (overruns)
  // and the most work one call did [work units].
  std::optional<double> t_first_imminent_published_s;
  std::uint32_t imminent_late_samples = 0;  // samples the first IMMINENT waited to be published
  std::uint32_t max_late_samples = 0;
  std::uint32_t shed_samples = 0;
  std::uint32_t overrun_calls = 0;
  std::int32_t max_call_units = 0;
  bool saturated = false;               // fixed point: a quantity reached its range limit
  std::optional<DoubleReference> reference;  // fixed point: the double engine on the same input
  std::optional<bool> collapsed_reference;      // with dt_check: the double verdict at the reference step
  std::optional<double> max_abs_x_reference_m;  // with dt_check: the double max |x| at the reference step [m]
  std::string error;                    // non-empty when the analysis refused the input (e.g. G ≤ 0); no verdict
};

// The verdict of record of a run: the double engine's (the reference's in a fixed-point study) and its time.
inline bool double_collapsed(const RunResult& r) { return r.reference ? r.reference->collapsed : r.collapsed; }
inline std::optional<double> double_t_collapse_s(const RunResult& r) {
  return r.reference ? r.reference->t_collapse_s : r.t_collapse_s;
}

// The integration step of a record in the plan, as sim::analyse chooses it: the record's dt divided into the fewest
// equal sub-steps of at most the plan's max step [s].
double integration_step_s(const StudyPlan& plan, const StudyRecord& record);

// The --dt-check reference's max step: the finer of half the plan's and 0.5 ms (the converged step of the figures in
// docs/BENCHMARKS.md, "Sub-steps": at 0.5 ms the survivors' max |x| changes by less than 0.1 % in the median when the
// step is halved) [s].
double dt_check_step_s(const StudyPlan& plan);

// Throws AnalysisError for an inconsistent plan (no records/levels/cases, a record without samples or peak,
// vertical = true for a record without a partner, a vertical of another length, a PGA level ≤ 0, invalid alarm
// settings, fixed point with the full model).
void validate_plan(const StudyPlan& plan);

// Called after each finished run with (runs done, runs in this call), from the worker threads, serialised.
using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

// Runs every run whose results[index].done is false; `results` is resized to run_count(plan) if empty (and must
// otherwise have that size). jobs = 0 means all hardware threads. Stops early, leaving unfinished runs not done,
// when *cancel becomes true. Results do not depend on `jobs`.
void run_study(const StudyPlan& plan, std::vector<RunResult>& results, std::size_t jobs,
               const ProgressFn& progress = {}, const std::atomic<bool>* cancel = nullptr);

}  // namespace rockwatch::sim::study
