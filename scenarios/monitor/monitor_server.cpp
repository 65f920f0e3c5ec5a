// rcsim — the remote monitor's network side (see monitor_server.h).
#include "scenarios/monitor/monitor_server.h"

#include "models/plumbing/config_error.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <sys/ioctl.h>
#include <linux/sockios.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <optional>

namespace rcsim::monitor {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

class WsSession;
class HttpSession;

class MonitorServer::Impl {
public:
    Impl(std::ostream& log, std::string page) : log_(log), page_(std::move(page)) {}

    // Before ioc: the sessions its destructor frees take themselves out of it. io thread only.
    struct OpenHttp {
        std::weak_ptr<HttpSession> session;
        std::string addr; // the peer's address, without the port
    };
    std::map<std::uint64_t, OpenHttp> http_open; // plain HTTP connections, in accept order
    std::uint64_t next_http_seq = 0;
    net::io_context ioc;
    tcp::acceptor acceptor{ioc};
    std::thread thread;

    void note(const std::string& line) {
        std::lock_guard<std::mutex> lock(log_mu_);
        log_ << "monitor: " << line << std::endl;
    }
    /// Queues a client's request; false when the queue, or this client's share of it, is full
    /// (the client floods: drop it).
    bool push(Request r) {
        {
            std::lock_guard<std::mutex> lock(req_mu);
            if (r.client != 0) {
                std::size_t& mine = pending_of[r.client];
                if (requests.size() >= kMaxPendingRequests || mine >= kMaxClientRequests) return false;
                ++mine;
            }
            requests.push_back(std::move(r));
        }
        req_cv.notify_one();
        return true;
    }
    std::shared_ptr<const std::string> snapshot() {
        std::lock_guard<std::mutex> lock(snap_mu);
        return snapshot_;
    }
    const std::string& page() const { return page_; }
    void start_accept();
    /// Room for one more plain HTTP connection from `addr` (kMaxHttpSessionsPerPeer from one
    /// address, kMaxHttpSessions in all): free, made by closing an idle connection, or none.
    enum class Room { free, evicted, evicted_peer, none };
    Room make_room(const std::string& addr);

    std::mutex req_mu;
    std::condition_variable req_cv;
    std::deque<Request> requests;
    std::map<std::uint64_t, std::size_t> pending_of; // requests queued per client
    std::mutex snap_mu;
    std::shared_ptr<const std::string> snapshot_;
    // io thread only
    std::map<std::uint64_t, std::weak_ptr<WsSession>> sessions;
    std::uint64_t next_id = 1;
    std::atomic<std::size_t> open_clients{0};
    bool http_full_noted = false;  // one log line per burst of refused connections

private:
    std::ostream& log_;
    std::mutex log_mu_;
    const std::string page_; // set before the io thread starts, read-only after
};

namespace {

std::string hello_text() {
    return nlohmann::json{{"type", "hello"}, {"api", kApiVersion}, {"server", "rcsim " RCSIM_VERSION}}.dump();
}

/// The deepest nesting of arrays and objects in a JSON text (strings skipped), counted before the
/// text is parsed: a message nested thousands deep would make every later dump() recurse as deep.
std::size_t json_depth(const std::string& text) {
    std::size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

std::string peer_of(const tcp::socket& s) {
    boost::system::error_code ec;
    const auto ep = s.remote_endpoint(ec);
    return ec ? std::string("?") : ep.address().to_string() + ":" + std::to_string(ep.port());
}

/// Bytes written to a socket that its peer has not taken yet (Linux SIOCOUTQ: the send queue,
/// unsent or unacknowledged; on loopback, what the peer's full receive buffer holds back).
std::size_t unsent_bytes(tcp::socket& s) {
    int n = 0;
    return ::ioctl(s.native_handle(), SIOCOUTQ, &n) == 0 && n > 0 ? static_cast<std::size_t>(n) : 0;
}

/// A tcp_stream that first hands out `prefix`: the bytes the HTTP parser read past the upgrade
/// request (a client may send its first WebSocket frames in the same segment), which the
/// WebSocket stream then reads as its own.
class PrefixedStream {
public:
    using executor_type = beast::tcp_stream::executor_type;
    PrefixedStream(tcp::socket&& s, std::string prefix) : next_(std::move(s)), prefix_(std::move(prefix)) {}

    executor_type get_executor() { return next_.get_executor(); }
    beast::tcp_stream& next_layer() { return next_; }

    template <class MutableBuffers, class Handler>
    void async_read_some(const MutableBuffers& buffers, Handler&& handler) {
        if (prefix_.empty()) return next_.async_read_some(buffers, std::forward<Handler>(handler));
        const std::size_t n = net::buffer_copy(buffers, net::buffer(prefix_));
        prefix_.erase(0, n);
        net::post(get_executor(), beast::bind_front_handler(std::forward<Handler>(handler), beast::error_code{}, n));
    }
    template <class ConstBuffers, class Handler>
    void async_write_some(const ConstBuffers& buffers, Handler&& handler) {
        next_.async_write_some(buffers, std::forward<Handler>(handler));
    }

private:
    beast::tcp_stream next_;
    std::string prefix_;
};

// How the WebSocket stream closes its next layer (found by argument-dependent lookup; the
// sessions use only the asynchronous operations).
template <class Handler>
void async_teardown(beast::role_type role, PrefixedStream& s, Handler&& handler) {
    beast::websocket::async_teardown(role, s.next_layer().socket(), std::forward<Handler>(handler));
}

} // namespace

// One WebSocket client: reads requests, writes the messages queued for it one at a time.
class WsSession : public std::enable_shared_from_this<WsSession> {
public:
    /// `early`: what the client sent after its upgrade request, read with it (its first frames).
    WsSession(MonitorServer::Impl& srv, tcp::socket&& s, std::string early, std::uint64_t id)
        : srv_(srv), id_(id), peer_(peer_of(s)), ws_(std::move(s), std::move(early)) {}

    void run(http::request<http::string_body> req) {
        ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        ws_.read_message_max(MonitorServer::kMaxMessageBytes);
        ws_.auto_fragment(false); // one frame per message: simpler for clients, nothing to interleave
        // A fixed kernel buffer (no autotuning to megabytes): a client that stops reading fills
        // it and its queue soon, and is dropped as too slow instead of hiding behind the kernel.
        beast::error_code ignored;
        beast::get_lowest_layer(ws_).socket().set_option(net::socket_base::send_buffer_size(MonitorServer::kSocketSendBuffer), ignored);
        ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) { self->on_accept(ec); });
    }

    /// Queues one message. What counts is what the client has not read: the messages waiting
    /// here and the bytes in the socket's send queue, not how many one slice produced (a client
    /// that pipelines 256 requests gets 256 replies at once, and reads them). A client that lets
    /// kMaxQueuedBytes or kMaxQueuedMessages pile up is dropped.
    void queue(std::shared_ptr<const std::string> text) {
        if (closed_) return;
        const std::size_t unread = queued_bytes_ + unsent_bytes(beast::get_lowest_layer(ws_).socket());
        if (out_.size() >= MonitorServer::kMaxQueuedMessages || unread + text->size() > MonitorServer::kMaxQueuedBytes) {
            drop("too slow: " + std::to_string(unread) + " bytes not yet read (" + std::to_string(out_.size()) +
                 " messages waiting)");
            return;
        }
        queued_bytes_ += text->size();
        out_.push_back(std::move(text));
        if (out_.size() == 1) write_front();
    }

private:
    MonitorServer::Impl& srv_;
    std::uint64_t id_;
    std::string peer_;
    websocket::stream<PrefixedStream> ws_;
    beast::flat_buffer buf_;
    std::deque<std::shared_ptr<const std::string>> out_;
    std::size_t queued_bytes_ = 0; // in out_
    bool closed_ = false;

    std::string who() const { return "client " + std::to_string(id_) + " (" + peer_ + ")"; }

    void on_accept(beast::error_code ec) {
        if (ec) {
            srv_.note(who() + " dropped: WebSocket handshake failed: " + ec.message());
            srv_.open_clients--;
            closed_ = true;
            return;
        }
        srv_.sessions[id_] = weak_from_this();
        srv_.note(who() + " connected");
        queue(std::make_shared<const std::string>(hello_text()));
        read_next();
    }

    void read_next() {
        ws_.async_read(buf_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
    }

    void on_read(beast::error_code ec) {
        if (closed_) return;
        if (ec == websocket::error::closed || ec == net::error::eof) return drop("disconnected");
        if (ec == websocket::error::message_too_big)
            return drop("sent a message over " + std::to_string(MonitorServer::kMaxMessageBytes) + " bytes");
        if (ec) return drop(ec.message());
        if (!ws_.got_text()) return drop("sent a binary message (the API is JSON text)");
        const std::string text = beast::buffers_to_string(buf_.data());
        buf_.consume(buf_.size());
        if (json_depth(text) > MonitorServer::kMaxJsonDepth)
            return drop("sent garbage: JSON nested deeper than " + std::to_string(MonitorServer::kMaxJsonDepth));
        nlohmann::json msg = nlohmann::json::parse(text, nullptr, false);
        if (msg.is_discarded() || !msg.is_object() || !msg.contains("op") || !msg["op"].is_string())
            return drop("sent garbage: not a JSON object with a string \"op\"");
        if (!srv_.push({id_, std::move(msg)})) return drop("flooding: the request queue is full");
        read_next();
    }

    void write_front() {
        ws_.text(true);
        ws_.async_write(net::buffer(*out_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
            if (self->closed_) return;
            if (ec) return self->drop(ec.message());
            self->queued_bytes_ -= self->out_.front()->size();
            self->out_.pop_front();
            if (!self->out_.empty()) self->write_front();
        });
    }

    void drop(const std::string& why) {
        if (closed_) return;
        closed_ = true;
        srv_.note(who() + (why == "disconnected" ? " disconnected" : " dropped: " + why));
        srv_.sessions.erase(id_);
        srv_.open_clients--;
        nlohmann::json closed = {{"op", "closed"}, {"client", id_}};
        srv_.push({0, std::move(closed)});
        beast::error_code ignored;
        beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
        beast::get_lowest_layer(ws_).close();
    }
};

// One HTTP request: the page, the snapshot, or the upgrade to a WebSocket. Registered in
// Impl::http_open while it lives, so that a new connection can take an idle one's place.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(MonitorServer::Impl& srv, tcp::socket&& s, std::uint64_t seq) : srv_(srv), seq_(seq), stream_(std::move(s)) {}
    ~HttpSession() { srv_.http_open.erase(seq_); }

    void run() {
        parser_.emplace();
        parser_->body_limit(MonitorServer::kMaxMessageBytes);
        parser_->header_limit(16 * 1024);
        stream_.expires_after(MonitorServer::kRequestTimeout);
        http::async_read(stream_, buf_, *parser_,
                         [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
    }

    /// Its whole request is in: it is being answered (or became a WebSocket).
    bool answering() const { return answering_; }
    /// It has sent nothing yet: no byte read, none waiting in its socket.
    bool idle() {
        boost::system::error_code ec;
        return !answering_ && buf_.size() == 0 && stream_.socket().available(ec) == 0 && !ec;
    }
    /// Closed to make room for a new connection (Impl::make_room); it logs nothing.
    void evict() {
        evicted_ = true;
        srv_.http_open.erase(seq_);
        stream_.close();
    }

private:
    MonitorServer::Impl& srv_;
    std::uint64_t seq_;
    beast::tcp_stream stream_;
    beast::flat_buffer buf_;
    std::optional<http::request_parser<http::string_body>> parser_;
    std::shared_ptr<http::response<http::string_body>> res_;
    bool answering_ = false, evicted_ = false;

    void on_read(beast::error_code ec) {
        if (evicted_) return;
        if (ec) {
            // A browser's idle spare connection ends by a close or the timeout: nothing to log.
            if (ec != http::error::end_of_stream && ec != beast::error::timeout) srv_.note("HTTP request from " + peer_of(stream_.socket()) + " dropped: " + ec.message());
            return;
        }
        answering_ = true;
        stream_.expires_after(MonitorServer::kAnswerTimeout);
        http::request<http::string_body> req = parser_->release();
        if (websocket::is_upgrade(req)) return upgrade(std::move(req));
        respond(req);
    }

    void upgrade(http::request<http::string_body> req) {
        if (req.target() != "/api/v1/ws") return reply(req, http::status::not_found, "text/plain", "WebSocket endpoint: /api/v1/ws\n");
        if (srv_.open_clients.load() >= MonitorServer::kMaxClients)
            return reply(req, http::status::service_unavailable, "text/plain", "too many monitor clients\n");
        srv_.open_clients++;
        stream_.expires_never();
        // What the parser read past the request is the client's first WebSocket frames.
        std::string early = beast::buffers_to_string(buf_.data());
        std::make_shared<WsSession>(srv_, stream_.release_socket(), std::move(early), srv_.next_id++)->run(std::move(req));
    }

    void respond(const http::request<http::string_body>& req) {
        if (req.method() != http::verb::get && req.method() != http::verb::head)
            return reply(req, http::status::method_not_allowed, "text/plain", "GET only; control goes over /api/v1/ws\n");
        const auto target = req.target();
        if (target == "/" || target == "/index.html") return reply(req, http::status::ok, "text/html; charset=utf-8", srv_.page());
        if (target == "/api/v1/snapshot") {
            const auto snap = srv_.snapshot();
            if (!snap) return reply(req, http::status::service_unavailable, "text/plain", "no snapshot yet\n");
            return reply(req, http::status::ok, "application/json", *snap);
        }
        if (target == "/api/v1" || target == "/api")
            return reply(req, http::status::ok, "application/json", hello_text());
        reply(req, http::status::not_found, "text/plain", "not found; see docs/monitor.md\n");
    }

    void reply(const http::request<http::string_body>& req, http::status st, const char* type, const std::string& body) {
        res_ = std::make_shared<http::response<http::string_body>>(st, req.version());
        res_->set(http::field::server, "rcsim " RCSIM_VERSION);
        res_->set(http::field::content_type, type);
        res_->set(http::field::cache_control, "no-store");
        res_->keep_alive(false);
        if (req.method() != http::verb::head) res_->body() = body;
        res_->prepare_payload();
        http::async_write(stream_, *res_, [self = shared_from_this()](beast::error_code, std::size_t) {
            beast::error_code ignored;
            self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        });
    }
};

MonitorServer::Impl::Room MonitorServer::Impl::make_room(const std::string& addr) {
    std::size_t mine = 0;
    for (const auto& open : http_open) mine += open.second.addr == addr;
    const bool peer_full = mine >= kMaxHttpSessionsPerPeer;
    if (!peer_full && http_open.size() < kMaxHttpSessions) return Room::free;
    // Oldest first (http_open is in accept order): the one that sent nothing, else the one still
    // sending its request; one being answered is never closed. A full peer gives up its own.
    std::shared_ptr<HttpSession> victim;
    for (int pass = 0; pass < 2 && !victim; ++pass) {
        for (const auto& open : http_open) {
            if (peer_full && open.second.addr != addr) continue;
            auto s = open.second.session.lock();
            if (s && !s->answering() && (pass == 1 || s->idle())) {
                victim = std::move(s);
                break;
            }
        }
    }
    if (!victim) return Room::none;
    victim->evict();
    return peer_full ? Room::evicted_peer : Room::evicted;
}

void MonitorServer::Impl::start_accept() {
    acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket s) {
        if (ec == net::error::operation_aborted) return;
        if (ec) {
            // Out of descriptors (EMFILE) or the like: retry in a moment rather than spin.
            note("accept failed: " + ec.message());
            auto retry = std::make_shared<net::steady_timer>(ioc, std::chrono::milliseconds(100));
            retry->async_wait([this, retry](beast::error_code) { start_accept(); });
            return;
        }
        boost::system::error_code addr_ec;
        const auto ep = s.remote_endpoint(addr_ec);
        const std::string addr = addr_ec ? std::string("?") : ep.address().to_string();
        const Room room = make_room(addr);
        if (room != Room::free && !http_full_noted) { // one log line per burst
            const std::string full = room == Room::evicted_peer ? std::to_string(kMaxHttpSessionsPerPeer) + " already open from " + addr
                                                                : std::to_string(kMaxHttpSessions) + " already open";
            note("HTTP connection from " + peer_of(s) + ": " + full +
                 (room == Room::none ? ", every one being answered: refused" : ": the oldest idle one closed to make room"));
        }
        http_full_noted = room != Room::free;
        if (room == Room::none) {
            boost::system::error_code ignored;
            s.close(ignored);
        } else {
            const std::uint64_t seq = next_http_seq++;
            auto session = std::make_shared<HttpSession>(*this, std::move(s), seq);
            http_open[seq] = {session, addr};
            session->run();
        }
        start_accept();
    });
}

// ---------------------------------------------------------------------------------------------

MonitorServer::MonitorServer(const std::string& host, unsigned port, std::string page, std::ostream& log)
    : impl_(std::make_unique<Impl>(log, std::move(page))) {
    const std::string where = host + ":" + std::to_string(port);
    boost::system::error_code ec;
    const auto addr = net::ip::make_address(host, ec);
    if (ec) throw ConfigError("--monitor '" + where + "': '" + host + "' is not a numeric IPv4 or IPv6 address");
    const tcp::endpoint ep(addr, static_cast<unsigned short>(port));
    auto& a = impl_->acceptor;
    a.open(ep.protocol(), ec);
    if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) a.bind(ep, ec);
    if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
    if (ec) throw ConfigError("--monitor '" + where + "': cannot listen: " + ec.message());
    const tcp::endpoint bound = a.local_endpoint();
    port_ = bound.port();
    // Read here, before the io thread owns the acceptor. All interfaces: this machine is one of them.
    std::string shown = bound.address().is_unspecified() ? std::string(bound.address().is_v6() ? "::1" : "127.0.0.1")
                                                         : bound.address().to_string();
    if (bound.address().is_v6()) shown = "[" + shown + "]";
    url_ = "http://" + shown + ":" + std::to_string(port_) + "/";
    impl_->start_accept();
    impl_->thread = std::thread([this] {
        for (;;) {
            try {
                impl_->ioc.run();
                return;
            } catch (const std::exception& e) {
                impl_->note(std::string("io thread: ") + e.what()); // one failed client; serve the rest
            }
        }
    });
}

MonitorServer::~MonitorServer() {
    impl_->ioc.stop();
    if (impl_->thread.joinable()) impl_->thread.join();
}

std::vector<MonitorServer::Request> MonitorServer::take_requests() {
    std::lock_guard<std::mutex> lock(impl_->req_mu);
    std::vector<Request> out(std::make_move_iterator(impl_->requests.begin()),
                             std::make_move_iterator(impl_->requests.end()));
    impl_->requests.clear();
    impl_->pending_of.clear();
    return out;
}

void MonitorServer::wait_for_request(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(impl_->req_mu);
    impl_->req_cv.wait_for(lock, timeout, [this] { return !impl_->requests.empty(); });
}

void MonitorServer::send(std::uint64_t client, std::shared_ptr<const std::string> text) {
    net::post(impl_->ioc, [this, client, text = std::move(text)]() mutable {
        const auto it = impl_->sessions.find(client);
        if (it == impl_->sessions.end()) return;
        if (auto s = it->second.lock()) s->queue(std::move(text));
    });
}

void MonitorServer::publish_snapshot(std::shared_ptr<const std::string> text) {
    std::lock_guard<std::mutex> lock(impl_->snap_mu);
    impl_->snapshot_ = std::move(text);
}

std::size_t MonitorServer::clients() const { return impl_->open_clients.load(); }

} // namespace rcsim::monitor
