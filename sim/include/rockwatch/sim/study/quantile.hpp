// Order statistics of a sample: the type-7 quantile (NumPy's and R's default) and the spread a study reports
// (median, 95th percentile, maximum).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace rockwatch::sim::study {

// The p-quantile (p in [0, 1]) of ascending values by linear interpolation between order statistics (Hyndman and
// Fan's type 7, NumPy's and R's default): h = (n − 1) p, x[⌊h⌋] + (h − ⌊h⌋)(x[⌊h⌋+1] − x[⌊h⌋]). None when empty.
std::optional<double> quantile_type7(const std::vector<double>& ascending, double p);

// Median, 95th percentile (type 7) and maximum of a set of values; none when empty.
struct Spread {
  std::size_t n = 0;
  std::optional<double> median, p95, max;
};

// The spread of values in any order.
Spread spread_of(std::vector<double> values);

}  // namespace rockwatch::sim::study
