#include "dashboard/dashboard_http.hpp"

#include <string>

namespace rockwatch::cli {

namespace {

HttpReply error_reply(int status, const std::string& message) {
  HttpReply r;
  r.status = status;
  r.content_type = "text/plain; charset=utf-8";
  r.body = message + "\n";
  return r;
}

std::string with_charset(const char* type) {
  const std::string t = type;
  return t.rfind("text/", 0) == 0 || t == "application/json" ? t + "; charset=utf-8" : t;
}

// The host part of a Host header value: "127.0.0.1:8080" -> "127.0.0.1", "[::1]:8080" -> "::1".
std::string host_name_of(const std::string& host) {
  if (!host.empty() && host.front() == '[') {
    const std::size_t close = host.find(']');
    return close == std::string::npos ? host : host.substr(1, close - 1);
  }
  const std::size_t colon = host.rfind(':');
  return colon == std::string::npos ? host : host.substr(0, colon);
}

bool is_path_char(char c) {
  // RFC 3986 pchar, '/', '?' and '%' (escapes are not decoded: no embedded file has one in its name).
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
         std::string("-._~!$&'()*+,;=:@/?%").find(c) != std::string::npos;
}

}  // namespace

bool is_loopback_host(const std::string& host) {
  if (host == "localhost" || host == "::1") return true;
  // 127.x.y.z, every part a number of 1 to 3 digits.
  if (host.rfind("127.", 0) != 0) return false;
  int dots = 0, digits = 0;
  for (std::size_t i = 4; i < host.size(); ++i) {
    if (host[i] == '.') {
      if (digits == 0) return false;
      ++dots;
      digits = 0;
    } else if (host[i] >= '0' && host[i] <= '9' && digits < 3) {
      ++digits;
    } else {
      return false;
    }
  }
  return dots == 2 && digits > 0;
}

HttpReply bad_request_reply(const std::string& why, int status) { return error_reply(status, "bad request: " + why); }

HttpReply route_request(const std::string& method, const std::string& target, const std::string& host,
                        bool websocket_upgrade, const RouteContext& context) {
  if (target.empty() || target.front() != '/' || target.size() > kMaxTargetLength) {
    return error_reply(400, "bad request: the target must be a path starting with / of at most " +
                                std::to_string(kMaxTargetLength) + " characters");
  }
  for (const char c : target) {
    if (!is_path_char(c)) return error_reply(400, "bad request: the target has a character not allowed in a path");
  }
  if (context.loopback_only && !host.empty() && !is_loopback_host(host_name_of(host))) {
    return error_reply(421, "misdirected request: this dashboard answers only to a loopback Host "
                            "(127.0.0.1, localhost, [::1]); start it with --allow-remote to serve other names");
  }
  const std::string path = target.substr(0, target.find('?'));
  if (method != "GET" && method != "HEAD") {
    HttpReply r = error_reply(405, "method not allowed: the dashboard only answers GET and HEAD");
    r.headers.emplace_back("Allow", "GET, HEAD");
    return r;
  }
  if (path == "/ws") {
    if (!websocket_upgrade || method != "GET") {
      HttpReply r = error_reply(426, "upgrade required: /ws is a WebSocket (the page connects to it)");
      r.headers.emplace_back("Upgrade", "websocket");
      return r;
    }
    HttpReply r;
    r.status = 101;
    r.upgrade = true;
    return r;
  }
  if (path == "/api/state") {
    HttpReply r;
    r.content_type = "application/json; charset=utf-8";
    r.body = context.state_json ? context.state_json() : "{}";
    r.headers.emplace_back("Cache-Control", "no-store");
    return r;
  }
  const std::string file = path == "/" ? "/index.html" : path;
  for (const EmbeddedAsset* a = context.assets; a != nullptr && a->path != nullptr; ++a) {
    if (file != a->path) continue;
    if (!a->present) {
      return error_reply(404, std::string("not found: ") + a->source +
                                  " was missing when rockwatch was built (run scripts/install-deps.sh, which runs "
                                  "`npm ci`, then rebuild)");
    }
    HttpReply r;
    r.content_type = with_charset(a->content_type);
    r.body.assign(reinterpret_cast<const char*>(a->bytes), a->size);
    r.headers.emplace_back("Cache-Control", "no-cache");
    return r;
  }
  return error_reply(404, "not found: " + path + " (the dashboard serves /, /api/state and /ws)");
}

}  // namespace rockwatch::cli
