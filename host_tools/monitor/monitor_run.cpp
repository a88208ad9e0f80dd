// rockwatch-monitor's entry: the settings parsed and checked (every wall started once on a null transport, since
// the engine's formats refuse some walls and rates) before anything is opened, --print-config, then the live or the
// offline run (monitor_modes.hpp) under the stop signals.
#include "monitor_run.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "monitor_config.hpp"
#include "monitor_modes.hpp"
#include "monitor_wall_set.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "stop_signals.hpp"

namespace rockwatch::monitor {

using nlohmann::json;

namespace {

class NullTransport final : public firmware::Transport {
 public:
  bool publish(const char*, const std::uint8_t*, std::size_t) override { return true; }
};

// --print-config: the normalised settings, their digest and origins, the worst call on paper, the timing asked for.
json printed_config(const MonitorConfig& config) {
  json j{{"settings", config.normalised},
         {"config_digest", digest_hex(config.settings.config_digest)},
         {"wall", config.wall_origin},
         {"lcm_url", config.lcm_url},
         {"lcm_url_origin", config.lcm_url_origin}};
  // The worst call of the firmware's engine on paper at the configured rate (core::worst_call_bound; docs/
  // FIXED_POINT.md "The worst call on paper"): what the fixed-point engine does per call on the wall's Cortex-M4
  // with the firmware's work budget, with the observer as configured. Not part of the settings (nor the digest).
  if (config.settings.arithmetic == core::MonitorArithmetic::fixed_point) {
    core::WallEngineConfig e = config.settings.engine;
    e.dt_s = 1.0 / config.settings.sample_rate_hz;
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
  const TimingSettings& t = config.timing;
  if (t.any()) {
    j["timing"] = {{"realtime_priority", t.priority > 0 ? json(t.priority) : json(nullptr)},
                   {"cpu", t.cpu >= 0 ? json(t.cpu) : json(nullptr)},
                   {"busy_poll_us", t.busy_poll_us > 0 ? json(t.busy_poll_us) : json(nullptr)}};
  }
  return j;
}

}  // namespace

int run_monitor(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
                const LiblcmInputFactory* liblcm) {
  std::optional<MonitorConfig> config;
  try {
    MonitorParse parse = parse_monitor_arguments(argc, argv);
    if (!parse.config) {
      out << parse.text << std::flush;
      return kExitOk;
    }
    config = std::move(parse.config);
  } catch (const options::UsageError& e) {
    err << kMessagePrefix << "error: " << e.what() << '\n';
    return kExitUsage;
  }
  {
    // Every setting is checked before anything is opened: the engine's formats refuse some walls and rates.
    NullTransport null_transport;
    MonitorWalls probe;
    if (!init_loop(probe, *config, null_transport, err, err)) return kExitUsage;
  }
  if (config->print_config) {
    out << printed_config(*config).dump() << '\n' << std::flush;
    return kExitOk;
  }
  const StopSignals signals;
  return config->offline_in ? run_offline(*config, out, err) : run_live(*config, liblcm, out, err);
}

}  // namespace rockwatch::monitor
