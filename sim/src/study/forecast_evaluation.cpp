#include "rockwatch/sim/study/forecast_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rockwatch/core/model.hpp"
#include "rockwatch/sim/study/parallel_runs.hpp"

namespace rockwatch::sim::study {

namespace {

// The restitution cases × records × levels of the horizontal-only setting (the members drive no v̈, SPEC §10).
bool has_horizontal_only(const StudyPlan& plan) {
  return std::find(plan.vertical.begin(), plan.vertical.end(), false) != plan.vertical.end();
}

class ForecastWorker {
 public:
  ForecastWorker(const StudyPlan& plan, const ForecastEvaluationPlan& evaluation, std::size_t longest)
      : plan_(plan), evaluation_(evaluation) {
    motion_.ug_mps2.reserve(longest);
  }

  ForecastRunResult run_one(std::size_t index) {
    const ForecastRunKey key = forecast_run_key(plan_, index);
    const StudyRecord& rec = plan_.records[key.record_index];
    const double factor = plan_.pga_g[key.pga_index] * plan_.wall.g_mps2 / rec.peak_ug_mps2;
    const std::size_t n = rec.ug_mps2.size();
    motion_.dt_s = rec.dt_s;
    motion_.ug_mps2.resize(n);
    for (std::size_t i = 0; i < n; ++i) motion_.ug_mps2[i] = rec.ug_mps2[i] * factor;
    motion_.vg_mps2.clear();

    ForecastRunResult out;
    out.done = true;
    try {
      AnalysisOptions o = plan_.analysis;
      o.arithmetic = Arithmetic::double_precision;  // the verdict of record, and the forecaster's arithmetic
      o.restitution = plan_.restitutions[key.restitution_index].restitution;
      o.keep_history = true;
      o.evaluate_alarm = true;
      o.max_impacts_kept = 0;
      o.max_alarm_transitions_kept = 0;
      const AnalysisResult result = analyse(plan_.wall, motion_, o);
      out.collapsed = result.verdict_collapse();
      out.t_collapse_s = result.t_collapse_s;
      out.t_first_imminent_s = result.alarm.t_first_imminent_s;
      forecast_run(result, out);
    } catch (const AnalysisError& e) {
      out = ForecastRunResult{};
      out.done = true;
      out.error = e.what();
    }
    return out;
  }

 private:
  // The forecasts of one run, as `rockwatch simulate --forecast-*` makes them (simulate_forecast.cpp): every every_s
  // while the wall moves, up to its collapse or the end of its history; the ground fitted to the record as run (zero
  // after its end).
  void forecast_run(const AnalysisResult& result, ForecastRunResult& out) {
    const std::vector<HistoryRow>& h = result.history;
    if (h.empty()) return;
    EnsembleForecaster forecaster(plan_.wall, plan_.analysis.model, result.r, plan_.analysis.kappa,
                                  evaluation_.settings);
    const core::StepperSetup<double>& su = forecaster.setup();
    const double g = plan_.wall.g_mps2;
    const double barrier[2] = {core::energy_barrier_jpm(su.model, core::Side::negative, g),
                               core::energy_barrier_jpm(su.model, core::Side::positive, g)};
    const core::Coefficients<double> free_k[2] = {core::evaluate(su.model, core::Side::negative, 0.0, g),
                                                  core::evaluate(su.model, core::Side::positive, 0.0, g)};
    energy_.resize(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) {
      const int s = h[i].side > 0 ? core::side_index(core::Side::positive) : core::side_index(core::Side::negative);
      energy_[i] = core::mechanical_energy(free_k[s], h[i].x_m, h[i].xd_mps) / barrier[s];
    }
    const double dt = motion_.dt_s;
    const double t_last = h.back().t_s;
    const auto n_ext = static_cast<std::size_t>(std::floor(t_last / dt + 1e-9)) + 1;
    ug_.assign(std::max<std::size_t>(n_ext, 2), 0.0);
    for (std::size_t i = 0; i < ug_.size() && i < motion_.ug_mps2.size(); ++i) {
      if (double(i) * dt <= result.t_end_s + 1e-9) ug_[i] = motion_.ug_mps2[i];
    }
    const double horizon = evaluation_.settings.horizon_s;
    const double t_stop = result.t_collapse_s ? *result.t_collapse_s : t_last;
    std::size_t row = 0;
    for (long k = 0;; ++k) {
      const double t = std::round(double(k) * evaluation_.every_s * 1e9) / 1e9;
      if (t > t_stop + 1e-9 || (result.t_collapse_s && t >= *result.t_collapse_s)) break;
      while (row + 1 < h.size() && h[row + 1].t_s <= t + 1e-9) ++row;
      const HistoryRow& s = h[row];
      ForecastState st;
      st.moving = !(s.x_m == 0.0 && s.xd_mps == 0.0);
      if (!st.moving) {
        ++out.at_rest;
        continue;
      }
      st.x_m = s.x_m;
      st.xd_mps = s.xd_mps;
      st.ug_now_mps2 = s.ug_mps2;
      const std::size_t n = std::min(ug_.size(), static_cast<std::size_t>(std::floor(s.t_s / dt + 1e-9)) + 1);
      const ForecastResult f = forecaster.forecast(st, ug_.data(), std::max<std::size_t>(n, 2), dt);
      ForecastPoint p;
      p.t_s = t;
      p.p_collapse = f.p_collapse;
      p.p_collapse_se = f.p_collapse_se;
      p.q50_max_x_over_x_inst = f.q50_max_x_over_x_inst;
      p.q90_max_x_over_x_inst = f.q90_max_x_over_x_inst;
      double e_max = energy_[row];
      for (std::size_t i = row; i-- > 0 && h[i].t_s >= s.t_s - kForecastEnergyWindow_s - 1e-9;) {
        e_max = std::max(e_max, energy_[i]);
      }
      p.energy_ratio_max = e_max;
      const int side = s.side > 0 ? core::side_index(core::Side::positive) : core::side_index(core::Side::negative);
      p.x_over_x_inst = std::fabs(s.x_m) / su.x_inst_m[side];
      p.imminent = out.t_first_imminent_s && *out.t_first_imminent_s <= t + 1e-9;
      p.outcome = result.t_collapse_s && t < *result.t_collapse_s && *result.t_collapse_s <= t + horizon + 1e-9;
      out.points.push_back(p);
    }
  }

  const StudyPlan& plan_;
  const ForecastEvaluationPlan& evaluation_;
  GroundMotion motion_;
  std::vector<double> energy_, ug_;
};

}  // namespace

std::size_t forecast_run_count(const StudyPlan& plan) {
  if (!has_horizontal_only(plan)) return 0;
  return plan.restitutions.size() * plan.records.size() * plan.pga_g.size();
}

ForecastRunKey forecast_run_key(const StudyPlan& plan, std::size_t index) {
  const std::size_t total = forecast_run_count(plan);
  if (index >= total) {
    throw AnalysisError("forecast run index " + std::to_string(index) + " is out of range (the evaluation has " +
                        std::to_string(total) + " runs)");
  }
  ForecastRunKey key;
  key.pga_index = index % plan.pga_g.size();
  index /= plan.pga_g.size();
  key.record_index = index % plan.records.size();
  key.restitution_index = index / plan.records.size();
  return key;
}

void validate_forecast_evaluation(const ForecastEvaluationPlan& e) {
  if (const char* bad = forecast_settings_error(e.settings)) {
    throw AnalysisError(std::string("forecast evaluation: setting out of range: ") + bad);
  }
  if (!(e.every_s >= kForecastEveryMin_s && e.every_s <= kForecastEveryMax_s)) {
    throw AnalysisError("forecast evaluation: every_s out of range [0.01, 60] s");
  }
}

void run_forecast_evaluation(const StudyPlan& plan, const ForecastEvaluationPlan& evaluation,
                             std::vector<ForecastRunResult>& results, std::size_t jobs, const ProgressFn& progress,
                             const std::atomic<bool>* cancel) {
  validate_plan(plan);
  validate_forecast_evaluation(evaluation);
  if (!has_horizontal_only(plan)) {
    throw AnalysisError("forecast evaluation: the plan has no horizontal-only setting (the members drive no v'')");
  }
  const std::size_t total = forecast_run_count(plan);
  if (results.empty()) results.resize(total);
  if (results.size() != total) {
    throw AnalysisError("forecast results hold " + std::to_string(results.size()) + " runs, the evaluation has " +
                        std::to_string(total));
  }
  std::size_t longest = 0;
  for (const StudyRecord& r : plan.records) longest = std::max(longest, r.ug_mps2.size());
  run_pending(results, jobs, progress, cancel, [&] { return ForecastWorker(plan, evaluation, longest); });
}

}  // namespace rockwatch::sim::study
