#include "progress_line.hpp"

#include <unistd.h>

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

}  // namespace rockwatch::cli
