// The dashboard's HTTP and WebSocket server: Boost.Beast on Boost.Asio, one port, one I/O thread (every connection
// is asynchronous on it, so a slow or vanished browser never blocks another or the LCM receiver).
//
// Bounded whatever the clients do: requests are parsed with a header limit and no body, every read and write has a
// deadline (a silent connection is closed), at most max_connections HTTP connections and max_ws_clients WebSockets
// (more are refused: 503, counted), and each WebSocket client has its own queue of at most ws_queue messages. When a
// client cannot keep up its queued updates are dropped (counted) and replaced by one fresh whole state, so its page
// is correct again as soon as it catches up. The stream: SnapshotStore::take_updates, polled every few milliseconds.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "dashboard/dashboard_assets.hpp"
#include "dashboard/dashboard_store.hpp"

namespace rockwatch::cli {

struct ServerSettings {
  std::string address = "127.0.0.1";
  unsigned short port = 8080;      // 0: any free port (DashboardServer::port() says which)
  bool loopback_only = true;       // check the Host header (dashboard_http.hpp)
  std::size_t max_connections = 128;
  std::size_t max_ws_clients = 64;  // a control room's screens and a few phones (50 measured: docs/BENCHMARKS.md)
  std::size_t ws_queue = 64;       // messages per WebSocket client
  int idle_timeout_s = 30;         // an HTTP connection with no complete request for this long is closed
  int send_buffer_bytes = 0;       // SO_SNDBUF of each connection; 0: the system's (the tests make it small)
};

class DashboardServer {
 public:
  // Binds and listens (nothing is served before start()). Throws UsageError when the address cannot be used.
  DashboardServer(SnapshotStore& store, const EmbeddedAsset* assets, const ServerSettings& settings);
  ~DashboardServer();  // stops
  DashboardServer(const DashboardServer&) = delete;
  DashboardServer& operator=(const DashboardServer&) = delete;

  unsigned short port() const;
  void start();  // the I/O thread
  void stop();   // closes every connection and joins the thread; idempotent

  // {"http_requests", "http_errors", "connections_refused", "ws_clients", "ws_clients_total", "ws_messages_sent",
  //  "ws_messages_dropped", "ws_resyncs"}.
  nlohmann::json counters() const;

  class Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace rockwatch::cli
