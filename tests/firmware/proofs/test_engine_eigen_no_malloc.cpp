// Eigen's own run-time allocation check around the firmware engine: this program is compiled WITHOUT NDEBUG and
// with EIGEN_RUNTIME_NO_MALLOC, and compiles firmware/src/wall_engine.cpp into itself (tests/firmware/proofs/
// CMakeLists.txt), so every Eigen expression evaluated by WallEngine::process asserts when it would allocate.
// Allocation is disallowed (Eigen::internal::set_is_malloc_allowed(false)) around 100 000 process() calls with
// impacts and collapses.
//
//   test_engine_eigen_no_malloc              the proof: exit 0
//   test_engine_eigen_no_malloc --deliberate makes a dynamic Eigen allocation while disallowed: Eigen's assertion
//                                            aborts (exit 1 through the SIGABRT handler); registered WILL_FAIL, so
//                                            it proves the check is armed. Exit 0 here would mean it is not.
#ifdef NDEBUG
#error "test_engine_eigen_no_malloc must be compiled without NDEBUG (Eigen's check is an eigen_assert)"
#endif
#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "test_engine_eigen_no_malloc must be compiled with EIGEN_RUNTIME_NO_MALLOC"
#endif

#include <csignal>
#include <cstdio>
#include <cstring>
#include <unistd.h>
#include <vector>

#include <Eigen/Core>

#include "engine_test_input.hpp"

namespace {

namespace et = rockwatch::engine_test;

extern "C" void on_abort(int) {
  static const char msg[] = "SIGABRT: Eigen's allocation check fired\n";
  const ssize_t ignored = write(STDERR_FILENO, msg, sizeof msg - 1);
  static_cast<void>(ignored);
  _exit(1);
}

int deliberate() {
  std::signal(SIGABRT, on_abort);
  Eigen::internal::set_is_malloc_allowed(false);
  std::printf("allocating an Eigen::VectorXd(64) with allocation disallowed: expect an assertion\n");
  std::fflush(stdout);
  Eigen::VectorXd v = Eigen::VectorXd::Ones(64);
  Eigen::internal::set_is_malloc_allowed(true);
  std::printf("NOT ARMED: the dynamic allocation went through (sum %g); EIGEN_RUNTIME_NO_MALLOC has no effect\n",
              v.sum());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--deliberate") == 0) return deliberate();
  if (argc != 1) {
    std::fprintf(stderr, "usage: %s [--deliberate]\n", argv[0]);
    return 2;
  }
  const std::vector<rockwatch::firmware::SensorSampleQ> cycle = et::make_cycle();
  rockwatch::firmware::WallEngine engine;
  const rockwatch::firmware::WallEngineError e = engine.init(et::paper_config());
  if (e != rockwatch::firmware::WallEngineError::ok) {
    std::fprintf(stderr, "FAIL: WallEngine::init: %s\n", rockwatch::firmware::wall_engine_error_message(e));
    return 1;
  }
  Eigen::internal::set_is_malloc_allowed(false);
  const et::RunCounts c = et::run_engine(engine, cycle, et::kMeasuredSamples);
  Eigen::internal::set_is_malloc_allowed(true);
  std::printf("process with Eigen allocation disallowed: %llu samples, %llu impacts, %llu collapses, %llu moving,"
              " %llu IMMINENT\n",
              static_cast<unsigned long long>(c.samples), static_cast<unsigned long long>(c.impacts),
              static_cast<unsigned long long>(c.collapses), static_cast<unsigned long long>(c.moving_samples),
              static_cast<unsigned long long>(c.imminent_samples));
  if (!et::run_was_eventful(c)) {
    std::fprintf(stderr, "FAIL: the input did not produce impacts and a collapse\n");
    return 1;
  }
  std::printf("ok\n");
  return 0;
}
