#include "dashboard/dashboard_request.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "common/replay_out/lcm_multicast.hpp"
#include "dashboard/dashboard_http.hpp"
#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace dashboard_request {

constexpr double kMaxDashboardDuration_s = 7.0 * 24.0 * 3600.0;

struct DashboardRawOptions {
  std::string lcm_url, http, state, alarm, status, sensor, estimate, forecast, kappa, model, lambda_w, margin, duration;
  bool allow_remote = false;
  WallOptionTexts wall;
};

const char* const kDashboardFooter =
    "What it serves (open the first URL it prints in a browser; no internet needed):\n"
    "  /            the live page: per wall the alarm level as a coloured banner, x(t) over the last 30 s (the\n"
    "               monitor's state, and the wall sensor's measured x when there is one) with +-x_inst, the\n"
    "               warning threshold and the collapse limit, E/E_barrier with the barrier and the energy margin,\n"
    "               the predicted time to instability, the alarm transitions and the monitor's status counters\n"
    "  /api/state   one JSON snapshot: walls[] with name, level, x_m, xd_mps, energy_ratio, t_to_instability_s,\n"
    "               transitions (the last 50), status, points ([id, t_s, x_m, energy_ratio]), measured, limits\n"
    "  /ws          a WebSocket: the snapshot, then updates, at most 30 per second per wall\n"
    "\n"
    "Walls are found from the channel names: the monitor's wall_state_t on STATE (the --state-channel base) is wall\n"
    "\"wall\", on STATE_NAME wall NAME (a many-wall monitor); likewise for the alarm, status, sensor, estimate and\n"
    "forecast channels. The lines drawn come from the wall options (all walls): give the dashboard the monitor's wall,\n"
    "--kappa, --lambda-w and --energy-margin.\n"
    "\n"
    "It only listens to LCM: the monitor runs in its own process, untouched. It listens on loopback unless\n"
    "--allow-remote is given with another address (the page has no authentication).\n"
    "\n"
    "Exit status: 0 stopped by SIGINT/SIGTERM or --duration, 2 invalid options, LCM or the address unusable,\n"
    "1 LCM failed while receiving.\n"
    "\n"
    "Examples:\n"
    "  rockwatch dashboard\n"
    "  rockwatch dashboard --http 127.0.0.1:9000 --lcm-url 'udpm://239.255.76.67:7667?ttl=0'\n"
    "  rockwatch dashboard --http 0.0.0.0:8080 --allow-remote\n";

void add_dashboard_options(CLI::App& app, DashboardRawOptions& raw) {
  app.add_option("--lcm-url", raw.lcm_url, std::string("LCM URL (default ") + kDefaultLcmUrl + ")")->type_name("URL");
  app.add_option("--http", raw.http,
                 std::string("Listen on ADDR:PORT (default ") + kDefaultDashboardAddress + ":" +
                     std::to_string(kDefaultDashboardPort) + "; PORT 0: any free port, printed at start)")
      ->type_name("ADDR:PORT");
  app.add_flag("--allow-remote", raw.allow_remote,
               "Allow --http on an address other than loopback (other machines can then read the page)");
  app.add_option("--state-channel", raw.state, "wall_state_t channel base (default ROCKWATCH_WALL_STATE)")
      ->type_name("NAME");
  app.add_option("--alarm-channel", raw.alarm, "alarm_event_t channel base (default ROCKWATCH_ALARM)")
      ->type_name("NAME");
  app.add_option("--status-channel", raw.status, "monitor_status_t channel base (default ROCKWATCH_STATUS)")
      ->type_name("NAME");
  app.add_option("--sensor-channel", raw.sensor, "wall_sensor_t channel base (default ROCKWATCH_WALL_SENSOR)")
      ->type_name("NAME");
  app.add_option("--estimate-channel", raw.estimate,
                 "wall_estimate_t channel base (default ROCKWATCH_WALL_ESTIMATE)")
      ->type_name("NAME");
  app.add_option("--forecast-channel", raw.forecast,
                 "wall_forecast_t channel base (rockwatch-monitor --forecast; default ROCKWATCH_WALL_FORECAST)")
      ->type_name("NAME");
  add_wall_options(app, raw.wall);
  app.add_option("--model", raw.model, "Equation of motion the monitor runs: linear (default) | full")
      ->type_name("linear|full");
  add_kappa_option(app, raw.kappa);
  app.add_option("--lambda-w", raw.lambda_w, "The monitor's warning threshold, a fraction of x_inst (default 0.4)")
      ->type_name("L");
  app.add_option("--energy-margin", raw.margin, "The monitor's energy margin, drawn on E/E_barrier (default 1.5)")
      ->type_name("M");
  app.add_option("--duration", raw.duration, "Stop after S seconds (default: serve until Ctrl-C or SIGTERM)")
      ->type_name("S");
  app.footer(kDashboardFooter);
}

}  // namespace dashboard_request
}  // namespace

void parse_listen_address(const std::string& option, const std::string& text, std::string& address,
                          unsigned short& port) {
  using namespace dashboard_request;
  const std::string expected = " must be ADDR:PORT, e.g. 127.0.0.1:8080 or [::1]:8080 (got " + options::quoted(text) + ")";
  std::string host, port_text;
  if (!text.empty() && text.front() == '[') {
    const std::size_t close = text.find(']');
    if (close == std::string::npos || close + 1 >= text.size() || text[close + 1] != ':')
      throw UsageError(option + expected);
    host = text.substr(1, close - 1);
    port_text = text.substr(close + 2);
  } else {
    const std::size_t colon = text.rfind(':');
    if (colon == std::string::npos || text.find(':') != colon) throw UsageError(option + expected);
    host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
  }
  if (host.empty()) throw UsageError(option + expected);
  const std::optional<std::uint64_t> p = whole_number(port_text, 0, 65535);
  if (!p) throw UsageError(option + ": the port must be a whole number from 0 to 65535 (got " + options::quoted(port_text) + ")");
  address = host == "localhost" ? "127.0.0.1" : host;
  port = static_cast<unsigned short>(*p);
}

DashboardParse parse_dashboard_arguments(int argc, const char* const* argv) {
  using namespace dashboard_request;
  CLI::App app{
      "The live dashboard: a web page showing every wall the monitor watches, as it happens (alarm level, x(t), "
      "E/E_barrier, time to instability, transitions, status), fed by the monitor's LCM messages.",
      "rockwatch dashboard"};
  DashboardRawOptions raw;
  add_dashboard_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "dashboard")) {
    return DashboardParse{std::nullopt, std::move(*help)};
  }
  DashboardRequest q;
  q.lcm_url = kDefaultLcmUrl;
  if (given(app, "--lcm-url")) {
    if (raw.lcm_url.empty()) throw UsageError("--lcm-url needs an LCM URL, e.g. " + std::string(kDefaultLcmUrl));
    q.lcm_url = raw.lcm_url;
  }
  if (given(app, "--http")) parse_listen_address("--http", raw.http, q.address, q.port);
  q.allow_remote = raw.allow_remote;
  if (!is_loopback_host(q.address) && !q.allow_remote) {
    throw UsageError("--http " + raw.http + " is not a loopback address: other machines could read the page, which "
                     "has no authentication; add --allow-remote to mean it (or use 127.0.0.1)");
  }
  const struct {
    const char* option;
    std::string* text;
    std::string* base;
  } channel_options[] = {{"--state-channel", &raw.state, &q.channels.state},
                         {"--alarm-channel", &raw.alarm, &q.channels.alarm},
                         {"--status-channel", &raw.status, &q.channels.status},
                         {"--sensor-channel", &raw.sensor, &q.channels.sensor},
                         {"--estimate-channel", &raw.estimate, &q.channels.estimate},
                         {"--forecast-channel", &raw.forecast, &q.channels.forecast}};
  for (const auto& c : channel_options) {
    if (!given(app, c.option)) continue;
    check_channel_base(c.option, *c.text);
    *c.base = *c.text;
  }
  const WallChoice wall = parse_wall_options(app, raw.wall);
  const core::ModelKind model = given(app, "--model") ? parse_model("--model", raw.model) : core::ModelKind::linear;
  const double kappa = given(app, "--kappa") ? parse_kappa("--kappa", raw.kappa) : default_kappa();
  core::AlarmSettings alarm;
  if (given(app, "--lambda-w")) {
    alarm.lambda_warning = parse_finite_number("--lambda-w", raw.lambda_w);
    check_lambda_w("--lambda-w", alarm.lambda_warning);
  }
  if (given(app, "--energy-margin")) {
    alarm.energy_margin = parse_finite_number("--energy-margin", raw.margin);
    check_energy_margin("--energy-margin", alarm.energy_margin);
  }
  const core::ModelConstants<double> constants = core::model_constants(wall.wall, model);
  for (int i = 0; i < 2; ++i) {
    const core::Side side = i == 0 ? core::Side::negative : core::Side::positive;
    const double x_inst = core::x_inst_m(constants, side, wall.wall.g_mps2);
    if (!std::isfinite(x_inst) || x_inst <= 0.0) {
      throw UsageError("the wall options give no finite x_inst (got " + number_text(x_inst) +
                       " m): check --b, --h1, --h2, --rho, --fp, --g");
    }
    q.limits.x_inst_m[i] = x_inst;
    q.limits.x_collapse_m[i] = kappa * x_inst;
    q.limits.x_warning_m[i] = alarm.lambda_warning * x_inst;
  }
  q.limits.energy_margin = alarm.energy_margin;
  q.wall_text = wall.name + " wall" + (wall.options_given.empty() ? std::string() : " (modified)") + ", " +
                model_name(model) + " model, kappa " + number_text(kappa) + ", x_inst " +
                number_text(q.limits.x_inst_m[1]) + " m";
  if (given(app, "--duration")) {
    q.duration_s = parse_positive_number("--duration", raw.duration, " s");
    if (q.duration_s > kMaxDashboardDuration_s) {
      throw UsageError("--duration must be at most " + number_text(kMaxDashboardDuration_s) +
                       " s, a week (got " + number_text(q.duration_s) + "); leave it out to serve until stopped");
    }
  }
  return DashboardParse{q, {}};
}

}  // namespace rockwatch::cli
