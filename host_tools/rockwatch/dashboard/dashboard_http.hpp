// What the dashboard answers to one HTTP request, decided from the method, target and Host header alone (no sockets,
// so the unit tests call it directly): the embedded files at their paths ("/" is the page), GET /api/state, the
// WebSocket upgrade at /ws; 400 for a target that is not a path, 404 for an unknown path, 405 for a method other
// than GET or HEAD, 426 for /ws without an upgrade, 421 for a Host header naming another machine while the server
// listens on loopback (a web page elsewhere cannot reach the dashboard through DNS rebinding).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "dashboard/dashboard_assets.hpp"

namespace rockwatch::cli {

struct HttpReply {
  int status = 200;
  std::string content_type;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // besides Content-Type and Content-Length
  bool upgrade = false;  // accept the WebSocket handshake instead of replying
};

struct RouteContext {
  const EmbeddedAsset* assets = nullptr;       // the table, ended by a null path
  std::function<std::string()> state_json;     // the body of /api/state
  bool loopback_only = true;                   // the server listens on a loopback address: check Host
};

inline constexpr std::size_t kMaxTargetLength = 2048;

// `method` as the request line has it ("GET"), `target` the request target ("/api/state?x"), `host` the Host header
// ("" when there is none), `websocket_upgrade` whether the request asks for a WebSocket.
HttpReply route_request(const std::string& method, const std::string& target, const std::string& host,
                        bool websocket_upgrade, const RouteContext& context);

// The reply to a request that could not be parsed (syntax, header or body too large): 400 or 413.
HttpReply bad_request_reply(const std::string& why, int status = 400);

// True for 127.0.0.0/8, ::1 and "localhost".
bool is_loopback_host(const std::string& host_without_port);

}  // namespace rockwatch::cli
