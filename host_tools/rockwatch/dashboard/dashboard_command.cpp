// `rockwatch dashboard`: the live web page of the monitor. Three threads: LCM receive (dashboard_receiver) -> the
// snapshot store (dashboard_store) -> the HTTP/WebSocket server (dashboard_server); this one waits for SIGINT,
// SIGTERM or --duration, then stops them and prints what was served.
#include <chrono>
#include <iostream>
#include <string>
#include <thread>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/signal_interrupt.hpp"
#include "dashboard/dashboard_assets.hpp"
#include "dashboard/dashboard_receiver.hpp"
#include "dashboard/dashboard_request.hpp"
#include "dashboard/dashboard_server.hpp"
#include "dashboard/dashboard_store.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kDashboardErrors{"rockwatch dashboard: error: ", "out of memory"};

std::string url_host(const std::string& address) {
  return address.find(':') != std::string::npos ? "[" + address + "]" : address;
}

int run_dashboard(const DashboardRequest& q) {
  for (const EmbeddedAsset* a = embedded_dashboard_assets(); a->path != nullptr; ++a) {
    if (!a->present) {
      std::cerr << "rockwatch dashboard: warning: " << a->source
                << " was missing when rockwatch was built: the page shows the values without the charts (run "
                   "scripts/install-deps.sh, which runs `npm ci`, then rebuild)\n";
    }
  }
  StoreSettings settings;
  settings.limits = q.limits;
  SnapshotStore store(settings);
  ServerSettings server_settings;
  server_settings.address = q.address;
  server_settings.port = q.port;
  server_settings.loopback_only = !q.allow_remote;
  DashboardServer server(store, embedded_dashboard_assets(), server_settings);
  LcmReceiver receiver(q.lcm_url, q.channels, store);
  const SignalInterrupt interrupt;
  receiver.start();
  server.start();
  const std::string url = "http://" + url_host(q.address) + ":" + std::to_string(server.port()) + "/";
  std::cout << "rockwatch dashboard: serving on " << url << "\n"
            << "  LCM " << q.lcm_url << ": walls from " << q.channels.state << "[_NAME], " << q.channels.alarm
            << "[_NAME], " << q.channels.status << "[_NAME], " << q.channels.sensor << "[_NAME], "
            << q.channels.estimate << "[_NAME], " << q.channels.forecast << "[_NAME]\n"
            << "  limits drawn: " << q.wall_text << "\n"
            << "  open " << url << " in a browser; JSON at " << url << "api/state; Ctrl-C stops\n"
            << std::flush;
  const auto start = std::chrono::steady_clock::now();
  bool lcm_failed = false;
  while (!interrupt.interrupted()) {
    if (receiver.failed()) {
      lcm_failed = true;
      break;
    }
    if (q.duration_s > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= q.duration_s) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  server.stop();
  receiver.stop();
  const nlohmann::json c = server.counters();
  std::cout << "rockwatch dashboard: stopped"
            << (lcm_failed ? " (LCM failed)" : interrupt.interrupted() ? " by a signal" : " (--duration)") << "; "
            << store.wall_count() << " walls, " << c["http_requests"] << " HTTP requests (" << c["http_errors"]
            << " refused as bad), " << c["ws_clients_total"] << " live pages, " << c["ws_messages_sent"]
            << " updates sent, " << c["ws_messages_dropped"] << " dropped for slow pages\n";
  if (lcm_failed) {
    return fail(kDashboardErrors, "LCM stopped receiving on " + q.lcm_url + ": the page would show stale values",
                kExitInternalError);
  }
  return finish_stdout(kDashboardErrors);
}

}  // namespace

int dashboard_main(int argc, const char* const* argv) {
  return run_command(kDashboardErrors, [&] {
    const DashboardParse parsed = parse_dashboard_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run_dashboard(*parsed.request);
  });
}

}  // namespace rockwatch::cli
