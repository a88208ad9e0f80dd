// Progress of a long run on standard error: on a terminal one line rewritten in place ("set 3/11 Y ..."), so the
// screen shows where the run is without scrolling; in a log file or a pipe only whole lines, one per finished step,
// because carriage returns make logs unreadable.
#pragma once

#include <ostream>
#include <string>

namespace rockwatch::cli {

// True when standard error is a terminal.
bool stderr_is_terminal();

class ProgressLine {
 public:
  ProgressLine(std::ostream& out, bool terminal) : out_(out), terminal_(terminal) {}
  ~ProgressLine() { clear(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // Terminal: replaces the line with `text`. Otherwise nothing: a log gets only step().
  void update(const std::string& text);
  // Not on a terminal: writes `text` as a line of its own. On a terminal nothing: the next update() replaces the line.
  void step(const std::string& text);
  // Removes an in-place line, so what follows starts on a clean line.
  void clear();

 private:
  std::ostream& out_;
  bool terminal_;
  bool showing_ = false;
};

}  // namespace rockwatch::cli
