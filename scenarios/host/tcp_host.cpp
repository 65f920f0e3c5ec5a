// rcsim — TCP serial backend and real-time pacer (see tcp_host.h).
#include "scenarios/host/tcp_host.h"

#include "models/plumbing/config_error.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <future>
#include <iostream>
#include <stdexcept>

namespace rcsim {

namespace asio = boost::asio;
using asio::ip::tcp;

void TcpHostConfig::set_listen(const std::string& text) {
    const auto colon = text.rfind(':');
    if (colon == std::string::npos) throw std::invalid_argument("'" + text + "' is not HOST:PORT");
    std::string host = text.substr(0, colon);
    const std::string p = text.substr(colon + 1);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    if (host.empty()) host = "127.0.0.1";
    unsigned long v = 0;
    try {
        std::size_t used = 0;
        v = std::stoul(p, &used, 10);
        if (used != p.size()) throw std::invalid_argument(p);
    } catch (const std::exception&) {
        throw std::invalid_argument("bad port '" + p + "' in '" + text + "'");
    }
    if (v > 65535) throw std::invalid_argument("port " + p + " out of range (0..65535)");
    boost::system::error_code ec;
    asio::ip::make_address(host, ec);
    if (ec) throw std::invalid_argument("bad address '" + host + "' (a numeric IPv4 or IPv6 address)");
    address = host;
    port = static_cast<unsigned>(v);
}

// ---------------------------------------------------------------------------------------------
// SystemC side

TcpHost::TcpHost(sc_core::sc_module_name name, const TcpHostConfig& cfg)
    : sc_module(name), cfg_(cfg), inbox_(sc_core::sc_gen_unique_name("inbox")), out_(cfg.max_buffer),
      acceptor_(io_) {
    cfg_.format.validate();
    boost::system::error_code ec;
    const auto addr = asio::ip::make_address(cfg_.address, ec);
    const std::string where = cfg_.address + ":" + std::to_string(cfg_.port);
    if (ec) throw ConfigError(std::string(this->name()) + ": bad listen address '" + cfg_.address + "'");
    const tcp::endpoint ep(addr, static_cast<unsigned short>(cfg_.port));
    acceptor_.open(ep.protocol(), ec);
    if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
    if (!ec) acceptor_.bind(ep, ec);
    if (!ec) acceptor_.listen(1, ec);
    if (ec) throw ConfigError(std::string(this->name()) + ": cannot listen on " + where + ": " + ec.message());
    port_ = acceptor_.local_endpoint().port();
    if (!cfg_.port_file.empty()) {
        std::ofstream pf(cfg_.port_file + ".tmp", std::ios::trunc);
        pf << port_ << '\n';
        pf.close();
        // Renamed into place so a reader polling for the file never sees it half written.
        if (!pf || std::rename((cfg_.port_file + ".tmp").c_str(), cfg_.port_file.c_str()) != 0)
            throw ConfigError(cfg_.port_file, 0, "cannot write the port file");
    }
    if (!cfg_.record_path.empty()) {
        rec_.open(cfg_.record_path, cfg_.format);
        rec_.event(sc_core::SC_ZERO_TIME, SessionEvent::Kind::listen, endpoint());
    }
    SC_HAS_PROCESS(TcpHost);
    SC_THREAD(run);
    start_accept();
    thread_ = std::thread([this] {
        for (;;) {
            try {
                io_.run();
                return;
            } catch (const std::exception& e) { // one failed client: serve the next
                std::cerr << this->name() << ": io thread: " << e.what() << std::endl;
                drop_client();
            }
        }
    });
}

TcpHost::~TcpHost() {
    stopping_ = true;
    io_.stop();
    if (thread_.joinable()) thread_.join();
    if (rec_.is_open() && !ended_ && !end_logged_) rec_.event(sc_core::sc_time_stamp(), SessionEvent::Kind::end);
    if (attached_) inbox_.async_detach_suspending();
}

void TcpHost::finish_log() {
    if (rec_.is_open() && !ended_ && !end_logged_) rec_.event(sc_core::sc_time_stamp(), SessionEvent::Kind::end);
    end_logged_ = true;
    rec_.check();
}

std::string TcpHost::endpoint() const {
    const bool v6 = cfg_.address.find(':') != std::string::npos;
    return (v6 ? "[" + cfg_.address + "]" : cfg_.address) + ":" + std::to_string(port_);
}

bool TcpHost::client_connected() const {
    std::lock_guard<std::mutex> lock(mu_);
    return connected_;
}

TcpHost::Counters TcpHost::counters() const { return out_.host_counters(mu_, counters_); }

void TcpHost::end_of_elaboration() { require_connected(name()); }

void TcpHost::start_of_simulation() {
    // Active from the start: while listening, the kernel must wait for a client rather than
    // end by starvation.
    attached_ = inbox_.async_attach_suspending();
}

void TcpHost::detach() {
    if (attached_) inbox_.async_detach_suspending();
    attached_ = false;
}

void TcpHost::run() {
    const sc_core::sc_time frame = cfg_.format.frame_time();
    bool disconnected = false; // a client went away since the queue last emptied
    for (;;) {
        std::optional<Item> item = pop_front_locked(mu_, in_);
        if (!item) {
            if (disconnected && cfg_.end_on_disconnect) {
                // Every byte the client sent is on the line: the session is over.
                ended_ = true;
                detach();
                rec_.event(sc_core::sc_time_stamp(), SessionEvent::Kind::end);
                sc_core::sc_pause();
                return;
            }
            wait(inbox_.arrived);
            continue;
        }
        switch (item->kind) {
        case Item::connected:
            rec_.event(sc_core::sc_time_stamp(), SessionEvent::Kind::connect);
            break;
        case Item::disconnected:
            rec_.event(sc_core::sc_time_stamp(), SessionEvent::Kind::disconnect);
            disconnected = true;
            break;
        case Item::brk:
            // The wire at SPACE for the break's length; the next character starts after it.
            line_->insert_break(side_, cfg_.break_duration);
            {
                std::lock_guard<std::mutex> lock(mu_);
                ++counters_.breaks_sent;
            }
            wait(cfg_.break_duration);
            break;
        case Item::byte:
            // One character per frame time: the pace of a real terminal at this baud.
            line_->transmit(side_, SerialWord::encode(item->value, cfg_.format));
            rec_.in(sc_core::sc_time_stamp(), item->value);
            {
                std::lock_guard<std::mutex> lock(mu_);
                ++counters_.bytes_sent;
                if (read_paused_ && in_.size() <= kMaxInput / 2) {
                    read_paused_ = false;
                    asio::post(io_, [this] { resume_read(); }); // thread-safe; never blocks
                }
            }
            wait(frame);
            break;
        }
    }
}

void TcpHost::rx_char(const SerialRx& c) {
    const auto byte = static_cast<std::uint8_t>(c.data);
    rec_.out(c.stop, byte, c.parity_error, c.framing_error);
    {
        std::lock_guard<std::mutex> lock(mu_);
        if (!connected_) ++counters_.bytes_buffered;
    }
    out_.push(c);
    asio::post(io_, [this] { start_write(); }); // thread-safe; never blocks
}

void TcpHost::rx_break(bool active) { out_.note_break(active); }

// ---------------------------------------------------------------------------------------------
// io thread

void TcpHost::push(Item it) {
    {
        std::lock_guard<std::mutex> lock(mu_);
        in_.push_back(it);
    }
    inbox_.async_request_update();
}

void TcpHost::start_accept() {
    acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket s) {
        if (stopping_ || ec == asio::error::operation_aborted) return;
        if (ec) {
            start_accept();
            return;
        }
        boost::system::error_code ignored;
        s.set_option(tcp::no_delay(true), ignored);
        sock_.emplace(std::move(s));
        telnet_ = TelnetDecoder{};
        {
            std::lock_guard<std::mutex> lock(mu_);
            connected_ = true;
            ++counters_.connections;
            in_.push_back({Item::connected, 0});
        }
        inbox_.async_request_update();
        start_read();
        start_write(); // whatever the controller sent while nobody listened
    });
}

void TcpHost::start_read() {
    sock_->async_read_some(asio::buffer(rbuf_), [this](const boost::system::error_code& ec, std::size_t n) {
        if (stopping_) return;
        if (ec) {
            drop_client();
            return;
        }
        bool full = false;
        {
            std::lock_guard<std::mutex> lock(mu_);
            for (std::size_t i = 0; i < n; ++i) {
                if (!cfg_.telnet) {
                    in_.push_back({Item::byte, rbuf_[i]});
                    continue;
                }
                std::uint8_t data = 0;
                switch (telnet_.feed(rbuf_[i], data)) {
                case TelnetDecoder::Out::byte: in_.push_back({Item::byte, data}); break;
                case TelnetDecoder::Out::brk: in_.push_back({Item::brk, 0}); break;
                case TelnetDecoder::Out::none: break;
                }
            }
            counters_.bytes_in += n;
            if (in_.size() >= kMaxInput) {
                // Full: read no more, so TCP flow control holds the client back until the line
                // drained half of it (run() posts resume_read).
                full = read_paused_ = true;
                ++counters_.input_stalls;
            }
        }
        inbox_.async_request_update();
        if (!full) start_read();
    });
}

void TcpHost::resume_read() {
    if (sock_ && !stopping_) start_read();
}

std::uint64_t TcpHost::bytes_unsent() {
    std::uint64_t queued = 0;
    {
        std::lock_guard<std::mutex> lock(mu_);
        for (const Item& it : in_) queued += it.kind == Item::byte;
    }
    // The socket belongs to the io thread: ask it, and wait a moment (it never blocks).
    auto unread = std::make_shared<std::promise<std::uint64_t>>();
    std::future<std::uint64_t> answer = unread->get_future();
    asio::post(io_, [this, unread] {
        boost::system::error_code ec;
        const std::size_t n = sock_ ? sock_->available(ec) : 0;
        unread->set_value(ec ? 0 : n);
    });
    if (answer.wait_for(std::chrono::seconds(1)) != std::future_status::ready) return queued;
    return queued + answer.get();
}

void TcpHost::start_write() {
    if (writing_ || !sock_ || stopping_ || !out_.take(wbuf_)) return;
    if (cfg_.telnet) wbuf_ = telnet_escape(wbuf_);
    writing_ = true;
    asio::async_write(*sock_, asio::buffer(wbuf_), [this](const boost::system::error_code& ec, std::size_t n) {
        writing_ = false;
        if (stopping_) return;
        {
            std::lock_guard<std::mutex> lock(mu_);
            counters_.bytes_out += n;
        }
        if (ec) return; // the read side notices the disconnect
        start_write();
    });
}

void TcpHost::drop_client() {
    if (!sock_) return;
    boost::system::error_code ignored;
    sock_->shutdown(tcp::socket::shutdown_both, ignored);
    sock_->close(ignored);
    sock_.reset();
    {
        std::lock_guard<std::mutex> lock(mu_);
        connected_ = false;
        ++counters_.disconnects;
        in_.push_back({Item::disconnected, 0});
    }
    inbox_.async_request_update();
    if (!cfg_.end_on_disconnect) start_accept(); // serve the next client
}

// ---------------------------------------------------------------------------------------------
// pacer

RealtimePacer::RealtimePacer(sc_core::sc_module_name name, double rtf, sc_core::sc_time step,
                             std::chrono::microseconds max_nap)
    : sc_module(name), step_(step), max_nap_(max_nap) {
    if (!(rtf > 0)) throw std::invalid_argument(std::string(this->name()) + ": real-time factor must be > 0");
    if (step == sc_core::SC_ZERO_TIME) throw std::invalid_argument(std::string(this->name()) + ": step must be > 0");
    stats_.rtf = rtf;
    SC_HAS_PROCESS(RealtimePacer);
    SC_THREAD(run);
}

void RealtimePacer::set_rtf(double rtf) {
    if (!(rtf >= 0)) throw std::invalid_argument(std::string(name()) + ": real-time factor must be >= 0");
    paced_ = rtf > 0;
    if (paced_) stats_.rtf = rtf;
    rebase();
}

void RealtimePacer::run() {
    using clock = std::chrono::steady_clock;
    auto wall0 = clock::now();
    sc_core::sc_time sim0 = sc_core::sc_time_stamp();
    for (;;) {
        if (rebase_) {
            wall0 = clock::now();
            sim0 = sc_core::sc_time_stamp();
            rebase_ = false;
        }
        if (!paced_) {
            wait(step_);
            continue;
        }
        const double sim = (sc_core::sc_time_stamp() - sim0).to_seconds();
        const double wall = std::chrono::duration<double>(clock::now() - wall0).count();
        stats_.sim_s = sim;
        stats_.wall_s = wall;
        const double ahead = sim / stats_.rtf - wall; // wall seconds the simulation is early
        if (ahead > 0) {
            stats_.max_lead_s = std::max(stats_.max_lead_s, ahead * stats_.rtf);
            // A bounded nap, then back to the kernel (a delta cycle, so input that arrived
            // meanwhile is taken in), then check again: never one long, unresponsive sleep.
            const auto nap = std::min(max_nap_, std::chrono::duration_cast<std::chrono::microseconds>(
                                                    std::chrono::duration<double>(ahead)) + std::chrono::microseconds(1));
            const auto t0 = clock::now();
            std::this_thread::sleep_for(nap);
            stats_.slept_s += std::chrono::duration<double>(clock::now() - t0).count();
            ++stats_.naps;
            wait(sc_core::SC_ZERO_TIME);
            continue;
        }
        stats_.max_lag_s = std::max(stats_.max_lag_s, -ahead * stats_.rtf);
        wait(step_);
    }
}

} // namespace rcsim
