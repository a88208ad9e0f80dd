// Offline mode's input: an LCM log replayed as an InputSource of the monitor loop, in log time. Each poll hands the
// next event to the loop when a wall reads its channel (as live, where the monitor receives its input channels
// only; the others are counted as skipped) and moves the ReplayClock to the event after, so the loop publishes the
// statuses and forecasts due before that event first. Nothing waits: a replay runs as fast as the loop does.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include "monitor_clock.hpp"
#include "monitor_input_source.hpp"
#include "traffic_log.hpp"

namespace rockwatch::monitor {

class LogReplaySource final : public InputSource {
 public:
  // Opens the log and reads its first event. False, with the message on `err`, when the file is missing, not a
  // regular file, unreadable, or not empty yet holds no LCM event: --offline-in's errors, found before the output
  // log is created.
  bool open(const std::string& path, std::ostream& err);
  // Replays into the input channels of `walls` (the other events are skipped) on `clock`, set to the first event.
  void attach(ReplayClock& clock, const firmware::MultiWallMonitor& walls);

  InputPoll poll(int timeout_ms, InputMessageSink& sink) override;
  std::string end_reason() const override { return "end of log"; }
  // The log stops at the end of the file or at an event that cannot be read (a log cut off while being written):
  // after the loop, unless a signal stopped it, says which, and warns on `err` when the log ends with such an event.
  void check_end(bool stopped, std::ostream& err);
  // "input_log", "log_events", "log_events_fed", "log_events_skipped", "input_log_complete" (after check_end) and,
  // when incomplete, "input_log_read_bytes".
  void add_summary(nlohmann::json& summary) const override;

  std::int64_t events() const { return events_; }
  std::int64_t fed() const { return fed_; }

 private:
  ReplayClock* clock_ = nullptr;
  const firmware::MultiWallMonitor* walls_ = nullptr;
  LcmLogReader reader_;
  std::string path_;
  std::int64_t file_bytes_ = 0;
  const LcmLogReader::Event* event_ = nullptr;  // the next event to hand over; null at the end
  std::int64_t read_end_ = 0;                   // the byte after the last event handed over
  std::int64_t events_ = 0, fed_ = 0, skipped_ = 0;
  bool complete_ = true;
};

}  // namespace rockwatch::monitor
