#include "rockwatch/sim/study/batch_study.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/sim/study/parallel_runs.hpp"

namespace rockwatch::sim::study {

namespace {

std::string record_text(const StudyPlan& plan, std::size_t i) {
  const StudyRecord& r = plan.records[i];
  std::string text = "record " + std::to_string(i) + " (" + r.name;
  if (!r.component.empty()) text += " " + r.component;
  return text + ")";
}

[[noreturn]] void reject(const std::string& what) { throw AnalysisError("study plan: " + what); }

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// What one worker owns: the scaled input (its vectors reserved once to the longest record, so refilling them
// never allocates) and the options of the current run.
class Worker {
 public:
  Worker(const StudyPlan& plan, std::size_t longest, bool any_vertical) : plan_(plan) {
    motion_.ug_mps2.reserve(longest);
    if (any_vertical) motion_.vg_mps2.reserve(longest);
  }

  RunResult run_one(std::size_t index) {
    const RunKey key = run_key(plan_, index);
    const StudyRecord& rec = plan_.records[key.record_index];
    // As `rockwatch simulate --scale-pga`: one factor, the horizontal to the PGA level, the vertical alike.
    const double factor = plan_.pga_g[key.pga_index] * plan_.wall.g_mps2 / rec.peak_ug_mps2;
    const std::size_t n = rec.ug_mps2.size();
    motion_.dt_s = rec.dt_s;
    motion_.ug_mps2.resize(n);  // within the reserved capacity: no allocation
    for (std::size_t i = 0; i < n; ++i) motion_.ug_mps2[i] = rec.ug_mps2[i] * factor;
    if (plan_.vertical[key.vertical_index]) {
      motion_.vg_mps2.resize(n);
      for (std::size_t i = 0; i < n; ++i) motion_.vg_mps2[i] = rec.vg_mps2[i] * factor;
    } else {
      motion_.vg_mps2.clear();  // keeps the capacity
    }

    AnalysisOptions options = plan_.analysis;
    options.restitution = plan_.restitutions[key.restitution_index].restitution;
    options.keep_history = false;
    options.max_impacts_kept = 0;
    options.max_alarm_transitions_kept = 0;

    RunResult out;
    out.done = true;
    try {
      const AnalysisResult a = analyse(plan_.wall, motion_, options);
      out.collapsed = a.verdict_collapse();
      out.t_collapse_s = a.t_collapse_s;
      out.t_exceed_s = a.t_exceed_s;
      out.max_abs_x_m = a.max_abs_x_m;
      out.n_impacts = a.n_impacts;
      out.t_first_imminent_s = a.alarm.t_first_imminent_s;
      out.t_first_imminent_published_s = a.alarm.published.t_first_imminent_s;
      out.imminent_late_samples = a.alarm.published.imminent_late_calls;
      out.max_late_samples = a.alarm.published.max_late_calls;
      out.shed_samples = a.alarm.published.shed_samples;
      out.overrun_calls = a.alarm.published.overruns;
      out.max_call_units = a.alarm.published.max_call_units;
      out.saturated = a.saturated;
      options.arithmetic = Arithmetic::double_precision;  // the reference and the half-step check: double
      if (plan_.analysis.arithmetic != Arithmetic::double_precision) {
        const AnalysisResult d = analyse(plan_.wall, motion_, options);
        out.reference = DoubleReference{d.verdict_collapse(), d.t_collapse_s, d.max_abs_x_m, d.alarm.t_first_imminent_s};
      }
      if (plan_.dt_check) {
        options.max_step_s = dt_check_step_s(plan_);
        options.evaluate_alarm = false;  // only the verdict and max |x| are kept
        const AnalysisResult reference = analyse(plan_.wall, motion_, options);
        out.collapsed_reference = reference.verdict_collapse();
        out.max_abs_x_reference_m = reference.max_abs_x_m;
      }
    } catch (const AnalysisError& e) {
      out = RunResult{};
      out.done = true;
      out.error = e.what();
    }
    return out;
  }

 private:
  const StudyPlan& plan_;
  GroundMotion motion_;
};

}  // namespace

double integration_step_s(const StudyPlan& plan, const StudyRecord& record) {
  const double n_sub = std::max(1, core::substeps_per_sample(record.dt_s, plan.analysis.max_step_s));
  return record.dt_s / n_sub;
}

double dt_check_step_s(const StudyPlan& plan) { return std::min(plan.analysis.max_step_s / 2.0, 0.0005); }

std::size_t run_count(const StudyPlan& plan) {
  return plan.vertical.size() * plan.restitutions.size() * plan.records.size() * plan.pga_g.size();
}

RunKey run_key(const StudyPlan& plan, std::size_t index) {
  const std::size_t total = run_count(plan);
  if (index >= total) {
    throw AnalysisError("study run index " + std::to_string(index) + " is out of range (the plan has " +
                        std::to_string(total) + " runs)");
  }
  RunKey key;
  key.pga_index = index % plan.pga_g.size();
  index /= plan.pga_g.size();
  key.record_index = index % plan.records.size();
  index /= plan.records.size();
  key.restitution_index = index % plan.restitutions.size();
  key.vertical_index = index / plan.restitutions.size();
  return key;
}

std::size_t run_index(const StudyPlan& plan, const RunKey& key) {
  if (key.vertical_index >= plan.vertical.size() || key.restitution_index >= plan.restitutions.size() ||
      key.record_index >= plan.records.size() || key.pga_index >= plan.pga_g.size()) {
    throw AnalysisError("study run key (vertical " + std::to_string(key.vertical_index) + ", restitution " +
                        std::to_string(key.restitution_index) + ", record " + std::to_string(key.record_index) +
                        ", pga " + std::to_string(key.pga_index) + ") is out of range of the plan");
  }
  return ((key.vertical_index * plan.restitutions.size() + key.restitution_index) * plan.records.size() +
          key.record_index) *
             plan.pga_g.size() +
         key.pga_index;
}

void validate_plan(const StudyPlan& plan) {
  if (plan.records.empty()) reject("no records");
  if (plan.pga_g.empty()) reject("no PGA levels");
  if (plan.restitutions.empty()) reject("no restitution cases");
  if (plan.vertical.empty()) reject("no vertical settings (horizontal only and/or with the vertical)");

  const core::WallCheck wc = core::validate_wall(plan.wall);
  if (!wc.ok()) reject(std::string("wall parameter ") + wc.field + " " + wc.message);
  if (!(std::isfinite(plan.analysis.kappa) && plan.analysis.kappa >= 1.0)) reject("kappa must be a finite number >= 1");
  if (!(std::isfinite(plan.analysis.max_step_s) && plan.analysis.max_step_s > 0.0)) reject("max step must be > 0 s");
  if (plan.analysis.t_end_s && !(std::isfinite(*plan.analysis.t_end_s) && *plan.analysis.t_end_s >= 0.0)) {
    reject("t_end must be >= 0 s");
  }
  if (plan.analysis.evaluate_alarm && !core::alarm_settings_valid(plan.analysis.alarm)) {
    const core::AlarmSettings& a = plan.analysis.alarm;
    reject("alarm settings: lambda_warning " + number_text(a.lambda_warning) + " must be in (0, 1], hold_s " +
           number_text(a.hold_s) + " in [0, 3600] s, energy_margin " + number_text(a.energy_margin) + " in [1, 100]");
  }
  if (plan.analysis.arithmetic == Arithmetic::fixed_point && plan.analysis.model != core::ModelKind::linear) {
    reject("fixed-point arithmetic supports the linear model only");
  }
  for (std::size_t i = 0; i < plan.restitutions.size(); ++i) {
    if (!core::restitution_valid(plan.restitutions[i].restitution)) {
      reject("restitution case " + std::to_string(i) + " (" + plan.restitutions[i].label + "): r must be in [0, 1]");
    }
  }

  for (std::size_t i = 0; i < plan.pga_g.size(); ++i) {
    const double a = plan.pga_g[i];
    if (!(std::isfinite(a) && a > 0.0)) {
      reject("PGA level " + std::to_string(i) + " is " + number_text(a) + " g: levels must be > 0");
    }
    if (i > 0 && !(a > plan.pga_g[i - 1])) {
      reject("PGA levels must be ascending: level " + std::to_string(i) + " (" + number_text(a) +
             " g) does not exceed the one before (" + number_text(plan.pga_g[i - 1]) + " g)");
    }
  }

  const bool any_vertical = std::find(plan.vertical.begin(), plan.vertical.end(), true) != plan.vertical.end();
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    const StudyRecord& r = plan.records[i];
    if (!(std::isfinite(r.dt_s) && r.dt_s > 0.0)) reject(record_text(plan, i) + ": sample interval must be > 0 s");
    if (r.ug_mps2.size() < 2) reject(record_text(plan, i) + ": no samples (at least two are needed)");
    const double finest_step_s = plan.dt_check ? dt_check_step_s(plan) : plan.analysis.max_step_s;
    if (core::substeps_per_sample(r.dt_s, finest_step_s) == 0) {
      reject(record_text(plan, i) + ": max step " + number_text(finest_step_s) + " s" +
             (plan.dt_check ? " (the --dt-check reference)" : "") + " would need more than " +
             std::to_string(core::kMaxSubsteps) + " sub-steps per sample (dt " + number_text(r.dt_s) +
             " s): choose max step >= dt / " + std::to_string(core::kMaxSubsteps));
    }
    if (!(std::isfinite(r.peak_ug_mps2) && r.peak_ug_mps2 > 0.0)) {
      reject(record_text(plan, i) + ": no peak (peak |u''| must be > 0 to scale it to a PGA level)");
    }
    if (!r.vg_mps2.empty() && r.vg_mps2.size() != r.ug_mps2.size()) {
      reject(record_text(plan, i) + ": its vertical has " + std::to_string(r.vg_mps2.size()) +
             " samples, the horizontal " + std::to_string(r.ug_mps2.size()) + " (same time grid required)");
    }
    if (any_vertical && r.vg_mps2.empty()) {
      reject(record_text(plan, i) + ": the plan runs it with its vertical, but it has no vertical partner");
    }
  }
}

void run_study(const StudyPlan& plan, std::vector<RunResult>& results, std::size_t jobs, const ProgressFn& progress,
               const std::atomic<bool>* cancel) {
  validate_plan(plan);
  const std::size_t total = run_count(plan);
  if (results.empty()) results.resize(total);
  if (results.size() != total) {
    throw AnalysisError("study results hold " + std::to_string(results.size()) + " runs, the plan has " +
                        std::to_string(total));
  }

  std::size_t longest = 0;
  for (const StudyRecord& r : plan.records) longest = std::max(longest, r.ug_mps2.size());
  const bool any_vertical = std::find(plan.vertical.begin(), plan.vertical.end(), true) != plan.vertical.end();

  run_pending(results, jobs, progress, cancel, [&] { return Worker(plan, longest, any_vertical); });
}

}  // namespace rockwatch::sim::study
