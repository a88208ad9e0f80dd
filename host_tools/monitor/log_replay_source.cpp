#include "log_replay_source.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "monitor_run.hpp"
#include "rockwatch/options/option_values.hpp"

namespace rockwatch::monitor {

bool LogReplaySource::open(const std::string& path, std::ostream& err) {
  path_ = path;
  const std::string what = std::string(kMessagePrefix) + "error: --offline-in " + options::quoted(path) + ": ";
  struct stat in_stat {};
  if (stat(path.c_str(), &in_stat) != 0) {
    err << what << std::strerror(errno) << '\n';
    return false;
  }
  if (!S_ISREG(in_stat.st_mode)) {
    err << what << "not a regular file\n";
    return false;
  }
  file_bytes_ = in_stat.st_size;
  if (!reader_.open(path)) {
    err << what << "cannot open the log (" << reader_.error() << ")\n";
    return false;
  }
  event_ = reader_.next();
  if (event_ == nullptr && file_bytes_ > 0) {
    err << what << "not an LCM log (no event found in " << file_bytes_ << " bytes)\n";
    return false;
  }
  read_end_ = reader_.read_end();
  return true;
}

void LogReplaySource::attach(ReplayClock& clock, const firmware::MultiWallMonitor& walls) {
  clock_ = &clock;
  walls_ = &walls;
  if (event_ != nullptr) clock_->advance_to(event_->utime);
}

InputPoll LogReplaySource::poll(int /*timeout_ms*/, InputMessageSink& sink) {
  if (event_ == nullptr) return InputPoll::ended;
  ++events_;
  if (walls_->reads(event_->channel.c_str())) {
    clock_->enter(event_->utime);  // the outputs this event causes carry its time
    sink.on_input_message(event_->channel.c_str(), event_->data.data(), event_->data.size(), event_->utime);
    ++fed_;
  } else {
    ++skipped_;
  }
  read_end_ = reader_.read_end();
  event_ = reader_.next();
  if (event_ != nullptr) clock_->advance_to(event_->utime);
  return InputPoll::ok;
}

void LogReplaySource::check_end(bool stopped, std::ostream& err) {
  if (stopped || read_end_ < 0 || read_end_ >= file_bytes_) return;
  complete_ = false;
  err << kMessagePrefix << "warning: --offline-in " << options::quoted(path_) << ": the log ends with an unreadable "
      << "or truncated event (events end at byte " << read_end_ << " of " << file_bytes_ << "); " << events_
      << " events processed\n";
}

void LogReplaySource::add_summary(nlohmann::json& summary) const {
  summary["input_log"] = path_;
  summary["log_events"] = events_;
  summary["log_events_fed"] = fed_;
  summary["log_events_skipped"] = skipped_;
  summary["input_log_complete"] = complete_;
  if (!complete_) summary["input_log_read_bytes"] = read_end_;
}

}  // namespace rockwatch::monitor
