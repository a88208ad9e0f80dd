#include "rockwatch/sim/study/logistic_fit.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rockwatch::sim::study {

double logistic_probability(const std::vector<double>& w, const double* x) {
  double z = 0.0;
  for (std::size_t a = 0; a < w.size(); ++a) z += w[a] * x[a];
  return 1.0 / (1.0 + std::exp(-std::clamp(z, -50.0, 50.0)));
}

std::vector<double> fit_logistic(const std::vector<double>& x, std::size_t k, const std::vector<std::uint8_t>& y,
                                 const std::vector<std::uint8_t>& use) {
  std::vector<double> w(k, 0.0);
  const std::size_t n = y.size();
  if (k == 0 || x.size() != n * k || (!use.empty() && use.size() != n)) return w;
  const std::size_t columns = k + 1;  // [H | g]
  std::vector<double> g(k), H(k * columns);
  for (int iteration = 0; iteration < 50; ++iteration) {
    std::fill(g.begin(), g.end(), 0.0);
    std::fill(H.begin(), H.end(), 0.0);
    for (std::size_t a = 0; a < k; ++a) H[a * columns + a] = 1e-6;
    for (std::size_t i = 0; i < n; ++i) {
      if (!use.empty() && !use[i]) continue;
      const double* xi = &x[i * k];
      const double p = logistic_probability(w, xi);
      const double yi = y[i] ? 1.0 : 0.0;
      for (std::size_t a = 0; a < k; ++a) {
        g[a] += (yi - p) * xi[a];
        for (std::size_t b = 0; b < k; ++b) H[a * columns + b] += p * (1.0 - p) * xi[a] * xi[b];
      }
    }
    for (std::size_t a = 0; a < k; ++a) H[a * columns + k] = g[a];
    for (std::size_t c = 0; c < k; ++c) {  // Gauss–Jordan with partial pivoting
      std::size_t pivot = c;
      for (std::size_t r = c + 1; r < k; ++r) {
        if (std::fabs(H[r * columns + c]) > std::fabs(H[pivot * columns + c])) pivot = r;
      }
      for (std::size_t j = 0; j <= k; ++j) std::swap(H[c * columns + j], H[pivot * columns + j]);
      if (H[c * columns + c] == 0.0) return w;
      for (std::size_t r = 0; r < k; ++r) {
        if (r == c) continue;
        const double m = H[r * columns + c] / H[c * columns + c];
        for (std::size_t j = c; j <= k; ++j) H[r * columns + j] -= m * H[c * columns + j];
      }
    }
    double largest = 0.0;
    for (std::size_t a = 0; a < k; ++a) {
      const double d = H[a * columns + k] / H[a * columns + a];
      w[a] += d;
      largest = std::max(largest, std::fabs(d));
    }
    if (largest < 1e-10) break;
  }
  return w;
}

}  // namespace rockwatch::sim::study
