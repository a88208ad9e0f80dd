// Progress of a `rockwatch study` on standard error: on a terminal a bar with the count and the time left, rewritten
// at most ten times a second; in a log or a pipe a line at every tenth of the analyses (progress_line.hpp).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <ostream>

#include "common/process/progress_line.hpp"

namespace rockwatch::cli {

class StudyProgress {
 public:
  // `already_done` of `total` analyses were done before this run (--resume); `cancel` is the interrupt flag, so the
  // line can say that the run is stopping.
  StudyProgress(std::ostream& out, bool terminal, std::size_t already_done, std::size_t total,
                const std::atomic<bool>* cancel);

  // run_study's progress callback: `done` of the `in_call` analyses of this run are finished. Called serialised.
  void report(std::size_t done, std::size_t in_call);

  // Clears the bar, so what follows starts on a clean line.
  void finish() { line_.clear(); }

 private:
  std::ostream& out_;
  ProgressLine line_;
  bool terminal_;
  std::size_t already_done_, total_;
  const std::atomic<bool>* cancel_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_update_;
  std::size_t next_tenth_ = 1;
  bool told_stopping_ = false;
};

}  // namespace rockwatch::cli
