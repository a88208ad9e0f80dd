// rockwatch.study: the statistics of `rockwatch study` for Python (sim/include/rockwatch/sim/study/: quantile,
// logistic_fit, alarm_scores, forecast_scores). Each function converts its arguments, calls the one the study
// calls and returns its result; nothing is computed here. Errors in the arguments are ValueError naming the argument.
#include "study_module.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "rockwatch/sim/study/alarm_scores.hpp"
#include "rockwatch/sim/study/forecast_scores.hpp"
#include "rockwatch/sim/study/logistic_fit.hpp"
#include "rockwatch/sim/study/quantile.hpp"
#include "study/report/study_summary.hpp"

namespace py = pybind11;

namespace rockwatch::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::vector<double> values_of(const Array& a, const char* name) {
  if (a.ndim() != 1) {
    throw py::value_error(std::string(name) + " must be one-dimensional (got " + std::to_string(a.ndim()) +
                          " dimensions)");
  }
  const double* p = a.data();
  return std::vector<double>(p, p + a.shape(0));
}

// Outcomes as 0/1 bytes: every value must be 0 or 1 (False or True).
std::vector<std::uint8_t> outcomes_of(const Array& a, const char* name) {
  std::vector<std::uint8_t> out;
  for (const double v : values_of(a, name)) {
    if (v != 0.0 && v != 1.0) {
      throw py::value_error(std::string(name) + " must hold 0 or 1 (False or True) only (got " +
                            py::repr(py::float_(v)).cast<std::string>() + ")");
    }
    out.push_back(v == 1.0 ? 1 : 0);
  }
  return out;
}

std::optional<double> time_or_none(double t) { return std::isnan(t) ? std::nullopt : std::optional<double>(t); }

py::array_t<double> numpy_of(const std::vector<double>& values) {
  py::array_t<double> a(static_cast<py::ssize_t>(values.size()));
  double* out = a.mutable_data();
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = values[i];
  return a;
}

std::optional<double> quantile_type7(const Array& values, double p) {
  if (!(p >= 0.0 && p <= 1.0)) throw py::value_error("p must be in [0, 1] (got " + std::to_string(p) + ")");
  std::vector<double> v = values_of(values, "values");
  std::sort(v.begin(), v.end());
  return sim::study::quantile_type7(v, p);
}

py::array_t<double> fit_logistic(const Array& x, const Array& y, const std::optional<Array>& use) {
  if (x.ndim() != 2) {
    throw py::value_error("x must be two-dimensional: one row of features per outcome (got " +
                          std::to_string(x.ndim()) + " dimensions)");
  }
  const auto n = static_cast<std::size_t>(x.shape(0));
  const auto k = static_cast<std::size_t>(x.shape(1));
  const std::vector<std::uint8_t> outcome = outcomes_of(y, "y");
  if (outcome.size() != n) {
    throw py::value_error("y has " + std::to_string(outcome.size()) + " outcomes and x " + std::to_string(n) +
                          " rows: give one outcome per row");
  }
  std::vector<std::uint8_t> rows;
  if (use) {
    rows = outcomes_of(*use, "use");
    if (rows.size() != n) throw py::value_error("use must have one entry per row of x");
  }
  const double* p = x.data();
  const std::vector<double> flat(p, p + n * k);
  std::vector<double> w;
  {
    py::gil_scoped_release release;
    w = sim::study::fit_logistic(flat, k, outcome, rows);
  }
  return numpy_of(w);
}

py::dict alarm_outcome(const Array& collapsed, const Array& t_collapse_s, const Array& t_first_imminent_s) {
  const std::vector<std::uint8_t> c = outcomes_of(collapsed, "collapsed");
  const std::vector<double> tc = values_of(t_collapse_s, "t_collapse_s");
  const std::vector<double> ti = values_of(t_first_imminent_s, "t_first_imminent_s");
  if (tc.size() != c.size() || ti.size() != c.size()) {
    throw py::value_error("collapsed, t_collapse_s and t_first_imminent_s must have one entry per run (got " +
                          std::to_string(c.size()) + ", " + std::to_string(tc.size()) + " and " +
                          std::to_string(ti.size()) + ")");
  }
  std::vector<sim::study::AlarmRun> runs;
  for (std::size_t i = 0; i < c.size(); ++i) runs.push_back({c[i] != 0, time_or_none(tc[i]), time_or_none(ti[i])});
  const sim::study::AlarmOutcome a = sim::study::alarm_outcome(runs);
  // summary.json's "alarm" scores, as the study writes them (shortest round-trip numbers: the same doubles).
  py::dict d = py::module_::import("json").attr("loads")(cli::alarm_score_json(a).dump());
  d["lead_times_s"] = numpy_of(a.lead_times_s);
  return d;
}

py::dict reliability(const Array& p, const Array& outcome) {
  const std::vector<double> probabilities = values_of(p, "p");
  const std::vector<std::uint8_t> o = outcomes_of(outcome, "outcome");
  if (o.size() != probabilities.size()) throw py::value_error("p and outcome must have one entry per forecast");
  std::size_t judged = 0;
  std::optional<double> max_error;
  const std::vector<sim::study::ReliabilityBin> bins = sim::study::reliability_bins(probabilities, o, judged, max_error);
  py::list list;
  for (const sim::study::ReliabilityBin& b : bins) {
    list.append(py::dict(py::arg("lo") = b.lo, py::arg("hi") = b.hi, py::arg("n") = b.n,
                         py::arg("mean_p") = b.mean_p, py::arg("observed") = b.observed));
  }
  py::dict d;
  d["brier"] = probabilities.empty() ? std::optional<double>() : sim::study::brier_score(probabilities, o);
  d["bins"] = list;
  d["bins_judged"] = judged;
  d["calibration_max_error"] = max_error;
  return d;
}

}  // namespace

void add_study_module(py::module_& parent) {
  py::module_ m = parent.def_submodule(
      "study", "The statistics of `rockwatch study` (sim/study): quantiles, the alarm's scores, the forecast "
               "baseline's logistic fit, reliability and Brier scores. See docs/python.md.");
  m.def("quantile_type7", &quantile_type7, py::arg("values"), py::arg("p"),
        "The p-quantile of the values (any order) by linear interpolation between order statistics (Hyndman and "
        "Fan's type 7, numpy.quantile's default), as the study's medians and percentiles; None when empty.");
  m.def("fit_logistic", &fit_logistic, py::arg("x"), py::arg("y"), py::kw_only(), py::arg("use") = py::none(),
        "Maximum-likelihood logistic regression by Newton-Raphson, as `rockwatch study --forecast` fits its baseline: "
        "x one row of k features per outcome (include a column of ones for the constant), y the outcomes (0/1), use "
        "the rows to fit (all when None). Returns the k weights.");
  m.def("alarm_outcome", &alarm_outcome, py::arg("collapsed"), py::arg("t_collapse_s"), py::arg("t_first_imminent_s"),
        "The alarm's scores of `rockwatch study --alarms` over runs: collapsed (0/1 per run), t_collapse_s and "
        "t_first_imminent_s (NaN where none). Returns summary.json's alarm scores (recall, false_alarm_rate, "
        "lead_time_s_median, lead_time_s_p05, lead_time_s_min, counts) and lead_times_s.");
  m.def("reliability", &reliability, py::arg("p"), py::arg("outcome"),
        "The forecast scores of `rockwatch study --forecast` for probabilities p and outcomes (0/1): brier, the "
        "reliability bins (width 0.1; lo, hi, n, mean_p, observed), bins_judged (at least 30 forecasts) and "
        "calibration_max_error.");
}

}  // namespace rockwatch::python
