#include "study/run/study_progress.hpp"

#include <chrono>
#include <cstddef>
#include <string>

#include "common/process/text_report.hpp"

namespace rockwatch::cli {

namespace {

constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

}  // namespace

StudyProgress::StudyProgress(std::ostream& out, bool terminal, std::size_t already_done, std::size_t total,
                             const std::atomic<bool>* cancel)
    : out_(out),
      line_(out, terminal),
      terminal_(terminal),
      already_done_(already_done),
      total_(total),
      cancel_(cancel),
      start_(std::chrono::steady_clock::now()),
      last_update_(start_ - kRedrawInterval) {}

void StudyProgress::report(std::size_t done, std::size_t in_call) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed_s = std::chrono::duration<double>(now - start_).count();
  const std::size_t all_done = already_done_ + done;
  if (cancel_ != nullptr && cancel_->load() && !told_stopping_) {
    told_stopping_ = true;
    line_.clear();
    out_ << "study: stopping: the analyses in flight finish, then the finished ones are written (a second Ctrl-C "
            "stops at once and loses them)\n"
         << std::flush;
    return;
  }
  if (told_stopping_) return;
  if (terminal_) {
    if (now - last_update_ < kRedrawInterval && done < in_call) return;
    last_update_ = now;
    // The rate is this run's: with --resume the analyses done before took no time here.
    std::string text = "study " + progress_bar_text(done, in_call, elapsed_s);
    if (already_done_ > 0) text += format("  (%zu/%zu in all)", all_done, total_);
    line_.update(text);
    return;
  }
  if (in_call == 0) return;
  // One line each time another tenth of this run's analyses is done (the last one at the end).
  if (next_tenth_ > 10 || done * 10 < next_tenth_ * in_call) return;
  while (next_tenth_ <= 10 && done * 10 >= next_tenth_ * in_call) ++next_tenth_;
  std::string text = format("study: %zu/%zu analyses (%d %%), %s", all_done, total_,
                            static_cast<int>(100.0 * static_cast<double>(all_done) / static_cast<double>(total_)),
                            duration_text(elapsed_s).c_str());
  if (done < in_call && done > 0) {
    text += ", " + duration_text(elapsed_s / static_cast<double>(done) * static_cast<double>(in_call - done)) + " left";
  }
  line_.step(text);
}

}  // namespace rockwatch::cli
