// Puts a second record (the vertical component) on the time grid of the first, because the analysis takes both
// inputs on one grid (sim::GroundMotion) while real component files differ in start time, step and length.
#pragma once

#include <cstddef>
#include <vector>

namespace rockwatch::cli {

// Uniform sampling: sample k is at t0_s + k·dt_s.
struct TimeGrid {
  double t0_s = 0.0;
  double dt_s = 0.0;
  std::size_t count = 0;
};

// Values of `values` (sampled at source.t0_s + k·source.dt_s; source.count is ignored, values.size() is used) at
// every time of `target`, by linear interpolation. Zero outside the source's span [t0, t0 + (n−1)·dt]: outside
// its record the ground is taken at rest, as the analysis does after a record ends. Times within 1e-9 of a sample
// spacing of a source sample take that sample exactly, so identical grids copy the values bit for bit.
// Throws std::invalid_argument when a grid's t0 or dt is not finite or a dt is not > 0.
std::vector<double> resample_linear(const std::vector<double>& values, const TimeGrid& source, const TimeGrid& target);

}  // namespace rockwatch::cli
