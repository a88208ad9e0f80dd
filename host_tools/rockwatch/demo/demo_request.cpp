#include "demo/demo_request.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "common/replay_out/lcm_multicast.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "common/records_in/shipped_suite.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_file.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace demo_request {

constexpr double kMaxDemoSpeed = 20.0;
constexpr double kMinDemoSpeed = 0.01;
// rockwatch-monitor's range (host_tools/monitor/monitor_config.cpp: a sample period of at most 0.03 s, up to 10 kHz): a
// rate outside it would only fail once the monitor starts.
constexpr double kMinDemoRateHz = 1.0 / 0.03;
// A PGA above this many g is no earthquake.
constexpr double kMaxDemoPga_g = 10.0;

struct RawOptions {
  std::string suite, set, pga, rate, speed, lcm_url, monitor, out, dashboard_http, dashboard_hold, monitor_config,
      wall_file;
  bool dashboard = false;
};

constexpr double kMaxDashboardHold_s = 24.0 * 3600.0;

const char* const kFooter =
    "What it does:\n"
    "  1. checks that LCM multicast works on this machine (a probe message sent and received within 1 s); if not,\n"
    "     it says what to do and exits with 2;\n"
    "  2. for component Y, then X, of suite set --set scaled to --pga (the shipped suite: Y collapses the paper's\n"
    "     wall at 0.25 g, X does not): starts rockwatch-monitor (a fresh one per record), replays the record to it\n"
    "     over LCM as `rockwatch replay` does (ground_accel_t at --rate, absolute deadlines), stops it and collects\n"
    "     the alarm transitions it printed;\n"
    "  3. runs the same samples offline through the fixed-point engine (`rockwatch simulate --arith fixed\n"
    "     --alarms`) and prints both timelines side by side: they match when they have the same transitions, each\n"
    "     in the same sample or the next (the offline COLLAPSED time is located inside the sample interval);\n"
    "  4. two instrumented walls, with a displacement transducer the monitor fuses (--observer): component X on a\n"
    "     wall whose real r is r_ana (the monitor assumes r_exp), and component Y at 0.72 x --pga on a wall 10 %\n"
    "     thinner than the monitor is told (it estimates the capacity as the wall rocks).\n"
    "\n"
    "--speed above about 4 can lose datagrams on a busy machine (the socket buffers fill); the demo then reports\n"
    "how many samples the monitor received, and the timelines may differ where the monitor bridged the gap.\n"
    "\n"
    "The monitor is $ROCKWATCH_MONITOR, else rockwatch-monitor next to this rockwatch executable (--monitor overrides\n"
    "both). It runs with --lcm-url, --rate, the paper wall, --r exp (or --wall-file), --kappa 2 and the default alarm\n"
    "settings.\n"
    "\n"
    "--dashboard starts `rockwatch dashboard` (this executable) on --dashboard-http before the first record and\n"
    "prints its URL: open it in a browser to watch the wall's level, x(t), energy and transitions live as each\n"
    "record is replayed (each record has a fresh monitor: the page starts the wall afresh). It stops with the demo,\n"
    "or --dashboard-hold S seconds later.\n"
    "\n"
    "Exit status: 0 the monitor's timelines match the offline ones, 1 they do not (or the monitor failed),\n"
    "2 invalid options, no multicast, or no monitor; 130 interrupted.\n"
    "\n"
    "Examples:\n"
    "  rockwatch demo\n"
    "  rockwatch demo --speed 4 --out demo-run\n"
    "  rockwatch demo --dashboard --dashboard-hold 60\n";

void add_options(CLI::App& app, RawOptions& raw) {
  app.add_option("--suite", raw.suite, "Suite directory (default: the shipped npr9998-2015 suite)")->type_name("DIR");
  app.add_option("--set", raw.set, "Record set of the suite (default 3)")->type_name("N");
  app.add_option("--pga", raw.pga, "Scale each record to peak |u''| = G*g (default 0.25)")->type_name("G");
  app.add_option("--rate", raw.rate, "Sample rate of the replay and the monitor (default 200)")->type_name("HZ");
  app.add_option("--speed", raw.speed, "Replay speed: 1 real time (default), 4 four times as fast")->type_name("X");
  app.add_option("--lcm-url", raw.lcm_url, std::string("LCM URL (default ") + kDefaultLcmUrl + ")")->type_name("URL");
  app.add_option("--monitor", raw.monitor, "The rockwatch-monitor executable")->type_name("PATH");
  app.add_option("--out", raw.out, "Keep each record's samples, monitor output and timelines in DIR")->type_name("DIR");
  app.add_flag("--dashboard", raw.dashboard, "Serve the live dashboard (rockwatch dashboard) during the demo");
  app.add_option("--dashboard-http", raw.dashboard_http,
                 "With --dashboard: its ADDR:PORT (default 127.0.0.1:8080; port 0: any free port)")
      ->type_name("ADDR:PORT");
  app.add_option("--dashboard-hold", raw.dashboard_hold,
                 "With --dashboard: keep it serving S seconds after the demo (default 0)")
      ->type_name("S");
  app.add_option("--monitor-config", raw.monitor_config,
                 "The monitor's --config, e.g. with a walls array (one monitor, many walls on the demo's ground "
                 "motion): the transitions compared are those of the wall named \"wall\" (the paper wall, unsuffixed "
                 "channels), the summary lists every wall's highest level")
      ->type_name("FILE");
  app.add_option("--wall-file", raw.wall_file,
                 "The wall (and r) of the monitor and the offline runs, from a wall file (rockwatch identify "
                 "--wall-out; default: the paper wall, r exp)")
      ->type_name("FILE.json");
  app.footer(kFooter);
}

}  // namespace demo_request
}  // namespace

DemoParse parse_demo_arguments(int argc, const char* const* argv) {
  using namespace demo_request;
  CLI::App app{
      "The main job: rockwatch-monitor watching the paper's wall live over LCM while two suite records are "
      "replayed to it, one that collapses the wall and one it survives; its alarm timeline beside the "
      "offline simulation of the same samples.",
      "rockwatch demo"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "demo")) {
    return DemoParse{std::nullopt, std::move(*help)};
  }
  DemoRequest q;
  if (given(app, "--wall-file")) {
    if (raw.wall_file.empty()) throw UsageError("--wall-file needs a file name");
    const options::WallFile file = options::read_wall_file("--wall-file", raw.wall_file);
    q.wall_file = raw.wall_file;
    q.wall = file.wall;
    q.restitution.kind = core::RestitutionKind::value;
    q.restitution.value = file.r;
  }
  if (given(app, "--suite")) {
    if (raw.suite.empty()) throw UsageError("--suite needs a suite directory");
    check_input_directory("--suite", raw.suite, "a suite directory written by rockwatch generate");
    q.suite_dir = raw.suite;
    q.suite_found_by = "--suite";
  } else {
    const SuiteLocation shipped = find_shipped_suite();
    q.suite_dir = shipped.dir;
    q.suite_found_by = shipped.found_by;
  }
  if (given(app, "--set")) {
    const std::optional<std::uint64_t> set = whole_number(raw.set, 1, 100);
    if (!set)
      throw UsageError("--set must be a whole number from 1 to 100, a set of the suite (got " + options::quoted(raw.set) +
                       ")");
    q.set = static_cast<int>(*set);
  }
  if (given(app, "--pga")) {
    q.pga_g = parse_positive_number("--pga", raw.pga, " (a multiple of g)");
    if (q.pga_g > kMaxDemoPga_g) {
      throw UsageError("--pga must be at most " + number_text(kMaxDemoPga_g) + " g (got " + number_text(q.pga_g) + ")");
    }
  }
  if (given(app, "--rate")) {
    q.rate_hz = parse_positive_number("--rate", raw.rate, " Hz");
    if (q.rate_hz > kMaxReplayRateHz || !(1.0 / q.rate_hz <= 0.03)) {
      throw UsageError("--rate must be from " + number_text(std::ceil(kMinDemoRateHz * 100.0) / 100.0) + " to " +
                       number_text(kMaxReplayRateHz) +
                       " Hz, the monitor's range (a sample period of at most 0.03 s; got " + number_text(q.rate_hz) +
                       ")");
    }
  }
  if (given(app, "--speed")) {
    q.speed = parse_positive_number("--speed", raw.speed, " (1 real time, 4 four times as fast)");
    if (q.speed < kMinDemoSpeed) {
      throw UsageError("--speed must be at least " + number_text(kMinDemoSpeed) +
                       ": slower, the two records would take hours to replay (got " + number_text(q.speed) + ")");
    }
    if (q.speed > kMaxDemoSpeed) {
      throw UsageError("--speed must be at most " + number_text(kMaxDemoSpeed) +
                       ": faster, datagrams get lost on a busy machine and the comparison tests the network, not the "
                       "monitor (got " +
                       number_text(q.speed) + ")");
    }
  }
  q.lcm_url = kDefaultLcmUrl;
  if (given(app, "--lcm-url")) {
    if (raw.lcm_url.rfind("udpm://", 0) != 0) {
      throw UsageError(
          "--lcm-url must be a UDP multicast URL udpm://GROUP:PORT?ttl=0, which the monitor, another "
          "process, can receive (got " +
          options::quoted(raw.lcm_url) + "; default " + kDefaultLcmUrl + ")");
    }
    q.lcm_url = raw.lcm_url;
  }
  if (given(app, "--monitor")) {
    if (raw.monitor.empty()) throw UsageError("--monitor needs the path of rockwatch-monitor");
    q.monitor = raw.monitor;
  }
  if (given(app, "--out")) {
    if (raw.out.empty()) throw UsageError("--out needs a directory");
    q.out_dir = raw.out;
  }
  q.dashboard = raw.dashboard;
  for (const char* option : {"--dashboard-http", "--dashboard-hold"}) {
    if (given(app, option) && !q.dashboard) throw UsageError(std::string(option) + " needs --dashboard");
  }
  if (given(app, "--dashboard-http")) {
    if (raw.dashboard_http.empty()) throw UsageError("--dashboard-http needs ADDR:PORT, e.g. 127.0.0.1:8080");
    q.dashboard_http = raw.dashboard_http;  // `rockwatch dashboard --http` checks it, and the demo reports its message
  }
  if (given(app, "--dashboard-hold")) {
    q.dashboard_hold_s = parse_finite_number("--dashboard-hold", raw.dashboard_hold);
    if (q.dashboard_hold_s < 0.0 || q.dashboard_hold_s > kMaxDashboardHold_s) {
      throw UsageError("--dashboard-hold must be from 0 to " + number_text(kMaxDashboardHold_s) + " s (got " +
                       number_text(q.dashboard_hold_s) + ")");
    }
  }
  if (given(app, "--monitor-config")) {
    check_input_file("--monitor-config", raw.monitor_config, "a rockwatch-monitor JSON configuration");
    q.monitor_config = raw.monitor_config;
  }
  return DemoParse{q, {}};
}

}  // namespace rockwatch::cli
