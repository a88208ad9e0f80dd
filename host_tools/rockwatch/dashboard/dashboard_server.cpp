#include "dashboard/dashboard_server.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>

#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "dashboard/dashboard_http.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

namespace {

constexpr std::size_t kHeaderLimit = 8192;
constexpr std::size_t kWsReadLimit = 1024;  // the page sends nothing; anything longer is not our page
constexpr auto kPushPeriod = std::chrono::milliseconds(5);

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Every reply: no sniffing, and the page may load only its own files and talk only to this server.
template <class Response>
void add_common_headers(Response& res, const HttpReply& reply) {
  res.set(http::field::server, "rockwatch-dashboard");
  res.set(http::field::content_type, reply.content_type);
  res.set("X-Content-Type-Options", "nosniff");
  res.set("Content-Security-Policy",
          "default-src 'self'; connect-src 'self'; img-src 'self' data:; style-src 'self'; script-src 'self'");
  for (const auto& [name, value] : reply.headers) res.set(name, value);
}

}  // namespace

class WsSession;

class DashboardServer::Impl {
 public:
  Impl(SnapshotStore& store, const EmbeddedAsset* assets, const ServerSettings& settings)
      : store_(store), settings_(settings), acceptor_(io_), timer_(io_) {
    context_.assets = assets;
    context_.loopback_only = settings.loopback_only;
    context_.state_json = [this] { return state_text(false); };
    beast::error_code ec;
    const asio::ip::address address = asio::ip::make_address(settings.address, ec);
    if (ec) throw UsageError("--http: " + settings.address + " is not an IP address (" + ec.message() + ")");
    const tcp::endpoint endpoint(address, settings.port);
    acceptor_.open(endpoint.protocol(), ec);
    if (!ec) acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
    if (!ec) acceptor_.bind(endpoint, ec);
    if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) {
      throw UsageError("--http " + settings.address + ":" + std::to_string(settings.port) + ": cannot listen there (" +
                       ec.message() + ")");
    }
    port_ = acceptor_.local_endpoint().port();
  }

  ~Impl() { stop(); }

  void start() {
    do_accept();
    schedule_push();
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() {
    if (stopped_.exchange(true)) return;
    io_.stop();
    if (thread_.joinable()) thread_.join();
  }

  // /api/state, and the first message of a WebSocket ("type": "state").
  std::string state_text(bool as_message) {
    nlohmann::json j = store_.state_json();
    j["server"] = counters();
    if (as_message) j["type"] = "state";
    return j.dump();
  }

  nlohmann::json counters() const {
    return nlohmann::json{{"http_requests", http_requests_.load()},
                          {"http_errors", http_errors_.load()},
                          {"connections_refused", connections_refused_.load()},
                          {"ws_clients", ws_clients_.load()},
                          {"ws_clients_total", ws_clients_total_.load()},
                          {"ws_messages_sent", ws_messages_sent_.load()},
                          {"ws_messages_dropped", ws_messages_dropped_.load()},
                          {"ws_resyncs", ws_resyncs_.load()}};
  }

  unsigned short port() const { return port_; }

  // Used by the sessions (I/O thread only, except the atomics).
  void join(const std::shared_ptr<WsSession>& s);
  void leave(WsSession* s);
  const RouteContext& context() const { return context_; }
  const ServerSettings& settings() const { return settings_; }

  std::atomic<std::int64_t> http_requests_{0}, http_errors_{0}, connections_refused_{0}, ws_clients_{0},
      ws_clients_total_{0}, ws_messages_sent_{0}, ws_messages_dropped_{0}, ws_resyncs_{0};
  std::atomic<std::int64_t> http_sessions_{0};

 private:
  void do_accept();
  void schedule_push();

  SnapshotStore& store_;
  ServerSettings settings_;
  RouteContext context_;
  asio::io_context io_{1};
  tcp::acceptor acceptor_;
  asio::steady_timer timer_;
  unsigned short port_ = 0;
  std::thread thread_;
  std::atomic<bool> stopped_{false};
  std::set<std::shared_ptr<WsSession>> clients_;
};

// One WebSocket client: its own bounded queue of messages, written one at a time.
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket&& socket, DashboardServer::Impl& server) : ws_(std::move(socket)), server_(server) {}

  template <class Request>
  void run(const Request& req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kWsReadLimit);
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::server, "rockwatch-dashboard"); }));
    ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) { self->on_accept(ec); });
  }

  // Queues one message (shared by every client). A full queue: the queued messages are dropped and replaced by the
  // whole state, which the page applies as it applies the first one.
  void send(const std::shared_ptr<const std::string>& message) {
    if (closed_) return;
    if (queue_.size() >= server_.settings().ws_queue) {
      const std::size_t keep = writing_ ? 1 : 0;  // the message being written stays
      server_.ws_messages_dropped_ += static_cast<std::int64_t>(queue_.size() - keep);
      queue_.resize(keep);
      ++server_.ws_resyncs_;
      queue_.push_back(std::make_shared<const std::string>(server_.state_text(true)));
    } else {
      queue_.push_back(message);
    }
    if (!writing_) do_write();
  }


 private:
  void on_accept(beast::error_code ec) {
    if (ec) return;
    server_.join(shared_from_this());
    send(std::make_shared<const std::string>(server_.state_text(true)));
    do_read();
  }

  void do_read() {
    ws_.async_read(read_buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->closed_ = true;
        self->server_.leave(self.get());
        return;
      }
      self->read_buffer_.consume(self->read_buffer_.size());  // the page sends nothing we need
      self->do_read();
    });
  }

  void do_write() {
    writing_ = true;
    ws_.text(true);
    const std::shared_ptr<const std::string> message = queue_.front();
    ws_.async_write(asio::buffer(*message), [self = shared_from_this(), message](beast::error_code ec, std::size_t) {
      if (ec) {
        self->closed_ = true;
        self->queue_.clear();
        self->writing_ = false;
        self->server_.leave(self.get());
        return;
      }
      ++self->server_.ws_messages_sent_;
      self->queue_.pop_front();
      if (self->queue_.empty()) {
        self->writing_ = false;
      } else {
        self->do_write();
      }
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  DashboardServer::Impl& server_;
  beast::flat_buffer read_buffer_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  bool writing_ = false;
  bool closed_ = false;
};

// One HTTP connection: requests one after the other (keep-alive), until it closes, errs, times out or upgrades.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, DashboardServer::Impl& server) : stream_(std::move(socket)), server_(server) {
    ++server_.http_sessions_;
    if (server_.settings().send_buffer_bytes > 0) {
      beast::error_code ec;  // a refused size leaves the system's, which only changes how soon a client is slow
      stream_.socket().set_option(asio::socket_base::send_buffer_size(server_.settings().send_buffer_bytes), ec);
    }
  }
  ~HttpSession() { --server_.http_sessions_; }

  void run() { do_read(); }

 private:
  void do_read() {
    parser_.emplace();
    parser_->header_limit(kHeaderLimit);
    parser_->body_limit(0);  // GET and HEAD have no body
    stream_.expires_after(std::chrono::seconds(server_.settings().idle_timeout_s));
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == asio::error::operation_aborted ||
        ec == asio::error::connection_reset || ec == asio::error::eof) {
      return close();
    }
    if (ec) {  // a request that is not HTTP, or too large
      ++server_.http_requests_;
      ++server_.http_errors_;
      const bool too_large = ec == http::error::header_limit || ec == http::error::body_limit ||
                             ec == http::error::buffer_overflow;
      return write(bad_request_reply(ec.message(), too_large ? 413 : 400), false, false);
    }
    ++server_.http_requests_;
    const http::request<http::empty_body>& req = parser_->get();
    const auto host = req.find(http::field::host);
    HttpReply reply = route_request(std::string(req.method_string()), std::string(req.target()),
                                    host == req.end() ? std::string() : std::string(host->value()),
                                    websocket::is_upgrade(req), server_.context());
    if (reply.upgrade) {
      if (static_cast<std::size_t>(server_.ws_clients_.load()) >= server_.settings().max_ws_clients) {
        ++server_.connections_refused_;
        reply = bad_request_reply("", 503);
        reply.body = "service unavailable: " + std::to_string(server_.settings().max_ws_clients) +
                     " live pages are open already\n";
      } else {
        stream_.expires_never();
        std::make_shared<WsSession>(stream_.release_socket(), server_)->run(parser_->release());
        return;
      }
    }
    if (reply.status >= 400) ++server_.http_errors_;
    write(reply, req.keep_alive(), req.method() == http::verb::head);
  }

  void write(const HttpReply& reply, bool keep_alive, bool head) {
    if (head) {
      auto res = std::make_shared<http::response<http::empty_body>>(static_cast<http::status>(reply.status), 11);
      add_common_headers(*res, reply);
      res->content_length(reply.body.size());
      res->keep_alive(keep_alive);
      send(res);
    } else {
      auto res = std::make_shared<http::response<http::string_body>>(static_cast<http::status>(reply.status), 11);
      add_common_headers(*res, reply);
      res->body() = reply.body;
      res->prepare_payload();
      res->keep_alive(keep_alive);
      send(res);
    }
  }

  template <class Response>
  void send(const std::shared_ptr<Response>& res) {
    stream_.expires_after(std::chrono::seconds(server_.settings().idle_timeout_s));
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) return self->close();
      self->do_read();
    });
  }

  void close() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
    stream_.socket().close(ec);
  }

  beast::tcp_stream stream_;
  DashboardServer::Impl& server_;
  beast::flat_buffer buffer_{kHeaderLimit};
  std::optional<http::request_parser<http::empty_body>> parser_;
};

void DashboardServer::Impl::do_accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;
    if (!ec) {
      if (static_cast<std::size_t>(http_sessions_.load()) >= settings_.max_connections) {
        ++connections_refused_;
        beast::error_code ignored;
        socket.close(ignored);
      } else {
        std::make_shared<HttpSession>(std::move(socket), *this)->run();
      }
    }
    do_accept();  // an accept error (too many open files) affects one connection, not the server
  });
}

void DashboardServer::Impl::schedule_push() {
  timer_.expires_after(kPushPeriod);
  timer_.async_wait([this](beast::error_code ec) {
    if (ec) return;
    if (!clients_.empty()) {
      for (std::string& update : store_.take_updates(steady_ns())) {
        const auto message = std::make_shared<const std::string>(std::move(update));
        for (const std::shared_ptr<WsSession>& c : clients_) c->send(message);
      }
    } else {
      store_.take_updates(steady_ns());  // nobody listens: the bookkeeping still advances, so nothing piles up
    }
    schedule_push();
  });
}

void DashboardServer::Impl::join(const std::shared_ptr<WsSession>& s) {
  clients_.insert(s);
  ++ws_clients_;
  ++ws_clients_total_;
}

void DashboardServer::Impl::leave(WsSession* s) {
  for (auto it = clients_.begin(); it != clients_.end(); ++it) {
    if (it->get() == s) {
      clients_.erase(it);
      --ws_clients_;
      return;
    }
  }
}

DashboardServer::DashboardServer(SnapshotStore& store, const EmbeddedAsset* assets, const ServerSettings& settings)
    : impl_(std::make_unique<Impl>(store, assets, settings)) {}
DashboardServer::~DashboardServer() = default;
unsigned short DashboardServer::port() const { return impl_->port(); }
void DashboardServer::start() { impl_->start(); }
void DashboardServer::stop() { impl_->stop(); }
nlohmann::json DashboardServer::counters() const { return impl_->counters(); }

}  // namespace rockwatch::cli
