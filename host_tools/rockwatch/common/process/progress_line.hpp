// Progress of a long run on standard error: on a terminal one line rewritten in place ("set 3/11 Y ..."), so the
// screen shows where the run is without scrolling; in a log file or a pipe only whole lines, one per finished step,
// because carriage returns make logs unreadable.
#pragma once

#include <cstddef>
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

// "[#########...............]  640/1760  36 %  1 min 02 s, 1 min 49 s left": a bar `width` characters wide, the
// count, and the elapsed and remaining time (by the rate so far; "left" only once something is done).
std::string progress_bar_text(std::size_t done, std::size_t total, double elapsed_s, std::size_t width = 24);

// "12 s", "3 min 05 s", "2 h 07 min": a duration as people read it, rounded to whole seconds.
std::string duration_text(double seconds);

}  // namespace rockwatch::cli
