#include "rockwatch/sim/study/quantile.hpp"

#include <algorithm>
#include <cmath>

namespace rockwatch::sim::study {

std::optional<double> quantile_type7(const std::vector<double>& ascending, double p) {
  if (ascending.empty()) return std::nullopt;
  const double h = static_cast<double>(ascending.size() - 1) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, ascending.size() - 1);
  return ascending[lo] + (h - static_cast<double>(lo)) * (ascending[hi] - ascending[lo]);
}

Spread spread_of(std::vector<double> values) {
  Spread s;
  std::sort(values.begin(), values.end());
  s.n = values.size();
  s.median = quantile_type7(values, 0.5);
  s.p95 = quantile_type7(values, 0.95);
  if (!values.empty()) s.max = values.back();
  return s;
}

}  // namespace rockwatch::sim::study
