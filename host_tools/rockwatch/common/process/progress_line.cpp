#include "common/process/progress_line.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace rockwatch::cli {

namespace {

// Carriage return, then erase to the end of the line (ANSI EL), so a shorter text leaves no tail of a longer one.
constexpr const char* kRewind = "\r\x1b[K";

}  // namespace

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

void ProgressLine::update(const std::string& text) {
  if (!terminal_) return;
  out_ << kRewind << text << std::flush;
  showing_ = true;
}

void ProgressLine::step(const std::string& text) {
  if (terminal_) return;
  out_ << text << '\n' << std::flush;
}

void ProgressLine::clear() {
  if (!showing_) return;
  out_ << kRewind << std::flush;
  showing_ = false;
}

std::string progress_bar_text(std::size_t done, std::size_t total, double elapsed_s, std::size_t width) {
  const double fraction =
      total == 0 || done >= total ? 1.0 : static_cast<double>(done) / static_cast<double>(total);
  const auto filled = static_cast<std::size_t>(fraction * static_cast<double>(width));
  std::string text = "[" + std::string(filled, '#') + std::string(width - filled, '.') + "]  ";
  char numbers[64];
  std::snprintf(numbers, sizeof numbers, "%zu/%zu  %d %%  ", done, total, static_cast<int>(std::floor(100.0 * fraction)));
  text += numbers;
  text += duration_text(elapsed_s);
  if (done > 0 && done < total) {
    text += ", " + duration_text(elapsed_s / static_cast<double>(done) * static_cast<double>(total - done)) + " left";
  }
  return text;
}

std::string duration_text(double seconds) {
  const long long total = std::llround(std::fmax(0.0, seconds));
  char text[64];
  if (total < 60) {
    std::snprintf(text, sizeof text, "%lld s", total);
  } else if (total < 3600) {
    std::snprintf(text, sizeof text, "%lld min %02lld s", total / 60, total % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld h %02lld min", total / 3600, (total % 3600) / 60);
  }
  return text;
}

}  // namespace rockwatch::cli
