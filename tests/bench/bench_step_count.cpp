// Runs N stepper steps of the benchmark input and nothing else that depends on N, so that under callgrind
// (callgrind_step.sh) the instruction count per step is the difference of two runs divided by the difference
// of their N: input generation and process start-up cancel.
//   bench_step_count N [rocking_linear|rocking_full|quiet_linear]
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "synthetic_motion.hpp"

namespace core = rockwatch::core;
using rockwatch::bench::kDt;
using rockwatch::bench::kG;

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s N [rocking_linear|rocking_full|quiet_linear]\n", argv[0]);
    return 2;
  }
  errno = 0;
  char* end = nullptr;
  const unsigned long long n_steps = std::strtoull(argv[1], &end, 10);
  if (errno != 0 || end == argv[1] || *end != '\0') {
    std::fprintf(stderr, "N must be a non-negative integer, got '%s'\n", argv[1]);
    return 2;
  }
  const char* variant = argc == 3 ? argv[2] : "rocking_linear";
  // Same inputs as BM_StepperStep in bench_engine.cpp.
  core::ModelKind kind = core::ModelKind::linear;
  double peak_mps2 = 0.2 * kG;
  if (std::strcmp(variant, "rocking_full") == 0) {
    kind = core::ModelKind::full;
  } else if (std::strcmp(variant, "quiet_linear") == 0) {
    peak_mps2 = 0.05 * kG;
  } else if (std::strcmp(variant, "rocking_linear") != 0) {
    std::fprintf(stderr, "unknown variant '%s'\n", variant);
    return 2;
  }

  const std::vector<double> input = rockwatch::bench::stationary_motion(peak_mps2);
  core::StepperOptions options;
  options.dt_s = kDt;
  core::RockingStepper<double> stepper;
  stepper.init(core::make_stepper_setup(core::paper_wall(), kind, core::r_exp(core::paper_wall()), options));
  stepper.reset(input[0], 0.0);

  std::size_t n = 1;
  std::uint64_t impacts = 0, moving_steps = 0, collapses = 0;
  for (unsigned long long k = 0; k < n_steps; ++k) {
    const core::StepReport<double> report = stepper.step(input[n], 0.0);
    impacts += report.impacts_counted;
    moving_steps += stepper.moving() ? 1U : 0U;
    if (stepper.collapsed()) {  // as in bench_engine: never expected, but never a silent no-op either
      ++collapses;
      stepper.reset(input[n], 0.0);
    }
    n = n + 1 == input.size() ? 0 : n + 1;
  }
  // Printing the results keeps the loop alive and lets the script check that the run really rocked.
  std::printf("variant %s steps %llu impacts %llu moving_steps %llu collapses %llu x_m %.9g\n", variant, n_steps,
              static_cast<unsigned long long>(impacts), static_cast<unsigned long long>(moving_steps),
              static_cast<unsigned long long>(collapses), stepper.state().x_m);
  return 0;
}
