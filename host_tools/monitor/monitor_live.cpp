// Live mode: the input from the monitor's own UDP path (udp_input_source.hpp; the benchmark's build may inject
// liblcm's), every output published with liblcm (and into --log), on the machine's clocks (LiveClock), forecasts in
// their own thread, systemd told when the monitor is ready, alive and stopping.
#include <cstdio>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "forecast_schedule.hpp"
#include "lcm_transport.hpp"
#include "log_flusher.hpp"
#include "monitor_clock.hpp"
#include "monitor_event_loop.hpp"
#include "monitor_forecast.hpp"
#include "monitor_modes.hpp"
#include "monitor_summary.hpp"
#include "monitor_timing.hpp"
#include "monitor_wall_set.hpp"
#include "rockwatch/options/option_values.hpp"
#include "service_notify.hpp"
#include "traffic_log.hpp"
#include "udp_input_source.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

namespace {

// Opens --log (appending after its last complete event) and says what it found there. False with the message.
bool open_traffic_log(TrafficLog& log, const std::string& path, std::ostream& err) {
  if (!log.open(path)) {
    err << kMessagePrefix << "error: --log " << options::quoted(path) << ": cannot open the log (" << log.error()
        << ")\n";
    return false;
  }
  const TrafficLogResume& r = log.resume();
  if (!r.rotated_to.empty()) {
    err << kMessagePrefix << "warning: --log " << options::quoted(path) << ": the existing log is damaged before "
        << "its end; kept unchanged as " << options::quoted(r.rotated_to) << ", a new log started\n";
  } else if (r.events_kept > 0 || r.torn_bytes_cut > 0) {
    err << kMessagePrefix << "note: --log " << options::quoted(path) << ": appending after its " << r.events_kept
        << " events (next event number " << r.next_event_number << ")";
    if (r.torn_bytes_cut > 0) err << "; cut " << r.torn_bytes_cut << " bytes of a torn last event";
    err << "\n";
  }
  return true;
}

// The summary's "log" (after the log is closed; `closed_ok`: the final write worked).
json traffic_log_summary(const TrafficLog& log, const std::string& path, bool closed_ok) {
  const TrafficLogResume& r = log.resume();
  json s = {{"path", path},
            {"events_written", log.events_written()},
            {"events_lost", log.events_lost()},
            {"events_not_durable", log.events_not_durable()},
            {"write_failures", log.write_failures()},
            {"bytes", log.bytes_written()},
            {"events_kept", r.events_kept},
            {"first_event_number", r.next_event_number},
            {"torn_bytes_cut", r.torn_bytes_cut},
            {"complete", closed_ok && log.events_lost() == 0 && log.events_not_durable() == 0}};
  if (!r.rotated_to.empty()) s["rotated_to"] = r.rotated_to;
  if (!log.error().empty()) s["last_error"] = log.error();
  return s;
}

// The line that says the monitor runs: where it listens, its channels, rate and digest (and each wall's channels).
void announce(std::ostream& err, const MonitorConfig& config, const std::string& url, MonitorWalls& walls) {
  const firmware::MonitorChannels& ch = config.settings.channels;
  const bool observer = config.settings.engine.observer_enabled;
  err << kMessagePrefix << "listening on " << url << " (" << config.lcm_url_origin << "): " << ch.accel << ", "
      << ch.accel_batch << (observer ? std::string(", ") + ch.wall_sensor : std::string()) << " -> " << ch.wall_state
      << ", " << ch.alarm << ", " << ch.status << (observer ? std::string(", ") + ch.wall_estimate : std::string())
      << (observer ? "; wall observer on" : "") << "; " << options::number_text(config.settings.sample_rate_hz)
      << " Hz; config digest " << digest_hex(config.settings.config_digest) << std::endl;
  if (walls.many()) {
    err << kMessagePrefix << walls->size() << " walls:";
    for (std::size_t i = 0; i < walls->size(); ++i) {
      const firmware::MonitorChannels& c = walls.settings[i].channels;
      err << (i == 0 ? " " : "; ") << walls.names[i] << " (" << c.accel << " -> " << c.wall_state << ", " << c.alarm
          << ", " << c.status << ")";
    }
    err << std::endl;
  }
  const std::string buffer_warning = receive_buffer_warning(url);
  if (!buffer_warning.empty()) err << kMessagePrefix << "note: " << buffer_warning << std::endl;
}

// --forecast: its own thread, publishing on an LCM instance of its own (the sample path's lcm_publish never waits
// for a forecast's). False with the message when that LCM cannot start.
bool start_forecasts(const MonitorConfig& config, const std::string& url, ForecastFeed& feed,
                     std::unique_ptr<lcm::LCM>& publisher_lcm, std::unique_ptr<MonitorForecaster>& forecaster,
                     ThreadForecasts& forecasts, std::ostream& err) {
  publisher_lcm = std::make_unique<lcm::LCM>(url);
  if (!publisher_lcm->good()) {
    err << kMessagePrefix << "error: " << config.forecast.origin << ": LCM could not start for the forecasts\n";
    return false;
  }
  forecaster = std::make_unique<MonitorForecaster>(config.forecast, config.settings, feed);
  lcm::LCM* const publisher = publisher_lcm.get();
  forecasts.start(std::make_unique<ForecastThread>(
      *forecaster, [publisher](const std::string& channel, const std::uint8_t* data, std::size_t size) {
        return publisher->publish(channel, data, static_cast<unsigned int>(size)) == 0;
      },
      config.timing.cpu));
  err << kMessagePrefix << "forecast: " << config.forecast.members << " members over "
      << options::number_text(config.forecast.horizon_s) << " s, " << options::number_text(config.forecast.rate_hz)
      << " per second -> " << config.forecast.channel << std::endl;
  return true;
}

}  // namespace

int run_live(const MonitorConfig& config, const LiblcmInputFactory* liblcm, std::ostream& out, std::ostream& err) {
  const bool via_liblcm = config.receive_path == ReceivePath::liblcm;
  if (via_liblcm && liblcm == nullptr) {
    err << kMessagePrefix << "error: --receive-path liblcm: this program reads its input with its own path only; "
        << "liblcm's receive thread is the benchmark's (tests/bench: rockwatch-monitor-liblcm)\n";
    return kExitUsage;
  }
  // A 2 MiB receive buffer unless the URL names one (bursts at high rates; the kernel may cap it: said at start).
  const std::string url = with_receive_buffer(config.lcm_url);
  UdpmEndpoint endpoint;
  std::string problem;
  if (!parse_udpm_url(url, &endpoint, &problem)) {
    err << kMessagePrefix << "error: " << config.lcm_url_origin << ": " << options::quoted(config.lcm_url) << ": "
        << problem << "\n";
    return kExitUsage;
  }
  // liblcm only publishes here (unless the benchmark's liblcm input subscribes): liblcm's receive thread, and its
  // fragment reassembly, which two crafted datagrams crash, never starts.
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    err << kMessagePrefix << "error: " << config.lcm_url_origin << ": LCM could not start with "
        << options::quoted(url) << " (a malformed URL, or no multicast route: see `ip route` for 224.0.0.0/4)\n";
    return kExitUsage;
  }
  std::unique_ptr<LiveInput> input;
  if (via_liblcm) {
    input = (*liblcm)(lcm);
  } else {
    auto own = std::make_unique<UdpInputSource>(config);
    if (!own->open(endpoint, &problem)) {
      err << kMessagePrefix << "error: " << config.lcm_url_origin << ": cannot receive on " << options::quoted(url)
          << ": " << problem << "\n";
      return kExitUsage;
    }
    input = std::move(own);
  }
  TrafficLog log;
  if (config.log_path && !open_traffic_log(log, *config.log_path, err)) return kExitUsage;
  LcmTransport lcm_transport(lcm);
  LoggedTransport logged_transport(lcm_transport, log);
  firmware::Transport& transport = config.log_path ? static_cast<firmware::Transport&>(logged_transport)
                                                   : static_cast<firmware::Transport&>(lcm_transport);
  LogFlusher flusher(log, config.log_path ? *config.log_path : std::string(), err);
  ForecastTap tap(config, transport);
  MonitorWalls walls;
  if (!init_loop(walls, config, tap.transport(), out, err)) return kExitUsage;
  firmware::MultiWallMonitor& loop = *walls.monitor;
  loop.set_step_clock(&monotonic_ns);
  // Real-time scheduling, CPU and memory locking once everything above is set up, before the input starts (a
  // receive thread the input starts inherits the policy and CPU).
  json timing_report;
  const std::unique_ptr<process::RealtimeConditions> timing = apply_timing(config.timing, *input, timing_report, err);
  if (!input->start(loop, &problem)) {
    err << kMessagePrefix << "error: " << problem << "\n";
    return kExitRuntime;
  }

  LoopInputSink sink(loop, config.log_path ? &log : nullptr, tap.feed());
  ServiceNotifier service;  // systemd (Type=notify, WatchdogSec=): ready once started, fed from the loop
  std::unique_ptr<lcm::LCM> forecast_lcm;
  std::unique_ptr<MonitorForecaster> forecaster;
  ThreadForecasts forecasts;
  LoopServices services;
  services.log = &flusher;
  services.service = &service;
  if (config.forecast.enabled) services.forecasts = &forecasts;
  services.on_started = [&]() {
    announce(err, config, url, walls);
    if (config.forecast.enabled &&
        !start_forecasts(config, url, *tap.feed(), forecast_lcm, forecaster, forecasts, err)) {
      return false;
    }
    service.ready();
    return true;
  };
  LiveClock clock;
  const LoopOutcome run = run_monitor_loop(*input, clock, loop, sink, services, err);
  if (run.aborted) return kExitRuntime;
  const bool log_ok = log.close();

  SummaryParts summary;
  summary.fields = {{"mode", "live"}, {"lcm_url", url}};
  input->add_summary(summary.fields);
  if (config.timing.any()) summary.fields["timing"] = timing_report;
  if (config.log_path) {
    summary.fields["log"] = traffic_log_summary(log, *config.log_path, log_ok);
    if (!log_ok) {
      err << kMessagePrefix << "warning: --log " << options::quoted(*config.log_path) << ": the final write failed ("
          << log.error() << ")\n";
    }
    summary.human_tail = "  log: " + std::to_string(log.events_written()) + " events written to " +
                         options::quoted(*config.log_path) + ", " + std::to_string(log.events_lost()) + " lost in " +
                         std::to_string(log.write_failures()) + " failed writes\n";
  }
  const double run_time_s = static_cast<double>(run.run_time_us) * 1e-6;
  summary.fields["run_time_s"] = run_time_s;
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f", run_time_s);
  summary.statuses = run.statuses;
  summary.stopped_by = run.stopped_by;
  summary.first_line = "stopped by " + run.stopped_by + " after " + seconds + " s";
  summary.forecaster = forecaster.get();
  write_summary(out, err, config, walls, summary);
  return run.receive_failed ? kExitRuntime : kExitOk;
}

}  // namespace rockwatch::monitor
