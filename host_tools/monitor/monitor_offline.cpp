// Offline mode: the input log replayed (log_replay_source.hpp) on its own clock (ReplayClock), every output written
// to the output log at the log time it was made (LogTransport), forecasts in log time (LogTimeForecasts).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "forecast_schedule.hpp"
#include "lcm_transport.hpp"
#include "log_replay_source.hpp"
#include "monitor_clock.hpp"
#include "monitor_event_loop.hpp"
#include "monitor_forecast.hpp"
#include "monitor_modes.hpp"
#include "monitor_summary.hpp"
#include "monitor_wall_set.hpp"
#include "rockwatch/options/option_values.hpp"

namespace rockwatch::monitor {

int run_offline(const MonitorConfig& config, std::ostream& out, std::ostream& err) {
  const std::string& out_path = *config.offline_out;
  LogReplaySource input;
  if (!input.open(*config.offline_in, err)) return kExitUsage;
  lcm::LogFile log_out(out_path, "w");
  if (!log_out.good()) {
    err << kMessagePrefix << "error: --offline-out " << options::quoted(out_path) << ": cannot create the log ("
        << std::strerror(errno) << ")\n";
    return kExitUsage;
  }
  LogTransport transport(log_out);
  ReplayClock clock(transport);
  ForecastTap tap(config, transport);
  MonitorWalls walls;
  if (!init_loop(walls, config, tap.transport(), out, err)) return kExitUsage;
  // No step clock: worst_step_ns would make the output depend on the machine.
  input.attach(clock, *walls.monitor);
  std::unique_ptr<MonitorForecaster> forecaster;
  std::unique_ptr<LogTimeForecasts> forecasts;
  if (config.forecast.enabled) {
    forecaster = std::make_unique<MonitorForecaster>(config.forecast, config.settings, *tap.feed(), false);
    forecasts = std::make_unique<LogTimeForecasts>(*forecaster, clock, transport);
  }
  LoopInputSink sink(*walls.monitor, nullptr, tap.feed());
  LoopServices services;
  services.forecasts = forecasts.get();
  const LoopOutcome loop = run_monitor_loop(input, clock, *walls.monitor, sink, services, err);

  input.check_end(loop.stopped, err);
  bool write_ok = transport.write_failures() == 0;
  if (FILE* f = log_out.getFilePtr(); f != nullptr) write_ok = std::fflush(f) == 0 && std::ferror(f) == 0 && write_ok;
  SummaryParts summary;
  summary.fields = {{"mode", "offline"}, {"output_log", out_path}, {"output_events", transport.events_written()}};
  input.add_summary(summary.fields);
  summary.statuses = loop.statuses;
  summary.stopped_by = loop.stopped_by;
  summary.first_line = "offline: " + std::to_string(input.events()) + " log events (" + std::to_string(input.fed()) +
                       " on the input channels) -> " + std::to_string(transport.events_written()) + " events in " +
                       out_path + (loop.stopped ? "; stopped by " + loop.stopped_by : std::string());
  summary.forecaster = forecaster.get();
  write_summary(out, err, config, walls, summary);
  if (!write_ok) {
    err << kMessagePrefix << "error: --offline-out " << options::quoted(out_path) << ": "
        << transport.write_failures() << " events could not be written\n";
    return kExitRuntime;
  }
  return kExitOk;
}

}  // namespace rockwatch::monitor
