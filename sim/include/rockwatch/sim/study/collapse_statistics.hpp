// Statistics of one study case (SPEC §6, paper Table 3), from its runs: minimum PGA that collapsed, survival rate
// per PGA, the paper's least-squares normal fit to the collapse fraction, a maximum-likelihood lognormal fragility
// with bootstrap confidence intervals, the probability of collapse at the static code capacities, and
// "resurrections". Pure functions; throw StatisticsError for empty or inconsistent input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

namespace rockwatch::sim::study {

class StatisticsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One analysis of the case: which record, at which PGA, and the verdict.
struct RunOutcome {
  std::size_t record_index = 0;
  double pga_g = 0.0;
  bool collapsed = false;
};

struct SurvivalPoint {
  double pga_g = 0.0;
  std::size_t runs = 0;
  std::size_t collapsed = 0;
  double survival_rate = 0.0;  // (runs − collapsed) / runs
};

// The paper's fit: P(collapse | a) = Φ((a − mean)/std), least squares on the collapse fractions per PGA level.
// ok = false (and the other fields 0) when no finite std > 0 fits better than the model's limits: a step (std → 0:
// all fractions 0 or all 1, a single level, 0…0 then 1…1 with at most one level between) or a constant
// (std → ∞: equal fractions, or fractions falling with PGA).
struct NormalFit {
  bool ok = false;              // false when the data cannot determine it (e.g. no or only collapses)
  double mean_g = 0.0;
  double std_g = 0.0;
  double sum_squared_residuals = 0.0;
};

// P(collapse | a) = Φ(ln(a/median)/beta), maximum likelihood over the individual runs (binomial), with 90 %
// confidence intervals from a bootstrap over records (resampling whole records with all their PGA levels).
// ok = false (fields 0, no bootstrap) when the maximum does not exist: no collapses, only collapses, collapses and
// survivals separated by PGA (beta → 0), or collapse more frequent at lower PGA (beta → ∞). The intervals are the
// 5th and 95th percentiles over the resamples with a fit (the others are skipped); they stay 0 when there are none.
struct LognormalFit {
  bool ok = false;
  double median_g = 0.0;
  double beta = 0.0;
  double median_ci90_low_g = 0.0, median_ci90_high_g = 0.0;
  double beta_ci90_low = 0.0, beta_ci90_high = 0.0;
  std::size_t bootstrap_samples = 0;  // resamples whose fit converged
};

struct BootstrapOptions {
  std::size_t samples = 1000;
  std::uint64_t seed = 1;  // the statistics are reproducible
};

// Probability of collapse at a capacity (a static check's allowable PGA) by the two fits and empirically
// (collapse fraction interpolated linearly between the two PGA levels around the capacity; nullopt outside the
// levels' range).
struct CollapseProbability {
  std::optional<double> normal_fit;
  std::optional<double> lognormal_fit;
  std::optional<double> empirical;
};

struct CaseStatistics {
  std::size_t n_runs = 0;
  std::optional<double> min_pga_collapse_g;  // smallest PGA with a collapse; nullopt when nothing collapsed
  std::vector<SurvivalPoint> survival;       // per PGA level, ascending
  NormalFit normal;
  LognormalFit lognormal;
  CollapseProbability at_ntc2008;
  CollapseProbability at_nzsee2016;
  // Runs that survive although the same record collapsed at a lower PGA (the paper observed such records).
  std::size_t resurrections = 0;
};

// PGAs within 1e-9 g of a level's smallest PGA are that level. The fits and collapse_probability read the collapse
// fraction as 1 − survival_rate (the counts are not used), and need levels ascending by more than 1e-9 g.
std::vector<SurvivalPoint> survival_by_pga(const std::vector<RunOutcome>& runs);
NormalFit fit_normal_least_squares(const std::vector<SurvivalPoint>& survival);
LognormalFit fit_lognormal_mle(const std::vector<RunOutcome>& runs, const BootstrapOptions& bootstrap);
CollapseProbability collapse_probability(const std::vector<SurvivalPoint>& survival, const NormalFit& normal,
                                         const LognormalFit& lognormal, double capacity_g);
std::size_t count_resurrections(const std::vector<RunOutcome>& runs);

CaseStatistics case_statistics(const std::vector<RunOutcome>& runs, double ntc2008_capacity_g,
                               double nzsee2016_capacity_g, const BootstrapOptions& bootstrap = {});

}  // namespace rockwatch::sim::study
