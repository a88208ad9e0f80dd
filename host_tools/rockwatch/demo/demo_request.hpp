// What `rockwatch demo` was asked to do: which suite records, how fast, over which LCM URL, which monitor.
#pragma once

#include <optional>
#include <string>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"

namespace rockwatch::cli {

struct DemoRequest {
  std::string suite_dir;               // --suite, else the shipped suite
  std::string suite_found_by;          // "--suite", "$ROCKWATCH_SUITE_DIR", ...
  int set = 3;                         // --set: component Y of it collapses the paper wall at 0.25 g, X does not
  double pga_g = 0.25;                 // --pga
  double rate_hz = 200.0;              // --rate: the monitor's and the replay's
  double speed = 1.0;                  // --speed: 1 real time; > 0
  std::string lcm_url;                 // --lcm-url
  std::optional<std::string> monitor;  // --monitor PATH
  std::optional<std::string> monitor_config;  // --monitor-config FILE: the monitor's --config (e.g. a walls array)
  std::optional<std::string> out_dir;  // --out DIR: keep the samples and the monitor's output there
  bool dashboard = false;              // --dashboard: run `rockwatch dashboard` during the demo
  std::string dashboard_http = "127.0.0.1:8080";  // --dashboard-http ADDR:PORT
  double dashboard_hold_s = 0.0;       // --dashboard-hold S: keep it serving this long after the demo
  // --wall-file FILE.json: the monitor's wall and r (and the offline runs'), e.g. from `rockwatch identify`; none: the
  // paper wall with r_exp.
  std::optional<std::string> wall_file;
  core::WallParameters wall = core::paper_wall();
  core::Restitution restitution{};     // r_exp unless the wall file gives r
};

struct DemoParse {
  std::optional<DemoRequest> request;  // empty for --help
  std::string help_text;
};

// Throws UsageError naming the option at fault.
DemoParse parse_demo_arguments(int argc, const char* const* argv);

}  // namespace rockwatch::cli
