// Collapse statistics of one study case (SPEC §6, paper Table 3).
//
// Choices (documented here and in the report):
//  * PGA levels: runs are sorted by PGA; a run starts a new level when its PGA exceeds the current level's first
//    (smallest) PGA by more than 1e-9 g; the level's PGA is that first value.
//  * Normal least-squares fit (the paper's): minimises S(μ, σ) = Σ_levels (Φ((a_i − μ)/σ) − f_i)², unweighted,
//    f_i = 1 − survival_rate_i. Levenberg–Marquardt on (μ, ln σ) from two starts — the interpolated 50 % crossing
//    with the 16–84 % half-spread (else range/4), and the best point of a coarse grid — keeping the lower S.
//    The fit is reported (ok) only when its S is below both degenerate limits of the model:
//      σ → 0 (a step, free to take any value at one level): S₀ = min_k Σ_{i<k} f_i² + Σ_{i>k} (1 − f_i)²,
//      σ → ∞ (a constant probability):                     S∞ = Σ (f_i − f̄)².
//    Otherwise the minimum is not attained at a finite σ > 0 and ok = false: all fractions 0 or all 1, a single
//    level, equal fractions everywhere, a step 0…0 (f) 1…1 with at most one intermediate level (σ → 0), or
//    fractions that fall with PGA (σ → ∞).
//  * Lognormal MLE: a probit regression of the runs on x = ln a, z = α + γ (x − x̄) with γ = 1/β and
//    ln θ = x̄ − α/γ. Its log-likelihood is concave in (α, γ), so Newton with backtracking converges from any start
//    whenever the maximum exists; it exists (Albert & Anderson 1984, Silvapulle 1981) iff collapses and survivals
//    overlap: some survival lies at a higher PGA than some collapse and some collapse at a higher PGA than some
//    survival. Without overlap (no collapses, only collapses, or separated / quasi-separated data, where β → 0)
//    ok = false; ok = false also when the maximum has γ ≤ 0 (collapse fraction falling with PGA, β → ∞ under the
//    constraint β > 0).
//  * Bootstrap: records (all their runs together) drawn with replacement by xoshiro256** (synthesis::RandomStream,
//    seeded with BootstrapOptions::seed), each resample refitted from the full-data estimate; resamples without an
//    MLE (by the rule above) are skipped. 90 % intervals are the 5th and 95th percentiles (linear interpolation
//    between order statistics, "type 7") of the converged resamples' medians and betas. With no converged resample
//    (or samples = 0) the interval fields stay 0 and bootstrap_samples = 0. No bootstrap when the full fit fails.
#include "rockwatch/sim/study/collapse_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "normal_distribution.hpp"
#include "rockwatch/sim/synthesis/random_stream.hpp"

namespace rockwatch::sim::study {

namespace {

using detail::log_normal_cdf;
using detail::mills_ratio;
using detail::normal_cdf;
using detail::normal_pdf;

constexpr double kLevelTolerance_g = 1e-9;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

// ---------------------------------------------------------------------------------------------------------------
// Input checks and PGA levels

void check_runs(const char* what, const std::vector<RunOutcome>& runs) {
  if (runs.empty()) throw StatisticsError(std::string(what) + ": no runs");
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const double a = runs[k].pga_g;
    if (!(std::isfinite(a) && a > 0.0)) {
      throw StatisticsError(std::string(what) + ": run " + std::to_string(k) + " has PGA " + number(a) +
                            " g (must be a finite value > 0)");
    }
  }
}

struct Levels {
  std::vector<double> pga_g;           // ascending, more than kLevelTolerance_g apart
  std::vector<std::size_t> run_level;  // the level of each run
};

Levels group_levels(const std::vector<RunOutcome>& runs) {
  std::vector<std::size_t> order(runs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&runs](std::size_t lhs, std::size_t rhs) { return runs[lhs].pga_g < runs[rhs].pga_g; });
  Levels levels;
  levels.run_level.resize(runs.size());
  for (const std::size_t index : order) {
    if (levels.pga_g.empty() || runs[index].pga_g - levels.pga_g.back() > kLevelTolerance_g) {
      levels.pga_g.push_back(runs[index].pga_g);
    }
    levels.run_level[index] = levels.pga_g.size() - 1;
  }
  return levels;
}

struct FractionPoint {
  double a = 0.0;  // PGA [g]
  double f = 0.0;  // collapse fraction
};

std::vector<FractionPoint> fraction_points(const char* what, const std::vector<SurvivalPoint>& survival) {
  if (survival.empty()) throw StatisticsError(std::string(what) + ": no PGA levels");
  std::vector<FractionPoint> points;
  points.reserve(survival.size());
  for (std::size_t i = 0; i < survival.size(); ++i) {
    const SurvivalPoint& p = survival[i];
    if (!std::isfinite(p.pga_g)) {
      throw StatisticsError(std::string(what) + ": level " + std::to_string(i) + " has PGA " + number(p.pga_g));
    }
    if (!(p.survival_rate >= 0.0 && p.survival_rate <= 1.0)) {
      throw StatisticsError(std::string(what) + ": level " + std::to_string(i) + " has survival rate " +
                            number(p.survival_rate) + " (must be in [0, 1])");
    }
    if (i > 0 && !(p.pga_g - survival[i - 1].pga_g > kLevelTolerance_g)) {
      throw StatisticsError(std::string(what) + ": PGA levels must be ascending (level " + std::to_string(i) +
                            " at " + number(p.pga_g) + " g after " + number(survival[i - 1].pga_g) + " g)");
    }
    points.push_back({p.pga_g, 1.0 - p.survival_rate});
  }
  return points;
}

// ---------------------------------------------------------------------------------------------------------------
// Normal least squares

double sum_squares(const std::vector<FractionPoint>& points, double mu, double sigma) {
  double s = 0.0;
  for (const FractionPoint& p : points) {
    const double r = normal_cdf((p.a - mu) / sigma) - p.f;
    s += r * r;
  }
  return s;
}

struct LsqPoint {
  double mu = 0.0;
  double sigma = 0.0;
  double ssr = 0.0;
};

// Levenberg–Marquardt on (μ, s = ln σ), s kept within [s_min, s_max]. Residuals r_i = Φ(z_i) − f_i with
// z_i = (a_i − μ)/σ: ∂r/∂μ = −φ(z)/σ, ∂r/∂s = −φ(z) z.
LsqPoint levenberg_marquardt(const std::vector<FractionPoint>& points, double mu0, double sigma0, double s_min,
                             double s_max) {
  double mu = mu0;
  double s = std::clamp(std::log(sigma0), s_min, s_max);
  double ssr = sum_squares(points, mu, std::exp(s));
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 500; ++iteration) {
    const double sigma = std::exp(s);
    double a11 = 0.0, a12 = 0.0, a22 = 0.0, g1 = 0.0, g2 = 0.0;
    for (const FractionPoint& p : points) {
      const double z = (p.a - mu) / sigma;
      const double r = normal_cdf(z) - p.f;
      const double pdf = normal_pdf(z);
      const double j1 = -pdf / sigma;
      const double j2 = -pdf * z;
      a11 += j1 * j1;
      a12 += j1 * j2;
      a22 += j2 * j2;
      g1 += j1 * r;
      g2 += j2 * r;
    }
    bool improved = false;
    double step_mu = 0.0, step_s = 0.0;
    while (lambda < 1e16) {
      const double d11 = a11 * (1.0 + lambda);
      const double d22 = a22 * (1.0 + lambda);
      const double det = d11 * d22 - a12 * a12;
      if (std::isfinite(det) && det > 0.0) {
        step_mu = -(d22 * g1 - a12 * g2) / det;
        step_s = -(d11 * g2 - a12 * g1) / det;
        const double mu_new = mu + step_mu;
        const double s_new = std::clamp(s + step_s, s_min, s_max);
        const double ssr_new = sum_squares(points, mu_new, std::exp(s_new));
        if (std::isfinite(mu_new) && ssr_new < ssr) {
          step_s = s_new - s;
          mu = mu_new;
          s = s_new;
          ssr = ssr_new;
          lambda = std::max(lambda * 0.1, 1e-12);
          improved = true;
          break;
        }
      }
      lambda *= 10.0;
    }
    if (!improved) break;  // no descent left at this precision
    if (std::fabs(step_mu) <= 1e-13 * std::exp(s) && std::fabs(step_s) <= 1e-13) break;
  }
  return {mu, std::exp(s), ssr};
}

// The PGA where the collapse fraction first reaches `level`, by linear interpolation between levels.
std::optional<double> crossing(const std::vector<FractionPoint>& points, double level) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].f >= level) {
      if (i == 0) return points[0].a;
      const FractionPoint& lo = points[i - 1];
      const FractionPoint& hi = points[i];
      return lo.a + (level - lo.f) / (hi.f - lo.f) * (hi.a - lo.a);
    }
  }
  return std::nullopt;
}

// Infimum of S over the degenerate limits σ → 0 and σ → ∞ (see the file comment).
double degenerate_limit(const std::vector<FractionPoint>& points) {
  const std::size_t n = points.size();
  // σ → 0: Σ_{i<k} f_i² + Σ_{i>k} (1 − f_i)², via prefix and suffix sums.
  std::vector<double> below(n + 1, 0.0), above(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) below[i + 1] = below[i] + points[i].f * points[i].f;
  for (std::size_t i = n; i-- > 0;) above[i] = above[i + 1] + (1.0 - points[i].f) * (1.0 - points[i].f);
  double step_limit = below[0] + above[1];
  for (std::size_t k = 0; k < n; ++k) step_limit = std::min(step_limit, below[k] + above[k + 1]);
  // σ → ∞: the best constant.
  double mean = 0.0;
  for (const FractionPoint& p : points) mean += p.f;
  mean /= static_cast<double>(n);
  double constant_limit = 0.0;
  for (const FractionPoint& p : points) constant_limit += (p.f - mean) * (p.f - mean);
  return std::min(step_limit, constant_limit);
}

// ---------------------------------------------------------------------------------------------------------------
// Lognormal maximum likelihood (probit on ln a)

struct LevelCounts {
  double x = 0.0;          // ln(PGA / 1 g)
  double runs = 0.0;       // n
  double collapsed = 0.0;  // k
};

struct ProbitFit {
  bool converged = false;
  double alpha = 0.0;
  double gamma = 0.0;
};

double log_likelihood(const std::vector<LevelCounts>& data, double centre, double alpha, double gamma) {
  double ll = 0.0;
  for (const LevelCounts& level : data) {
    if (level.runs <= 0.0) continue;
    const double z = alpha + gamma * (level.x - centre);
    const double survived = level.runs - level.collapsed;
    if (level.collapsed > 0.0) ll += level.collapsed * log_normal_cdf(z);
    if (survived > 0.0) ll += survived * log_normal_cdf(-z);
  }
  return ll;
}

// Whether the MLE exists: collapses and survivals overlap in both directions (levels are distinct in x).
bool overlapping(const std::vector<LevelCounts>& data) {
  bool any_collapse = false, any_survival = false;
  double min_collapse = 0.0, max_collapse = 0.0, min_survival = 0.0, max_survival = 0.0;
  for (const LevelCounts& level : data) {
    if (level.collapsed > 0.0) {
      min_collapse = any_collapse ? std::min(min_collapse, level.x) : level.x;
      max_collapse = any_collapse ? std::max(max_collapse, level.x) : level.x;
      any_collapse = true;
    }
    if (level.runs - level.collapsed > 0.0) {
      min_survival = any_survival ? std::min(min_survival, level.x) : level.x;
      max_survival = any_survival ? std::max(max_survival, level.x) : level.x;
      any_survival = true;
    }
  }
  return any_collapse && any_survival && max_survival > min_collapse && max_collapse > min_survival;
}

// Newton's method with backtracking on the concave probit log-likelihood, z = α + γ (x − centre).
ProbitFit fit_probit(const std::vector<LevelCounts>& data, double centre, double alpha, double gamma) {
  double ll = log_likelihood(data, centre, alpha, gamma);
  if (!std::isfinite(ll)) return {};
  int polishing_steps = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    // Gradient g and the negated Hessian h (positive definite) of ℓ in (α, γ).
    double g0 = 0.0, g1 = 0.0, h00 = 0.0, h01 = 0.0, h11 = 0.0;
    for (const LevelCounts& level : data) {
      if (level.runs <= 0.0) continue;
      const double u = level.x - centre;
      const double z = alpha + gamma * u;
      double dz = 0.0, d2z = 0.0;  // dℓ/dz and −d²ℓ/dz²
      if (level.collapsed > 0.0) {
        const double m = mills_ratio(z);
        dz += level.collapsed * m;
        d2z += level.collapsed * m * (z + m);
      }
      const double survived = level.runs - level.collapsed;
      if (survived > 0.0) {
        const double m = mills_ratio(-z);
        dz -= survived * m;
        d2z += survived * m * (m - z);
      }
      g0 += dz;
      g1 += dz * u;
      h00 += d2z;
      h01 += d2z * u;
      h11 += d2z * u * u;
    }
    const double det = h00 * h11 - h01 * h01;
    if (!(std::isfinite(det) && det > 0.0)) return {};
    const double step_alpha = (h11 * g0 - h01 * g1) / det;
    const double step_gamma = (h00 * g1 - h01 * g0) / det;
    const double decrement = g0 * step_alpha + g1 * step_gamma;  // ≈ 2 (ℓ_max − ℓ)
    if (!std::isfinite(decrement)) return {};
    const double scale = 1.0 + std::fabs(ll);
    if (decrement <= 1e-10 * scale) {
      // Within the quadratic region: the predicted gain is near the rounding of ℓ, so ℓ can no longer rank steps.
      // Finish with full Newton steps (each squares the relative error) until the decrement is negligible.
      alpha += step_alpha;
      gamma += step_gamma;
      if (decrement <= 1e-24 * scale || ++polishing_steps >= 3) return {true, alpha, gamma};
      continue;
    }
    bool accepted = false;
    double t = 1.0;
    for (int halving = 0; halving < 60 && !accepted; ++halving, t *= 0.5) {
      const double alpha_new = alpha + t * step_alpha;
      const double gamma_new = gamma + t * step_gamma;
      const double ll_new = log_likelihood(data, centre, alpha_new, gamma_new);
      if (ll_new >= ll + 1e-4 * t * decrement) {
        alpha = alpha_new;
        gamma = gamma_new;
        ll = ll_new;
        accepted = true;
      }
    }
    if (!accepted) return {};
  }
  return {};
}

// Percentile p in [0, 1] with linear interpolation between order statistics ("type 7"); `v` non-empty.
double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double h = p * static_cast<double>(v.size() - 1);
  const double lower = std::floor(h);
  const auto i = static_cast<std::size_t>(lower);
  if (i + 1 >= v.size()) return v.back();
  return v[i] + (h - lower) * (v[i + 1] - v[i]);
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------

std::vector<SurvivalPoint> survival_by_pga(const std::vector<RunOutcome>& runs) {
  check_runs("survival by PGA", runs);
  const Levels levels = group_levels(runs);
  std::vector<SurvivalPoint> survival(levels.pga_g.size());
  for (std::size_t i = 0; i < survival.size(); ++i) survival[i].pga_g = levels.pga_g[i];
  for (std::size_t k = 0; k < runs.size(); ++k) {
    SurvivalPoint& point = survival[levels.run_level[k]];
    ++point.runs;
    if (runs[k].collapsed) ++point.collapsed;
  }
  for (SurvivalPoint& point : survival) {
    point.survival_rate = static_cast<double>(point.runs - point.collapsed) / static_cast<double>(point.runs);
  }
  return survival;
}

NormalFit fit_normal_least_squares(const std::vector<SurvivalPoint>& survival) {
  const std::vector<FractionPoint> points = fraction_points("normal fit", survival);
  NormalFit fit;
  const double limit = degenerate_limit(points);
  if (points.size() < 2 || !(limit > 0.0)) return fit;  // one level, all 0, all 1, equal fractions or a pure step

  const double a_min = points.front().a;
  const double a_max = points.back().a;
  const double range = a_max - a_min;
  double min_spacing = range;
  for (std::size_t i = 1; i < points.size(); ++i) min_spacing = std::min(min_spacing, points[i].a - points[i - 1].a);
  const double s_min = std::log(min_spacing * 1e-6);
  const double s_max = std::log(range * 1e6);

  // Start 1: the 50 % crossing and the 16–84 % half-spread (else range/4).
  const double mu1 = crossing(points, 0.5).value_or(a_max);
  double sigma1 = range / 4.0;
  const std::optional<double> a16 = crossing(points, 0.15865525393145705);
  const std::optional<double> a84 = crossing(points, 0.84134474606854293);
  if (a16 && a84 && *a84 > *a16) sigma1 = 0.5 * (*a84 - *a16);
  const LsqPoint from_crossing = levenberg_marquardt(points, mu1, sigma1, s_min, s_max);

  // Start 2: the best point of a coarse grid, μ over the levels' range widened by half of it on each side, σ
  // log-spaced from a quarter of the smallest spacing to twice the range.
  constexpr int kMuSteps = 40, kSigmaSteps = 30;
  const double sigma_lo = 0.25 * min_spacing, sigma_hi = 2.0 * range;
  LsqPoint grid_best{mu1, sigma1, sum_squares(points, mu1, sigma1)};
  for (int j = 0; j <= kMuSteps; ++j) {
    const double mu = a_min - 0.5 * range + 2.0 * range * static_cast<double>(j) / kMuSteps;
    for (int k = 0; k <= kSigmaSteps; ++k) {
      const double sigma = sigma_lo * std::pow(sigma_hi / sigma_lo, static_cast<double>(k) / kSigmaSteps);
      const double ssr = sum_squares(points, mu, sigma);
      if (ssr < grid_best.ssr) grid_best = {mu, sigma, ssr};
    }
  }
  const LsqPoint from_grid = levenberg_marquardt(points, grid_best.mu, grid_best.sigma, s_min, s_max);

  const LsqPoint& best = from_grid.ssr < from_crossing.ssr ? from_grid : from_crossing;
  // A finite optimum only when it beats the degenerate limits (σ → 0 or ∞) by more than rounding.
  if (!(std::isfinite(best.mu) && std::isfinite(best.sigma) && best.sigma > 0.0)) return fit;
  if (!(best.ssr < limit * (1.0 - 1e-9))) return fit;
  fit.ok = true;
  fit.mean_g = best.mu;
  fit.std_g = best.sigma;
  fit.sum_squared_residuals = best.ssr;
  return fit;
}

LognormalFit fit_lognormal_mle(const std::vector<RunOutcome>& runs, const BootstrapOptions& bootstrap) {
  check_runs("lognormal fit", runs);
  const Levels levels = group_levels(runs);
  const std::size_t n_levels = levels.pga_g.size();

  std::vector<LevelCounts> data(n_levels);
  for (std::size_t i = 0; i < n_levels; ++i) data[i].x = std::log(levels.pga_g[i]);
  double centre = 0.0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    LevelCounts& level = data[levels.run_level[k]];
    level.runs += 1.0;
    if (runs[k].collapsed) level.collapsed += 1.0;
    centre += level.x;
  }
  centre /= static_cast<double>(runs.size());

  LognormalFit fit;
  if (!overlapping(data)) return fit;
  double spread = 0.0;
  for (const LevelCounts& level : data) spread += level.runs * (level.x - centre) * (level.x - centre);
  spread = std::sqrt(spread / static_cast<double>(runs.size()));  // > 0: overlap needs two levels
  const ProbitFit full = fit_probit(data, centre, 0.0, 1.0 / spread);
  if (!full.converged || !(full.gamma > 0.0)) return fit;
  fit.ok = true;
  fit.median_g = std::exp(centre - full.alpha / full.gamma);
  fit.beta = 1.0 / full.gamma;

  if (bootstrap.samples == 0) return fit;
  // Each record's runs as (level, runs, collapsed) triples; records by their index, in ascending order.
  struct RecordLevel {
    std::size_t level = 0;
    double runs = 0.0;
    double collapsed = 0.0;
  };
  std::map<std::size_t, std::map<std::size_t, RecordLevel>> by_record;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    RecordLevel& entry = by_record[runs[k].record_index][levels.run_level[k]];
    entry.level = levels.run_level[k];
    entry.runs += 1.0;
    if (runs[k].collapsed) entry.collapsed += 1.0;
  }
  std::vector<std::vector<RecordLevel>> records;
  records.reserve(by_record.size());
  for (const auto& [record, entries] : by_record) {
    std::vector<RecordLevel>& list = records.emplace_back();
    for (const auto& [level, entry] : entries) list.push_back(entry);
  }
  const std::size_t n_records = records.size();

  synthesis::RandomStream rng(bootstrap.seed);
  std::vector<LevelCounts> resample = data;
  std::vector<double> medians, betas;
  medians.reserve(bootstrap.samples);
  betas.reserve(bootstrap.samples);
  for (std::size_t sample = 0; sample < bootstrap.samples; ++sample) {
    for (LevelCounts& level : resample) level.runs = level.collapsed = 0.0;
    for (std::size_t draw = 0; draw < n_records; ++draw) {
      const auto pick = std::min(n_records - 1, static_cast<std::size_t>(rng.uniform() * static_cast<double>(n_records)));
      for (const RecordLevel& entry : records[pick]) {
        resample[entry.level].runs += entry.runs;
        resample[entry.level].collapsed += entry.collapsed;
      }
    }
    if (!overlapping(resample)) continue;
    const ProbitFit refit = fit_probit(resample, centre, full.alpha, full.gamma);
    if (!refit.converged || !(refit.gamma > 0.0)) continue;
    medians.push_back(std::exp(centre - refit.alpha / refit.gamma));
    betas.push_back(1.0 / refit.gamma);
  }
  fit.bootstrap_samples = medians.size();
  if (medians.empty()) return fit;
  fit.median_ci90_low_g = percentile(medians, 0.05);
  fit.median_ci90_high_g = percentile(medians, 0.95);
  fit.beta_ci90_low = percentile(betas, 0.05);
  fit.beta_ci90_high = percentile(betas, 0.95);
  return fit;
}

CollapseProbability collapse_probability(const std::vector<SurvivalPoint>& survival, const NormalFit& normal,
                                         const LognormalFit& lognormal, double capacity_g) {
  const std::vector<FractionPoint> points = fraction_points("collapse probability", survival);
  if (!std::isfinite(capacity_g)) throw StatisticsError("collapse probability: capacity " + number(capacity_g) + " g");
  CollapseProbability p;
  if (normal.ok) p.normal_fit = normal_cdf((capacity_g - normal.mean_g) / normal.std_g);
  if (lognormal.ok) {
    p.lognormal_fit = capacity_g > 0.0 ? normal_cdf(std::log(capacity_g / lognormal.median_g) / lognormal.beta) : 0.0;
  }
  if (capacity_g < points.front().a - kLevelTolerance_g || capacity_g > points.back().a + kLevelTolerance_g) return p;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (std::fabs(capacity_g - points[i].a) <= kLevelTolerance_g) {
      p.empirical = points[i].f;
      return p;
    }
    if (i + 1 < points.size() && capacity_g < points[i + 1].a) {
      const double w = (capacity_g - points[i].a) / (points[i + 1].a - points[i].a);
      p.empirical = points[i].f + w * (points[i + 1].f - points[i].f);
      return p;
    }
  }
  return p;
}

std::size_t count_resurrections(const std::vector<RunOutcome>& runs) {
  check_runs("resurrections", runs);
  const Levels levels = group_levels(runs);
  std::map<std::size_t, std::size_t> first_collapse_level;  // record → lowest level at which it collapsed
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k].collapsed) continue;
    const auto [it, inserted] = first_collapse_level.emplace(runs[k].record_index, levels.run_level[k]);
    if (!inserted) it->second = std::min(it->second, levels.run_level[k]);
  }
  std::size_t count = 0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (runs[k].collapsed) continue;
    const auto it = first_collapse_level.find(runs[k].record_index);
    if (it != first_collapse_level.end() && levels.run_level[k] > it->second) ++count;
  }
  return count;
}

CaseStatistics case_statistics(const std::vector<RunOutcome>& runs, double ntc2008_capacity_g,
                               double nzsee2016_capacity_g, const BootstrapOptions& bootstrap) {
  check_runs("case statistics", runs);
  if (!std::isfinite(ntc2008_capacity_g) || !std::isfinite(nzsee2016_capacity_g)) {
    throw StatisticsError("case statistics: capacities must be finite (got " + number(ntc2008_capacity_g) + " g, " +
                          number(nzsee2016_capacity_g) + " g)");
  }
  CaseStatistics stats;
  stats.n_runs = runs.size();
  stats.survival = survival_by_pga(runs);
  for (const SurvivalPoint& point : stats.survival) {
    if (point.collapsed > 0) {
      stats.min_pga_collapse_g = point.pga_g;
      break;
    }
  }
  stats.normal = fit_normal_least_squares(stats.survival);
  stats.lognormal = fit_lognormal_mle(runs, bootstrap);
  stats.at_ntc2008 = collapse_probability(stats.survival, stats.normal, stats.lognormal, ntc2008_capacity_g);
  stats.at_nzsee2016 = collapse_probability(stats.survival, stats.normal, stats.lognormal, nzsee2016_capacity_g);
  stats.resurrections = count_resurrections(runs);
  return stats;
}

}  // namespace rockwatch::sim::study
