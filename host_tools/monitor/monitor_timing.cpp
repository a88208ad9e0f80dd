#include "monitor_timing.hpp"

#include <string>

#include "monitor_run.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

std::unique_ptr<process::RealtimeConditions> apply_timing(const TimingSettings& t, LiveInput& input,
                                                          json& report, std::ostream& err) {
  if (!t.any()) return nullptr;
  process::RealtimeRequest request;
  request.fifo_priority = t.priority;
  request.memory_lock = t.priority > 0 ? process::MemoryLock::current_and_future : process::MemoryLock::none;
  request.cpu = t.cpu;
  request.minimal_timer_slack = t.priority > 0;
  auto conditions = std::make_unique<process::RealtimeConditions>(request);
  const process::RealtimeOutcome& o = conditions->outcome();
  json warnings = json::array();
  const auto warn = [&](const std::string& origin, const std::string& problem, const char* goes_on) {
    const std::string text = origin + ": " + problem + "; " + goes_on;
    err << kMessagePrefix << "warning: " << text << std::endl;
    warnings.push_back(text);
  };
  if (!o.realtime_problem.empty()) warn(t.priority_origin, o.realtime_problem, "the monitor goes on with ordinary scheduling");
  if (!o.memory_problem.empty()) warn(t.priority_origin, o.memory_problem, "the monitor goes on with its memory unlocked");
  if (!o.cpu_problem.empty()) warn(t.cpu_origin, o.cpu_problem, "the monitor goes on on any CPU");
  bool busy_poll = false;
  if (t.busy_poll_us > 0) {
    std::string problem;
    busy_poll = input.set_busy_poll(t.busy_poll_us, &problem);
    if (!busy_poll) warn(t.busy_poll_origin, problem, "the monitor goes on without busy polling");
  }
  report = {{"realtime_priority", t.priority > 0 ? json(t.priority) : json(nullptr)},
            {"realtime", o.realtime},
            {"memory_locked", o.memory_locked},
            {"cpu", t.cpu >= 0 ? json(t.cpu) : json(nullptr)},
            {"pinned", o.pinned},
            {"busy_poll_us", t.busy_poll_us > 0 ? json(t.busy_poll_us) : json(nullptr)},
            {"busy_poll", busy_poll},
            {"warnings", warnings}};
  std::string granted;
  const auto add = [&](const std::string& item) { granted += (granted.empty() ? "" : ", ") + item; };
  if (o.realtime) add("SCHED_FIFO " + std::to_string(t.priority));
  if (o.memory_locked) add("memory locked");
  if (o.pinned) add("pinned to CPU " + std::to_string(t.cpu));
  if (busy_poll) add("busy poll " + std::to_string(t.busy_poll_us) + " us");
  if (!granted.empty()) err << kMessagePrefix << "timing: " << granted << std::endl;
  return conditions;
}

}  // namespace rockwatch::monitor
