// What `rockwatch dashboard` was asked to do: where to listen (HTTP), which LCM URL and channels to watch, the wall
// the monitor runs (for the lines drawn at ±x_inst, ±κ·x_inst and the warning threshold) and how long to serve.
#pragma once

#include <optional>
#include <string>

#include "dashboard/dashboard_channels.hpp"
#include "dashboard/dashboard_store.hpp"

namespace rockwatch::cli {

inline constexpr const char* kDefaultDashboardAddress = "127.0.0.1";
inline constexpr unsigned short kDefaultDashboardPort = 8080;

struct DashboardRequest {
  std::string lcm_url;                                 // --lcm-url
  std::string address = kDefaultDashboardAddress;      // --http ADDR:PORT
  unsigned short port = kDefaultDashboardPort;
  bool allow_remote = false;                           // --allow-remote: needed for a non-loopback ADDR
  DashboardChannels channels;                          // --state-channel ...
  WallLimits limits;                                   // --wall, --b ..., --kappa, --lambda-w, --energy-margin
  std::string wall_text;                               // "paper wall, kappa 2" for the start line
  double duration_s = 0.0;                             // --duration: 0 = until SIGINT/SIGTERM
};

struct DashboardParse {
  std::optional<DashboardRequest> request;  // empty for --help
  std::string help_text;
};

// Throws UsageError naming the option at fault.
DashboardParse parse_dashboard_arguments(int argc, const char* const* argv);

// "ADDR:PORT" (ADDR an IPv4 address, "localhost" or [IPv6]; PORT 0 to 65535, 0 = any free port). Throws UsageError
// naming `option`.
void parse_listen_address(const std::string& option, const std::string& text, std::string& address,
                          unsigned short& port);

}  // namespace rockwatch::cli
