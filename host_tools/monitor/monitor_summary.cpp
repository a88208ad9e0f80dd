#include "monitor_summary.hpp"

#include <algorithm>

#include "monitor_output.hpp"
#include "monitor_run.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

namespace {

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
  err << kMessagePrefix << first_line << '\n'
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


}  // namespace

void write_summary(std::ostream& out, std::ostream& err, const MonitorConfig& config, MonitorWalls& walls,
                   const SummaryParts& parts) {
  json s = common_summary(config, walls, parts.statuses);
  for (const auto& field : parts.fields.items()) s[field.key()] = field.value();
  s["stopped_by"] = parts.stopped_by;
  if (parts.forecaster != nullptr) s["forecast"] = forecast_summary(config.forecast, parts.forecaster->counters());
  out << json{{"summary", s}}.dump() << '\n' << std::flush;
  human_summary(err, parts.first_line, walls, parts.statuses);
  if (parts.forecaster != nullptr) forecast_human_summary(err, parts.forecaster->counters());
  err << parts.human_tail;
}

}  // namespace rockwatch::monitor
