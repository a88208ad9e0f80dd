// The dashboard's request handling: route_request's answers (paths, methods, targets that are not paths, Host
// checks, /ws without an upgrade, assets missing at build time), then the real server on a free loopback port —
// malformed and oversized requests get 4xx and the server goes on; a WebSocket client that stops reading is dropped
// behind (counted, resynchronised) without slowing the other clients.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "dashboard/dashboard_assets.hpp"
#include "dashboard/dashboard_http.hpp"
#include "dashboard/dashboard_request.hpp"
#include "dashboard/dashboard_server.hpp"
#include "dashboard/dashboard_store.hpp"
#include "rockwatch/options/usage_error.hpp"

#include <CppUTest/TestHarness.h>

using rockwatch::cli::EmbeddedAsset;
using rockwatch::cli::HttpReply;
using rockwatch::cli::route_request;
using rockwatch::cli::RouteContext;

namespace {

const unsigned char kPage[] = "<html>page</html>";
const unsigned char kNothing[] = "";
const EmbeddedAsset kTestAssets[] = {
    {"/index.html", "text/html", kPage, sizeof kPage - 1, true, "web/index.html"},
    {"/app.js", "text/javascript", kPage, sizeof kPage - 1, true, "web/app.js"},
    {"/uPlot.iife.min.js", "text/javascript", kNothing, 0, false, "node_modules/uplot/dist/uPlot.iife.min.js"},
    {nullptr, nullptr, nullptr, 0, false, nullptr},
};

RouteContext test_context() {
  RouteContext c;
  c.assets = kTestAssets;
  c.state_json = [] { return std::string(R"({"walls":[]})"); };
  return c;
}

HttpReply get(const std::string& target, const std::string& host = "127.0.0.1:8080") {
  return route_request("GET", target, host, false, test_context());
}

bool has_header(const HttpReply& r, const std::string& name, const std::string& value) {
  for (const auto& [n, v] : r.headers) {
    if (n == name && v == value) return true;
  }
  return false;
}

// A blocking client socket to 127.0.0.1:port with 5-s timeouts; `receive_buffer` > 0 sets SO_RCVBUF first.
int connect_to(unsigned short port, int receive_buffer = 0) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  CHECK(fd >= 0);
  timeval timeout{5, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
  if (receive_buffer > 0) setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  CHECK(connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
  return fd;
}

void send_all(int fd, const std::string& bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;  // the server may close early on a bad request: what it answered is what is checked
    sent += static_cast<std::size_t>(n);
  }
}

// Sends `request` and reads until the server closes (or the timeout).
std::string http_exchange(unsigned short port, const std::string& request) {
  const int fd = connect_to(port);
  send_all(fd, request);
  std::string reply;
  char buffer[4096];
  for (;;) {
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    reply.append(buffer, static_cast<std::size_t>(n));
  }
  close(fd);
  return reply;
}

std::string status_line(const std::string& reply) { return reply.substr(0, reply.find("\r\n")); }

rockwatch::wall_state_t some_state(std::int64_t seq) {
  rockwatch::wall_state_t m{};
  m.utime = 1700000000000000 + seq * 5000;
  m.seq = seq;
  m.x_m = 0.01 * std::sin(0.1 * static_cast<double>(seq));
  m.alarm_level = 1;
  m.t_to_instability_s = -1.0;
  return m;
}

}  // namespace

TEST_GROUP(DashboardRoutes){};

TEST(DashboardRoutes, ThePageTheFilesAndTheState) {
  HttpReply r = get("/");
  CHECK_EQUAL(200, r.status);
  STRCMP_EQUAL("<html>page</html>", r.body.c_str());
  STRCMP_EQUAL("text/html; charset=utf-8", r.content_type.c_str());
  r = get("/app.js?v=2");
  CHECK_EQUAL(200, r.status);
  STRCMP_EQUAL("text/javascript; charset=utf-8", r.content_type.c_str());
  r = get("/api/state");
  CHECK_EQUAL(200, r.status);
  STRCMP_EQUAL(R"({"walls":[]})", r.body.c_str());
  STRCMP_EQUAL("application/json; charset=utf-8", r.content_type.c_str());
  CHECK(has_header(r, "Cache-Control", "no-store"));
  CHECK_EQUAL(200, route_request("HEAD", "/", "localhost:9", false, test_context()).status);
}

TEST(DashboardRoutes, UnknownPathsAre404) {
  for (const char* target : {"/nope", "/index.htm", "/api/state/x", "/../etc/passwd", "/api", "//"}) {
    CHECK_EQUAL_TEXT(404, get(target).status, target);
  }
}

TEST(DashboardRoutes, AFileMissingAtBuildTimeIs404SayingWhatToDo) {
  const HttpReply r = get("/uPlot.iife.min.js");
  CHECK_EQUAL(404, r.status);
  CHECK(r.body.find("node_modules/uplot/dist/uPlot.iife.min.js") != std::string::npos);
  CHECK(r.body.find("npm ci") != std::string::npos);
}

TEST(DashboardRoutes, OtherMethodsAre405WithAllow) {
  for (const char* method : {"POST", "PUT", "DELETE", "PATCH", "OPTIONS", "TRACE", "CONNECT", "BREW"}) {
    const HttpReply r = route_request(method, "/", "127.0.0.1", false, test_context());
    CHECK_EQUAL_TEXT(405, r.status, method);
    CHECK_TEXT(has_header(r, "Allow", "GET, HEAD"), method);
  }
  CHECK_EQUAL(405, route_request("POST", "/api/state", "", false, test_context()).status);
}

TEST(DashboardRoutes, TargetsThatAreNotPathsAre400) {
  const std::string too_long = "/" + std::string(rockwatch::cli::kMaxTargetLength, 'a');
  for (const std::string& target : {std::string(""), std::string("*"), std::string("http://x/"), too_long,
                                     std::string("/a b"), std::string("/\x01"), std::string("/\xff"),
                                     std::string("/a\"b")}) {
    CHECK_EQUAL_TEXT(400, get(target).status, target.c_str());
  }
}

TEST(DashboardRoutes, WebSocketNeedsTheUpgrade) {
  HttpReply r = get("/ws");
  CHECK_EQUAL(426, r.status);
  CHECK_FALSE(r.upgrade);
  r = route_request("GET", "/ws", "127.0.0.1:1", true, test_context());
  CHECK(r.upgrade);
  CHECK_FALSE(route_request("HEAD", "/ws", "127.0.0.1:1", true, test_context()).upgrade);
}

TEST(DashboardRoutes, OnLoopbackOnlyLoopbackHostNamesAreServed) {
  for (const char* host : {"127.0.0.1:8080", "localhost:8080", "[::1]:8080", "127.1.2.3", "localhost", ""}) {
    CHECK_EQUAL_TEXT(200, get("/", host).status, host);
  }
  for (const char* host : {"evil.example:8080", "192.168.1.2:8080", "127.0.0.1.evil.example", "[::2]:80",
                           "127.0.0.1x:8080", "localhost.:8080"}) {
    CHECK_EQUAL_TEXT(421, get("/", host).status, host);
  }
  RouteContext remote = test_context();
  remote.loopback_only = false;
  CHECK_EQUAL(200, route_request("GET", "/", "dashboard.lab:8080", false, remote).status);
}

TEST(DashboardRoutes, ListenAddresses) {
  std::string address;
  unsigned short port = 0;
  rockwatch::cli::parse_listen_address("--http", "127.0.0.1:9000", address, port);
  STRCMP_EQUAL("127.0.0.1", address.c_str());
  CHECK_EQUAL(9000, port);
  rockwatch::cli::parse_listen_address("--http", "localhost:0", address, port);
  STRCMP_EQUAL("127.0.0.1", address.c_str());
  CHECK_EQUAL(0, port);
  rockwatch::cli::parse_listen_address("--http", "[::1]:80", address, port);
  STRCMP_EQUAL("::1", address.c_str());
  for (const char* bad : {"", "8080", "127.0.0.1", ":80", "127.0.0.1:", "127.0.0.1:65536", "127.0.0.1:-1",
                          "127.0.0.1:8e3", "[::1]80", "::1:80"}) {
    CHECK_THROWS(rockwatch::options::UsageError, rockwatch::cli::parse_listen_address("--http", bad, address, port));
  }
}

// The store and the server live in the group, not in the test's frame: a failed CHECK leaves the test body by
// longjmp, which runs no destructors, and a server thread left running would read a dead frame (CI saw exactly that).
// teardown() always runs, and stops the I/O thread before the store goes.
TEST_GROUP(DashboardServer) {
  std::unique_ptr<rockwatch::cli::SnapshotStore> store;
  std::unique_ptr<rockwatch::cli::DashboardServer> server;
  void start(const rockwatch::cli::ServerSettings& settings) {
    store = std::make_unique<rockwatch::cli::SnapshotStore>(rockwatch::cli::StoreSettings{});
    server = std::make_unique<rockwatch::cli::DashboardServer>(*store, rockwatch::cli::embedded_dashboard_assets(),
                                                               settings);
    server->start();
  }
  void teardown() override {
    server.reset();  // joins the I/O thread
    store.reset();
  }
};

TEST(DashboardServer, BadRequestsGet4xxAndTheServerGoesOn) {
  rockwatch::cli::ServerSettings settings;
  settings.port = 0;
  start(settings);
  const unsigned short port = server->port();
  const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
  const struct {
    std::string request;
    const char* status;
  } cases[] = {
      {"GARBAGE\r\n\r\n", "HTTP/1.1 400"},
      {"GET / HTTP/9.9\r\n\r\n", "HTTP/1.1 400"},
      {"GET /\r\n\r\n", "HTTP/1.1 400"},
      {"POST /api/state HTTP/1.1\r\n" + host + "Content-Length: 5\r\nConnection: close\r\n\r\nhello", "HTTP/1.1 4"},
      {"GET / HTTP/1.1\r\n" + host + "X-Big: " + std::string(20000, 'x') + "\r\n\r\n", "HTTP/1.1 413"},
      {"DELETE / HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", "HTTP/1.1 405"},
      {"GET /nope HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", "HTTP/1.1 404"},
      {"GET /ws HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", "HTTP/1.1 426"},
      {"GET / HTTP/1.1\r\nHost: attacker.example\r\nConnection: close\r\n\r\n", "HTTP/1.1 421"},
      {std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03", 11), "HTTP/1.1 400"},  // TLS to a plain port
  };
  for (const auto& c : cases) {
    const std::string reply = http_exchange(port, c.request);
    CHECK_TEXT(reply.rfind(c.status, 0) == 0, (c.request.substr(0, 40) + " -> " + status_line(reply)).c_str());
  }
  // Still serving, the page included, on a kept-alive connection.
  const std::string page = http_exchange(port, "GET / HTTP/1.1\r\n" + host + "\r\nGET /api/state HTTP/1.1\r\n" + host +
                                              "Connection: close\r\n\r\n");
  STRCMP_EQUAL("HTTP/1.1 200 OK", status_line(page).c_str());
  CHECK(page.find("data-testid") != std::string::npos || page.find("<!doctype html>") != std::string::npos);
  CHECK(page.find("\"walls\":[]") != std::string::npos);
  const nlohmann::json counters = server->counters();
  CHECK(counters["http_errors"].get<int>() >= 10);
}

TEST(DashboardServer, ASlowWebSocketClientIsDroppedBehindAndOthersAreServed) {
  rockwatch::cli::ServerSettings settings;
  settings.port = 0;
  settings.ws_queue = 4;
  settings.send_buffer_bytes = 4096;
  start(settings);
  const unsigned short port = server->port();
  // A WebSocket client that completes the handshake and then never reads.
  const int slow = connect_to(port, 2048);
  send_all(slow, "GET /ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                 "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  char head[512];
  const ssize_t n = recv(slow, head, sizeof head - 1, 0);
  CHECK(n > 0);
  head[n > 0 ? n : 0] = '\0';
  CHECK_TEXT(std::string(head).rfind("HTTP/1.1 101", 0) == 0, head);
  // 20 walls at 200 Hz for 2 s of wall-clock time: about 30 updates per second per wall, far more than 2 kB of buffers.
  const auto start = std::chrono::steady_clock::now();
  double worst_state_s = 0.0;
  std::int64_t seq = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(2)) {
    for (int w = 0; w < 20; ++w) store->on_state("w" + std::to_string(w), some_state(seq));
    ++seq;
    if (seq % 100 == 0) {  // a normal client meanwhile: answered at once
      const auto t0 = std::chrono::steady_clock::now();
      const std::string reply = http_exchange(port, "GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
      worst_state_s = std::max(worst_state_s, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      STRCMP_EQUAL("HTTP/1.1 200 OK", status_line(reply).c_str());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const nlohmann::json c = server->counters();
  CHECK_TEXT(c["ws_messages_dropped"].get<std::int64_t>() > 0, c.dump().c_str());
  CHECK_TEXT(c["ws_resyncs"].get<std::int64_t>() > 0, c.dump().c_str());
  CHECK_EQUAL(1, c["ws_clients"].get<int>());
  CHECK_TEXT(worst_state_s < 1.0, std::to_string(worst_state_s).c_str());
  close(slow);
}

TEST(DashboardServer, AnAddressInUseIsAUsageError) {
  rockwatch::cli::SnapshotStore snapshots{rockwatch::cli::StoreSettings{}};
  rockwatch::cli::ServerSettings settings;
  settings.port = 0;
  rockwatch::cli::DashboardServer first(snapshots, rockwatch::cli::embedded_dashboard_assets(), settings);
  settings.port = first.port();
  CHECK_THROWS(rockwatch::options::UsageError,
               rockwatch::cli::DashboardServer(snapshots, rockwatch::cli::embedded_dashboard_assets(), settings));
  settings.address = "not-an-address";
  CHECK_THROWS(rockwatch::options::UsageError,
               rockwatch::cli::DashboardServer(snapshots, rockwatch::cli::embedded_dashboard_assets(), settings));
}
