#include "common/records_in/align.hpp"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace rockwatch::cli {

namespace {

void check_grid(const TimeGrid& grid, const char* which) {
  if (!std::isfinite(grid.t0_s) || !std::isfinite(grid.dt_s) || !(grid.dt_s > 0.0)) {
    throw std::invalid_argument(std::string("resample_linear: ") + which + " grid needs a finite t0 and dt > 0");
  }
}

}  // namespace

std::vector<double> resample_linear(const std::vector<double>& values, const TimeGrid& source, const TimeGrid& target) {
  check_grid(source, "source");
  check_grid(target, "target");
  std::vector<double> out(target.count, 0.0);
  if (values.empty()) return out;

  // Position in source samples as offset + k·ratio: when the grids coincide, offset is 0 and ratio 1 exactly, so
  // every position is an exact integer (t0 + k·dt − t0 divided by dt is not).
  const double offset = (target.t0_s - source.t0_s) / source.dt_s;
  const double ratio = target.dt_s / source.dt_s;
  const auto last = static_cast<double>(values.size() - 1);
  constexpr double kSnap = 1e-9;  // of a source step: rounding in t0 and dt, far below any physical time

  for (std::size_t k = 0; k < target.count; ++k) {
    double position = offset + static_cast<double>(k) * ratio;
    const double nearest = std::round(position);
    if (std::fabs(position - nearest) <= kSnap) position = nearest;
    if (position < 0.0 || position > last) continue;
    const double floor_position = std::floor(position);
    const auto i = static_cast<std::size_t>(floor_position);
    const double fraction = position - floor_position;
    out[k] = fraction == 0.0 ? values[i] : values[i] + (values[i + 1] - values[i]) * fraction;
  }
  return out;
}

}  // namespace rockwatch::cli
