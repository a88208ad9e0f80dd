// Logistic regression of an outcome (0/1) on features, as `rockwatch study --forecast` fits its state-only baseline
// (the probability of collapse from max E/E_barrier over 2 s and |x|/x_inst, leave one record out).
// Reachable from Python as rockwatch.study.fit_logistic.
//
// Not sim::fit_logistic_regression (forecast_calibration.hpp), the recalibration's fit: that one is a ridge-penalised
// maximum a posteriori fit (the ridge in the gradient too, up to 100 Newton steps); this one is the maximum-likelihood
// fit whose Newton steps are only damped by the ridge (50 at most), as the baseline's published figures were computed
// (docs/BENCHMARKS.md, "Is it right? `rockwatch study --forecast`"). Keeping both keeps both sets of figures bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rockwatch::sim::study {

// Maximum-likelihood logistic regression by Newton–Raphson (a 1e-6 ridge on the Hessian's diagonal keeps it
// invertible when the classes separate; at most 50 steps, until no weight moves by 1e-10): rows x[i] of k features
// (the constant included by the caller, as a column of ones), outcomes y[i] (0 or 1), only the rows with use[i]
// (every row when use is empty). Returns the k weights; zeros when k = 0 or the sizes disagree.
std::vector<double> fit_logistic(const std::vector<double>& x, std::size_t k, const std::vector<std::uint8_t>& y,
                                 const std::vector<std::uint8_t>& use = {});

// 1 / (1 + exp(−z)), z = Σ w[a] x[a] over the k = w.size() features of the row x (clamped to ±50).
double logistic_probability(const std::vector<double>& w, const double* x);

}  // namespace rockwatch::sim::study
