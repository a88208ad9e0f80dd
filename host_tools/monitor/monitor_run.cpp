#include "monitor_run.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "datagram_input.hpp"
#include "lcm_transport.hpp"
#include "monitor_config.hpp"
#include "monitor_forecast.hpp"
#include "monitor_output.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/process/realtime.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"
#include "service_notify.hpp"
#include "traffic_log.hpp"
#include "udp_receiver.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

namespace {

constexpr const char* kPrefix = "rockwatch-monitor: ";

// ---------------------------------------------------------------------------------------------------------------
// SIGINT / SIGTERM: a flag the loops check (every ≤ 100 ms live, every event offline).

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) { g_stop_signal = signal_number; }

class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;  // no SA_RESTART: the signal interrupts LCM's select() at once
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
    // A reader of stdout that goes away must not kill the monitor: it keeps publishing on LCM.
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, &old_pipe_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    sigaction(SIGPIPE, &old_pipe_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  static bool stopped() { return g_stop_signal != 0; }
  static std::string stopped_by() {
    const int s = g_stop_signal;
    if (s == SIGINT) return "SIGINT";
    if (s == SIGTERM) return "SIGTERM";
    return "signal " + std::to_string(s);
  }

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
  struct sigaction old_pipe_ {};
};

// ---------------------------------------------------------------------------------------------------------------

class NullTransport final : public firmware::Transport {
 public:
  bool publish(const char*, const std::uint8_t*, std::size_t) override { return true; }
};

// Live with --log: every published message also goes to the monitor's traffic log.
class LoggedTransport final : public firmware::Transport {
 public:
  LoggedTransport(firmware::Transport& inner, TrafficLog& log) : inner_(inner), log_(log) {}
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override {
    log_.add(channel, data, size, realtime_utime());
    return inner_.publish(channel, data, size);
  }

 private:
  firmware::Transport& inner_;
  TrafficLog& log_;
};

// The input side of --log: a second subscription to the input channels, made before the loop's, so each input
// event precedes in the log the outputs it caused.
// Input messages from the receive path: into the traffic log (when --log), then the loop.
// With --forecast, the ground messages also go to the forecast's feed (a wait-free copy, monitor_forecast.hpp).
class LoopInputSink final : public InputMessageSink {
 public:
  LoopInputSink(firmware::MultiWallMonitor& loop, TrafficLog* log, ForecastFeed* feed)
      : loop_(loop), log_(log), feed_(feed) {}
  void on_input_message(const char* channel, const std::uint8_t* data, std::size_t size,
                        std::int64_t receive_utime) override {
    if (log_ != nullptr) log_->add(channel, data, size, receive_utime);
    if (feed_ != nullptr) feed_->on_input(channel, data, size);
    loop_.on_message(channel, data, size, receive_utime);
  }

 private:
  firmware::MultiWallMonitor& loop_;
  TrafficLog* log_;
  ForecastFeed* feed_;
};

// Every datagram the socket received, and where it went (datagram_input.hpp).
json datagram_summary(const UdpReceiver& receiver, const DatagramInput& input) {
  const firmware::DatagramCounters& d = input.datagram_counters();
  static const char* const kReasons[firmware::kDatagramRejectReasons] = {
      "truncated_header", "bad_magic", "channel_unterminated", "channel_length", "(retired)",
      "fragment_count", "fragment_bounds", "fragment_mismatch", "fragment_duplicate"};
  json reasons = json::object();
  for (int k = 0; k < firmware::kDatagramRejectReasons; ++k) reasons[kReasons[k]] = d.rejected_by_reason[k];
  return {{"received", receiver.datagrams()},
          {"from_other_sources", input.counters().from_other_sources},
          {"short_messages", d.short_messages},
          {"fragments", d.fragments},
          {"messages_reassembled", d.messages_reassembled},
          {"skipped_too_large", d.skipped_too_large},
          {"rejected", d.rejected},
          {"rejected_by_reason", reasons},
          {"abandoned", d.abandoned},
          {"evicted", d.evicted},
          {"expired", d.expired},
          {"input_messages", input.counters().input_messages},
          {"other_channels", input.counters().other_channels}};
}

// Writes the log's buffer; a failure is counted by the loop (status flag, counter) and reported on stderr once per
// run of failures, and again when writing works again. Monitoring never stops for the log.
class LogFlusher {
 public:
  LogFlusher(TrafficLog& log, std::string path, std::ostream& err) : log_(log), path_(std::move(path)), err_(err) {}
  void flush(firmware::MultiWallMonitor& loop) {
    if (!log_.is_open()) return;
    if (log_.flush()) {
      if (failing_) {
        err_ << kPrefix << "note: --log " << options::quoted(path_) << ": writing again ("
             << log_.events_lost() << " events lost in all)" << std::endl;
        failing_ = false;
      }
      return;
    }
    // One count per failed write or sync, so the status's log_write_failures is the log's write_failures.
    const std::int64_t failures = log_.write_failures();
    for (; failures_noted_ < failures; ++failures_noted_) loop.note_log_write_failure();
    if (!failing_) {
      err_ << kPrefix << "warning: --log " << options::quoted(path_) << ": write failed (" << log_.error() << "); "
           << (log_.events_lost() - lost_reported_) << " events lost; monitoring goes on, the log is retried every "
           << "second" << std::endl;
      failing_ = true;
      lost_reported_ = log_.events_lost();
    }
  }
  // At shutdown: everything handed to the disk and waited for, so the last status counts every failure.
  void drain(firmware::MultiWallMonitor& loop) {
    if (!log_.is_open()) return;
    (void)log_.drain();  // failures are reported by the flush below
    flush(loop);
  }

 private:
  TrafficLog& log_;
  std::string path_;
  std::ostream& err_;
  bool failing_ = false;
  std::int64_t lost_reported_ = 0;  // events lost when the last warning was written
  std::int64_t failures_noted_ = 0;  // failures counted by the loop
};

// The engines the monitor can run: the loop is handed the one --arith selects.
struct MonitorEngines {
  firmware::WallEngine fixed;
  sim::DoubleWallEngine dbl;
  firmware::SampleEngine& selected(firmware::MonitorArithmetic a) {
    if (a == firmware::MonitorArithmetic::double_precision) return dbl;
    return fixed;
  }
};

// The walls the monitor follows: the one of the top-level settings, or those of the `walls` key (monitor_walls.hpp),
// each with its engines and its alarm printer (which names the wall when there are several).
struct MonitorWalls {
  std::vector<std::string> names;  // empty with the single top-level wall
  std::vector<firmware::MonitorSettings> settings;
  std::vector<std::unique_ptr<MonitorEngines>> engines;
  std::vector<std::unique_ptr<AlarmPrinter>> printers;
  std::unique_ptr<firmware::MultiWallMonitor> monitor = std::make_unique<firmware::MultiWallMonitor>();
  bool many() const { return !names.empty(); }
  firmware::MultiWallMonitor* operator->() { return monitor.get(); }
};

// Starts the walls' loops on the selected engines; on refusal prints a message naming the wall and the settings at
// fault and returns false. `out`: where the alarm printers write.
bool init_loop(MonitorWalls& walls, const MonitorConfig& config, firmware::Transport& transport, std::ostream& out,
               std::ostream& err) {
  if (config.walls.empty()) {
    walls.settings.push_back(config.settings);
  } else {
    for (const WallMonitorConfig& w : config.walls) {
      walls.names.push_back(w.name);
      walls.settings.push_back(w.settings);
    }
  }
  std::vector<firmware::SampleEngine*> engines;
  std::vector<firmware::MonitorListener*> listeners;
  for (std::size_t i = 0; i < walls.settings.size(); ++i) {
    walls.engines.push_back(std::make_unique<MonitorEngines>());
    walls.printers.push_back(std::make_unique<AlarmPrinter>(out, walls.many() ? walls.names[i] : std::string()));
    engines.push_back(&walls.engines.back()->selected(config.settings.arithmetic));
    listeners.push_back(walls.printers.back().get());
  }
  const firmware::MultiWallError me =
      walls->init(walls.settings.data(), engines.data(), listeners.data(), walls.settings.size(), transport);
  if (me == firmware::MultiWallError::ok) return true;
  const std::size_t at = walls->failed_wall();
  const std::string wall_name = walls.many() ? "walls[" + std::to_string(at) + "] (" + walls.names[at] + "): " : "";
  const std::string wall_origin = walls.many() ? config.walls[at].wall_origin : config.wall_origin;
  err << kPrefix << "error: " << wall_name;
  if (me != firmware::MultiWallError::wall) {
    err << firmware::multi_wall_error_message(me) << '\n';
    return false;
  }
  const firmware::MonitorError e = walls->wall_error();
  if (e == firmware::MonitorError::engine) {
    const firmware::WallEngineError w = walls->wall(at).engine_error();
    if (w == firmware::WallEngineError::fixed_point_setup) {
      err << "the wall (" << wall_origin << ") at the sample rate " << options::number_text(config.settings.sample_rate_hz)
          << " Hz (" << config.rate_origin << ") is outside the fixed-point engine's formats: "
          << firmware::wall_engine_error_message(w);
    } else if (w == firmware::WallEngineError::indicator_constants) {
      err << "the wall (" << wall_origin << ") is outside the alarm's formats: "
          << firmware::wall_engine_error_message(w);
    } else {
      err << "the wall engine refused the settings: " << firmware::wall_engine_error_message(w);
    }
  } else {
    err << "the monitor loop refused the settings: " << firmware::monitor_error_message(e);
  }
  err << '\n';
  return false;
}

json wall_summary(const MonitorConfig& config, const firmware::MonitorLoop& loop, const AlarmPrinter& printer,
                  std::int64_t statuses) {
  json s;
  s["config_digest"] = digest_hex(config.settings.config_digest);
  s["alarm_level"] = level_name(static_cast<std::int64_t>(loop.alarm_level()));
  s["max_alarm_level"] = level_name(printer.max_level());
  s["alarm_events"] = printer.events();
  s["status_published"] = statuses;
  s["counters"] = counters_json(loop.counters());
  if (const core::ObserverCounters* c = loop.observer_counters()) {
    s["observer"] = observer_json(config.settings.engine.observer, loop.last_observer(), *c, loop.counters());
  }
  return s;
}

// One wall: its summary, as always. Many: the first wall's (the walls share the ground input, so its sample counters
// are the input's), the highest alarm level and the alarm transitions of all, and "walls": each wall's summary with
// its name and alarm channel.
json common_summary(const MonitorConfig& config, MonitorWalls& walls, std::int64_t statuses) {
  json s = wall_summary(config, walls->wall(0), *walls.printers[0], statuses);
  if (!walls.many()) return s;
  std::int64_t highest = 0, events = 0;
  json list = json::array();
  for (std::size_t i = 0; i < walls->size(); ++i) {
    highest = std::max(highest, walls.printers[i]->max_level());
    events += walls.printers[i]->events();
    json w = wall_summary(config, walls->wall(i), *walls.printers[i], statuses);
    w.erase("config_digest");
    w["name"] = walls.names[i];
    w["alarm_channel"] = walls.settings[i].channels.alarm;
    list.push_back(w);
  }
  s["max_alarm_level"] = level_name(highest);
  s["alarm_events"] = events;
  s["walls"] = list;
  return s;
}

void human_summary(std::ostream& err, const std::string& first_line, MonitorWalls& walls, std::int64_t statuses) {
  const firmware::MonitorLoop& loop = walls->wall(0);
  const AlarmPrinter& printer = *walls.printers[0];
  const firmware::MonitorCounters& c = loop.counters();
  err << kPrefix << first_line << '\n'
      << "  samples: " << c.samples_received << " received, " << c.samples_processed << " processed ("
      << c.samples_bridged << " bridged), " << c.gaps << " gaps, " << c.state_resets << " state resets, "
      << c.duplicates << " duplicates, " << c.out_of_order << " out of order, " << c.late << " late\n"
      << "  faults: " << c.rejected_not_finite << " not finite, " << c.rejected_out_of_range << " out of range, "
      << c.lift_off << " lift-off, " << c.sensor_flags << " sensor flags, " << c.decode_errors << " decode errors, "
      << c.saturated << " saturated, " << c.publisher_restarts << " publisher restarts, " << c.publish_failures
      << " publish failures, " << c.messages_ignored << " ignored, " << c.log_write_failures << " log write failures, " << c.time_untrusted << " untrusted times\n"
      << "  alarm: " << printer.events() << " transitions, highest " << level_name(printer.max_level()) << ", now "
      << level_name(static_cast<std::int64_t>(loop.alarm_level())) << "; " << c.states_published
      << " wall states, " << statuses << " status messages; worst step " << c.worst_step_ns << " ns\n";
  if (const core::ObserverCounters* o = loop.observer_counters()) {
    const core::ObserverSample& last = loop.last_observer();
    err << "  observer: " << c.sensor_samples_received << " sensor samples (" << c.sensor_time_untrusted
        << " untrusted times), " << o->x_updates << " x and " << o->a_updates << " a updates, " << o->rejected
        << " rejected, faults " << o->not_finite << " not finite, " << o->out_of_range << " out of range, " << o->stuck
        << " stuck, " << o->jumps << " jumps, " << o->motion_while_quiet << " motion while quiet, " << o->stale
        << " stale, " << o->queue_overflow << " queue overflow; " << o->misaligned << " misaligned, " << o->dropouts
        << " dropouts, " << o->reinitialised << " re-initialisations; r " << last.r_estimate << " +- " << last.sigma_r
        << ", offset " << last.bias_m << " m; " << c.estimates_published << " estimates\n";
  }
  if (!walls.many()) return;
  err << "  walls (" << walls->size() << ", the counters above are the first one's):\n";
  for (std::size_t i = 0; i < walls->size(); ++i) {
    const firmware::MonitorCounters& w = walls->wall(i).counters();
    err << "    " << walls.names[i] << ": alarm highest " << level_name(walls.printers[i]->max_level()) << ", now "
        << level_name(static_cast<std::int64_t>(walls->wall(i).alarm_level())) << "; " << walls.printers[i]->events()
        << " transitions, " << w.samples_processed << " samples processed, " << w.states_published
        << " wall states on " << walls.settings[i].channels.wall_state << "\n";
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Timing of the live receive thread (--realtime, --cpu, --busy-poll-us; config realtime_priority, cpu, busy_poll_us).

// Asks for what the settings request, for this (the receive and processing) thread; a refusal is a warning on
// `err`, never a failure: the monitor goes on as it would without the option. `report`: the summary's "timing".
std::unique_ptr<process::RealtimeConditions> apply_timing(const TimingSettings& t, UdpReceiver* receiver,
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
    err << kPrefix << "warning: " << text << std::endl;
    warnings.push_back(text);
  };
  if (!o.realtime_problem.empty()) warn(t.priority_origin, o.realtime_problem, "the monitor goes on with ordinary scheduling");
  if (!o.memory_problem.empty()) warn(t.priority_origin, o.memory_problem, "the monitor goes on with its memory unlocked");
  if (!o.cpu_problem.empty()) warn(t.cpu_origin, o.cpu_problem, "the monitor goes on on any CPU");
  bool busy_poll = false;
  if (t.busy_poll_us > 0 && receiver != nullptr) {
    std::string problem;
    busy_poll = receiver->set_busy_poll(t.busy_poll_us, &problem);
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
  if (!granted.empty()) err << kPrefix << "timing: " << granted << std::endl;
  return conditions;
}

// ---------------------------------------------------------------------------------------------------------------
// Live: LCM in, LCM out.

int run_live(const MonitorConfig& config, std::ostream& out, std::ostream& err) {
  // A 2 MiB receive buffer unless the URL names one (bursts at high rates; the kernel may cap it: said below).
  const std::string url = with_receive_buffer(config.lcm_url);
  UdpmEndpoint endpoint;
  std::string problem;
  if (!parse_udpm_url(url, &endpoint, &problem)) {
    err << kPrefix << "error: " << config.lcm_url_origin << ": " << options::quoted(config.lcm_url) << ": " << problem
        << "\n";
    return kExitUsage;
  }
  // liblcm only publishes: the monitor never subscribes or handles through it, so liblcm's receive thread (and its
  // fragment reassembly, which two crafted datagrams crash) never starts.
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    err << kPrefix << "error: " << config.lcm_url_origin << ": LCM could not start with "
        << options::quoted(url)
        << " (a malformed URL, or no multicast route: see `ip route` for 224.0.0.0/4)\n";
    return kExitUsage;
  }
  // --receive-path liblcm: liblcm's own receive thread, kept only to measure the two paths side by side
  // (docs/BENCHMARKS.md); it is the path two crafted datagrams crash.
  const bool via_liblcm = config.receive_path == ReceivePath::liblcm;
  UdpReceiver receiver;
  if (!via_liblcm && !receiver.open(endpoint, &problem)) {
    err << kPrefix << "error: " << config.lcm_url_origin << ": cannot receive on " << options::quoted(url) << ": "
        << problem << "\n";
    return kExitUsage;
  }
  TrafficLog log;
  if (config.log_path && !log.open(*config.log_path)) {
    err << kPrefix << "error: --log " << options::quoted(*config.log_path) << ": cannot open the log (" << log.error()
        << ")\n";
    return kExitUsage;
  }
  if (config.log_path) {
    const TrafficLogResume& r = log.resume();
    if (!r.rotated_to.empty()) {
      err << kPrefix << "warning: --log " << options::quoted(*config.log_path) << ": the existing log is damaged before "
          << "its end; kept unchanged as " << options::quoted(r.rotated_to) << ", a new log started\n";
    } else if (r.events_kept > 0 || r.torn_bytes_cut > 0) {
      err << kPrefix << "note: --log " << options::quoted(*config.log_path) << ": appending after its " << r.events_kept
          << " events (next event number " << r.next_event_number << ")";
      if (r.torn_bytes_cut > 0) err << "; cut " << r.torn_bytes_cut << " bytes of a torn last event";
      err << "\n";
    }
  }
  LcmTransport lcm_transport(lcm);
  LoggedTransport logged_transport(lcm_transport, log);
  firmware::Transport& transport = config.log_path ? static_cast<firmware::Transport&>(logged_transport)
                                                   : static_cast<firmware::Transport&>(lcm_transport);
  LogFlusher flusher(log, config.log_path ? *config.log_path : std::string(), err);
  // --forecast: the loop's outputs also go to the forecast's feed.
  std::unique_ptr<ForecastFeed> feed;
  std::unique_ptr<FeedTransport> feed_transport;
  if (config.forecast.enabled) {
    feed = std::make_unique<ForecastFeed>(config.settings.channels, config.settings.engine.observer_enabled);
    feed_transport = std::make_unique<FeedTransport>(transport, *feed);
  }
  MonitorWalls walls;
  if (!init_loop(walls, config, feed_transport ? static_cast<firmware::Transport&>(*feed_transport) : transport, out,
                 err)) {
    return kExitUsage;
  }
  firmware::MultiWallMonitor* const loop = walls.monitor.get();
  loop->set_step_clock(&monotonic_ns);
  // Real-time scheduling, CPU and memory locking once everything above is set up; before liblcm's subscription, so
  // that with --receive-path liblcm its receive thread (started by the subscription) inherits the policy and CPU.
  json timing_report;
  const std::unique_ptr<process::RealtimeConditions> timing =
      apply_timing(config.timing, via_liblcm ? nullptr : &receiver, timing_report, err);
  LoopInputSink sink(*loop, config.log_path ? &log : nullptr, feed.get());
  DatagramInput input(config.settings.channels, config.accept_from, sink, config.settings.engine.observer_enabled);
  input.set_input_channels(loop);
  std::unique_ptr<LcmInput> lcm_input;
  if (via_liblcm) {
    lcm_input = std::make_unique<LcmInput>(lcm, loop->wall(0));  // one wall only (the config refuses walls)
    if (!lcm_input->good()) {
      err << kPrefix << "error: LCM refused the subscription to the input channels\n";
      return kExitRuntime;
    }
  }

  std::int64_t statuses = 0;
  loop->publish_status(realtime_utime());
  ++statuses;
  const firmware::MonitorChannels& ch = config.settings.channels;
  const std::string buffer_warning = receive_buffer_warning(url);
  const bool observer = config.settings.engine.observer_enabled;
  err << kPrefix << "listening on " << url << " (" << config.lcm_url_origin << "): " << ch.accel << ", "
      << ch.accel_batch << (observer ? std::string(", ") + ch.wall_sensor : std::string()) << " -> " << ch.wall_state
      << ", " << ch.alarm << ", " << ch.status << (observer ? std::string(", ") + ch.wall_estimate : std::string())
      << (observer ? "; wall observer on" : "") << "; "
      << options::number_text(config.settings.sample_rate_hz) << " Hz; config digest "
      << digest_hex(config.settings.config_digest) << std::endl;
  if (walls.many()) {
    err << kPrefix << walls->size() << " walls:";
    for (std::size_t i = 0; i < walls->size(); ++i) {
      const firmware::MonitorChannels& c = walls.settings[i].channels;
      err << (i == 0 ? " " : "; ") << walls.names[i] << " (" << c.accel << " -> " << c.wall_state << ", " << c.alarm
          << ", " << c.status << ")";
    }
    err << std::endl;
  }
  if (!buffer_warning.empty()) err << kPrefix << "note: " << buffer_warning << std::endl;
  // --forecast: its own thread, publishing on an LCM instance of its own (the sample path's lcm_publish never waits
  // for a forecast's).
  std::unique_ptr<lcm::LCM> forecast_lcm;
  std::unique_ptr<MonitorForecaster> forecaster;
  std::unique_ptr<ForecastThread> forecast_thread;
  if (config.forecast.enabled) {
    forecast_lcm = std::make_unique<lcm::LCM>(url);
    if (!forecast_lcm->good()) {
      err << kPrefix << "error: " << config.forecast.origin << ": LCM could not start for the forecasts\n";
      return kExitRuntime;
    }
    forecaster = std::make_unique<MonitorForecaster>(config.forecast, config.settings, *feed);
    lcm::LCM* const publisher = forecast_lcm.get();
    forecast_thread = std::make_unique<ForecastThread>(
        *forecaster, [publisher](const std::string& channel, const std::uint8_t* data, std::size_t size) {
          return publisher->publish(channel, data, static_cast<unsigned int>(size)) == 0;
        },
        config.timing.cpu);
    err << kPrefix << "forecast: " << config.forecast.members << " members over "
        << options::number_text(config.forecast.horizon_s) << " s, " << options::number_text(config.forecast.rate_hz)
        << " per second -> " << config.forecast.channel << std::endl;
  }
  ServiceNotifier service;  // systemd (Type=notify, WatchdogSec=): ready now, fed from the loop below
  service.ready();

  constexpr std::int64_t kSecondNs = 1000000000;
  const std::int64_t start_ns = monotonic_ns();
  std::int64_t next_status_ns = start_ns + kSecondNs;
  int consecutive_errors = 0;
  bool failed = false;
  while (!StopSignals::stopped()) {
    const std::int64_t now_ns = monotonic_ns();
    service.feed(now_ns);
    if (now_ns >= next_status_ns) {
      flusher.flush(*loop);  // before the status, which then carries a log failure
      loop->publish_status(realtime_utime());
      ++statuses;
      next_status_ns += kSecondNs;
      if (next_status_ns <= now_ns) next_status_ns = now_ns + kSecondNs;  // the process was stopped for a while
    }
    const std::int64_t wait_ms = std::clamp<std::int64_t>((next_status_ns - now_ns + 999999) / 1000000, 0, 100);
    errno = 0;
    const int rc = via_liblcm ? lcm.handleTimeout(static_cast<int>(wait_ms))
                              : receiver.receive(input, static_cast<int>(wait_ms), &realtime_utime);
    loop->note_datagram_counts(input.datagram_counters().rejected, input.counters().from_other_sources);
    if (rc >= 0) {
      consecutive_errors = 0;
      continue;
    }
    if (StopSignals::stopped()) break;
    if (errno == EINTR) continue;
    if (++consecutive_errors > 100) {
      err << kPrefix << "error: the receive socket failed " << consecutive_errors << " times in a row ("
          << std::strerror(errno) << "); stopping\n";
      failed = true;
      break;
    }
  }
  service.stopping();
  if (forecast_thread) forecast_thread->stop();
  loop->finish_pending();  // samples the engine still worked on (carry-over) are published before the last status
  flusher.drain(*loop);
  loop->publish_status(realtime_utime());
  ++statuses;
  const bool log_ok = log.close();
  const double run_time_s = static_cast<double>(monotonic_ns() - start_ns) * 1e-9;

  json s = common_summary(config, walls, statuses);
  s["mode"] = "live";
  s["stopped_by"] = failed ? std::string("receive failure") : StopSignals::stopped_by();
  s["lcm_url"] = url;
  s["receive_path"] = via_liblcm ? "liblcm" : "own";
  s["lcm_messages"] = via_liblcm ? lcm_input->messages() : input.counters().input_messages;
  if (!via_liblcm) s["datagrams"] = datagram_summary(receiver, input);
  if (config.timing.any()) s["timing"] = timing_report;
  if (config.log_path) {
    const TrafficLogResume& r = log.resume();
    s["log"] = {{"path", *config.log_path},
                {"events_written", log.events_written()},
                {"events_lost", log.events_lost()},
                {"events_not_durable", log.events_not_durable()},
                {"write_failures", log.write_failures()},
                {"bytes", log.bytes_written()},
                {"events_kept", r.events_kept},
                {"first_event_number", r.next_event_number},
                {"torn_bytes_cut", r.torn_bytes_cut},
                {"complete", log_ok && log.events_lost() == 0 && log.events_not_durable() == 0}};
    if (!r.rotated_to.empty()) s["log"]["rotated_to"] = r.rotated_to;
    if (!log.error().empty()) s["log"]["last_error"] = log.error();
    if (!log_ok) {
      err << kPrefix << "warning: --log " << options::quoted(*config.log_path) << ": the final write failed ("
          << log.error() << ")\n";
    }
  }
  s["run_time_s"] = run_time_s;
  if (forecaster) s["forecast"] = forecast_summary(config.forecast, forecaster->counters());
  out << json{{"summary", s}}.dump() << '\n' << std::flush;
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f", run_time_s);
  human_summary(err, "stopped by " + s["stopped_by"].get<std::string>() + " after " + seconds + " s", walls, statuses);
  if (forecaster) forecast_human_summary(err, forecaster->counters());
  if (config.log_path) {
    err << "  log: " << log.events_written() << " events written to " << options::quoted(*config.log_path) << ", "
        << log.events_lost() << " lost in " << log.write_failures() << " failed writes\n";
  }
  return failed ? kExitRuntime : kExitOk;
}

// ---------------------------------------------------------------------------------------------------------------
// Offline: an LCM log in, an LCM log out, in log time.

int run_offline(const MonitorConfig& config, std::ostream& out, std::ostream& err) {
  const std::string& in_path = *config.offline_in;
  const std::string& out_path = *config.offline_out;
  struct stat in_stat {};
  if (stat(in_path.c_str(), &in_stat) != 0) {
    err << kPrefix << "error: --offline-in " << options::quoted(in_path) << ": " << std::strerror(errno) << '\n';
    return kExitUsage;
  }
  if (!S_ISREG(in_stat.st_mode)) {
    err << kPrefix << "error: --offline-in " << options::quoted(in_path) << ": not a regular file\n";
    return kExitUsage;
  }
  LcmLogReader in;
  if (!in.open(in_path)) {
    err << kPrefix << "error: --offline-in " << options::quoted(in_path) << ": cannot open the log (" << in.error()
        << ")\n";
    return kExitUsage;
  }
  const LcmLogReader::Event* event = in.next();
  if (event == nullptr && in_stat.st_size > 0) {
    err << kPrefix << "error: --offline-in " << options::quoted(in_path) << ": not an LCM log (no event found in "
        << in_stat.st_size << " bytes)\n";
    return kExitUsage;
  }
  lcm::LogFile log_out(out_path, "w");
  if (!log_out.good()) {
    err << kPrefix << "error: --offline-out " << options::quoted(out_path) << ": cannot create the log ("
        << std::strerror(errno) << ")\n";
    return kExitUsage;
  }
  LogTransport transport(log_out);
  // --forecast: run in log time, synchronously, every 1/rate s (deterministic; compute_us 0).
  std::unique_ptr<ForecastFeed> feed;
  std::unique_ptr<FeedTransport> feed_transport;
  if (config.forecast.enabled) {
    feed = std::make_unique<ForecastFeed>(config.settings.channels, config.settings.engine.observer_enabled);
    feed_transport = std::make_unique<FeedTransport>(transport, *feed);
  }
  MonitorWalls walls;
  firmware::Transport& loop_transport = feed_transport ? static_cast<firmware::Transport&>(*feed_transport)
                                                      : static_cast<firmware::Transport&>(transport);
  if (!init_loop(walls, config, loop_transport, out, err)) return kExitUsage;
  firmware::MultiWallMonitor* const loop = walls.monitor.get();
  // No step clock: worst_step_ns would make the output depend on the machine.
  std::unique_ptr<MonitorForecaster> forecaster;
  if (config.forecast.enabled) {
    forecaster = std::make_unique<MonitorForecaster>(config.forecast, config.settings, *feed, false);
  }
  const auto forecast_period_us = static_cast<std::int64_t>(std::llround(1e6 / config.forecast.rate_hz));
  std::int64_t next_forecast_us = 0;
  std::vector<std::uint8_t> forecast_bytes;

  constexpr std::int64_t kSecondUs = 1000000;
  std::int64_t statuses = 0, events = 0, fed = 0, skipped = 0;
  std::int64_t next_status_us = 0, last_us = 0;
  const auto status_at = [&](std::int64_t utime) {
    transport.set_event_time(utime);
    loop->publish_status(utime);
    ++statuses;
  };
  // The reader stops at the end of the file or at an event it cannot read (a log cut off while being written): the
  // position after the last event read tells them apart.
  std::int64_t read_end = in.read_end();
  for (; event != nullptr && !StopSignals::stopped(); event = in.next()) {
    const std::int64_t ts = event->utime;
    if (events == 0) {
      status_at(ts);
      next_status_us = ts + kSecondUs;
    }
    // A status at every whole second of log time after the first event; one for a gap of a minute or more.
    while (ts >= next_status_us) {
      if (ts - next_status_us >= 60 * kSecondUs) next_status_us += (ts - next_status_us) / kSecondUs * kSecondUs;
      status_at(next_status_us);
      next_status_us += kSecondUs;
    }
    ++events;
    last_us = ts;
    if (forecaster) {
      // The forecasts due before this event, in log time, from what the loop had done by then.
      if (next_forecast_us == 0) next_forecast_us = ts + forecast_period_us;
      for (; ts >= next_forecast_us; next_forecast_us += forecast_period_us) {
        transport.set_event_time(next_forecast_us);
        const std::size_t n = encode_forecast(forecaster->run_once(), forecast_bytes);
        forecaster->note_publish(n > 0 && transport.publish(config.forecast.channel.c_str(), forecast_bytes.data(), n));
        if (ts - next_forecast_us >= 60 * kSecondUs) {  // a gap of a minute or more: one forecast for it
          next_forecast_us += (ts - next_forecast_us) / forecast_period_us * forecast_period_us;
        }
      }
    }
    if (loop->reads(event->channel.c_str())) {
      transport.set_event_time(ts);
      const std::size_t size = event->data.size();
      if (feed) feed->on_input(event->channel.c_str(), event->data.data(), size);
      loop->on_message(event->channel.c_str(), event->data.data(), size, ts);
      ++fed;
    } else {
      ++skipped;  // as live: the monitor subscribes to its input channels only
    }
    read_end = in.read_end();
  }
  if (events > 0) {
    transport.set_event_time(last_us);
    loop->finish_pending();
    status_at(last_us);
  }

  bool complete = true;
  if (!StopSignals::stopped() && read_end >= 0 && read_end < in_stat.st_size) {
    complete = false;
    err << kPrefix << "warning: --offline-in " << options::quoted(in_path) << ": the log ends with an unreadable or "
        << "truncated event (events end at byte " << read_end << " of " << in_stat.st_size << "); " << events
        << " events processed\n";
  }
  bool write_ok = transport.write_failures() == 0;
  if (FILE* f = log_out.getFilePtr(); f != nullptr) write_ok = std::fflush(f) == 0 && std::ferror(f) == 0 && write_ok;

  json s = common_summary(config, walls, statuses);
  s["mode"] = "offline";
  s["stopped_by"] = StopSignals::stopped() ? StopSignals::stopped_by() : std::string("end of log");
  s["input_log"] = in_path;
  s["output_log"] = out_path;
  s["log_events"] = events;
  s["log_events_fed"] = fed;
  s["log_events_skipped"] = skipped;
  s["output_events"] = transport.events_written();
  s["input_log_complete"] = complete;
  if (!complete) s["input_log_read_bytes"] = read_end;
  if (forecaster) s["forecast"] = forecast_summary(config.forecast, forecaster->counters());
  out << json{{"summary", s}}.dump() << '\n' << std::flush;
  human_summary(err,
                "offline: " + std::to_string(events) + " log events (" + std::to_string(fed) + " on the input channels) -> " +
                    std::to_string(transport.events_written()) + " events in " + out_path +
                    (StopSignals::stopped() ? "; stopped by " + StopSignals::stopped_by() : std::string()),
                walls, statuses);
  if (forecaster) forecast_human_summary(err, forecaster->counters());
  if (!write_ok) {
    err << kPrefix << "error: --offline-out " << options::quoted(out_path) << ": " << transport.write_failures()
        << " events could not be written\n";
    return kExitRuntime;
  }
  return kExitOk;
}

}  // namespace

int run_monitor(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  std::optional<MonitorConfig> config;
  try {
    MonitorParse parse = parse_monitor_arguments(argc, argv);
    if (!parse.config) {
      out << parse.text << std::flush;
      return kExitOk;
    }
    config = std::move(parse.config);
  } catch (const options::UsageError& e) {
    err << kPrefix << "error: " << e.what() << '\n';
    return kExitUsage;
  }
  {
    // Every setting is checked before anything is opened: the engine's formats refuse some walls and rates.
    NullTransport null_transport;
    MonitorWalls probe;
    if (!init_loop(probe, *config, null_transport, err, err)) return kExitUsage;
  }
  if (config->print_config) {
    json j{{"settings", config->normalised},
           {"config_digest", digest_hex(config->settings.config_digest)},
           {"wall", config->wall_origin},
           {"lcm_url", config->lcm_url},
           {"lcm_url_origin", config->lcm_url_origin}};
    // The worst call of the firmware's engine on paper at the configured rate (core::worst_call_bound; docs/
    // FIXED_POINT.md "The worst call on paper"): what the fixed-point engine does per call on the wall's Cortex-M4
    // with the firmware's work budget, with the observer as configured. Not part of the settings (nor the digest).
    if (config->settings.arithmetic == core::MonitorArithmetic::fixed_point) {
      core::WallEngineConfig e = config->settings.engine;
      e.dt_s = 1.0 / config->settings.sample_rate_hz;
      if (e.work_budget_units == 0) e.work_budget_units = core::kDefaultWorkBudgetUnits;  // the firmware's
      const core::WorstCallBound b = core::worst_call_bound(e);
      j["worst_call"] = {{"observer", e.observer_enabled},
                         {"work_overflow", options::work_overflow_name(e.work_overflow)},
                         {"substeps", b.substeps},
                         {"segments_per_substep", b.segments_per_substep},
                         {"sensor_samples_per_sample", b.updates_per_sample},
                         {"budget_units", b.budget_units},
                         {"overrun_units", b.overrun_units},
                         {"overhead_units", b.overhead_units},
                         {"bound_m4_instructions", b.bound_units},
                         {"estimator_share_m4_instructions", e.observer_enabled ? json(b.share_units) : json(nullptr)}};
    }
    const TimingSettings& t = config->timing;
    if (t.any()) {
      j["timing"] = {{"realtime_priority", t.priority > 0 ? json(t.priority) : json(nullptr)},
                     {"cpu", t.cpu >= 0 ? json(t.cpu) : json(nullptr)},
                     {"busy_poll_us", t.busy_poll_us > 0 ? json(t.busy_poll_us) : json(nullptr)}};
    }
    out << j.dump() << '\n' << std::flush;
    return kExitOk;
  }
  const StopSignals signals;
  return config->offline_in ? run_offline(*config, out, err) : run_live(*config, out, err);
}

}  // namespace rockwatch::monitor
