// rcsim — the Modbus TCP server's network side (see modbus_server.h, docs/monitor.md).
#include "scenarios/modbus/modbus_server.h"

#include "models/plumbing/config_error.h"

#include <modbus/modbus.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <thread>

namespace rcsim::modbus {

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kMbap = 7;          // transaction, protocol, length, unit
constexpr std::size_t kMaxAdu = 260;      // MODBUS_TCP_MAX_ADU_LENGTH
constexpr int kPollMs = 50;               // how soon the thread sees the stop flag

// Exception codes (Modbus Application Protocol v1.1b3, section 7).
constexpr int kIllegalFunction = MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
constexpr int kIllegalAddress = MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
constexpr int kIllegalValue = MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
constexpr int kBusy = MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY;
constexpr int kGatewayTarget = MODBUS_EXCEPTION_GATEWAY_TARGET; // no device with that unit id

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }

// "60 s", or "500 ms" for a time that is not whole seconds (the log's words for the idle timeout).
std::string duration_text(std::chrono::milliseconds t) {
    return t.count() % 1000 == 0 ? std::to_string(t.count() / 1000) + " s" : std::to_string(t.count()) + " ms";
}

struct Connection {
    int fd = -1;
    std::string peer;
    std::vector<std::uint8_t> buf;
    Clock::time_point last;
};

} // namespace

class ModbusServer::Impl {
public:
    Impl(int listen_fd, std::ostream& log, std::chrono::milliseconds idle_timeout)
        : listen_fd_(listen_fd), log_(log), idle_timeout_(idle_timeout) {
        ctx_ = modbus_new_tcp("127.0.0.1", 0); // only for modbus_reply(): it never connects or listens
        map_ = modbus_mapping_new(table_size(Table::coil), table_size(Table::discrete_input),
                                  table_size(Table::holding_register), table_size(Table::input_register));
        if (!ctx_ || !map_) throw ConfigError("modbus: libmodbus could not allocate its context");
        for (Table t : {Table::coil, Table::discrete_input, Table::input_register, Table::holding_register})
            size_[static_cast<unsigned>(t)] = table_size(t);
        for (Table t : {Table::coil, Table::discrete_input, Table::input_register, Table::holding_register})
            mapped_[static_cast<unsigned>(t)].assign(table_size(t), false);
        for (const Row& r : map_rows())
            for (unsigned w = 0; w < words(r.entry->type); ++w) {
                const auto cell = static_cast<std::uint16_t>(r.address + w);
                mapped_[static_cast<unsigned>(r.entry->table)][cell] = true;
                if (r.entry->access == Access::read_write) writable_[static_cast<unsigned>(r.entry->table)].push_back(cell);
            }
        thread_ = std::thread([this] { loop(); });
    }
    ~Impl() {
        stop_ = true;
        thread_.join();
        for (Connection& c : conns_) ::close(c.fd);
        ::close(listen_fd_);
        modbus_mapping_free(map_);
        modbus_free(ctx_);
    }

    std::vector<Write> take_writes(std::uint64_t& taken) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::vector<Write> out;
        out.swap(writes_);
        taken_ += out.size();
        taken = taken_;
        return out;
    }
    void publish(Image image) {
        std::lock_guard<std::mutex> lock(mutex_);
        image_ = std::move(image);
    }

private:
    int listen_fd_;
    std::ostream& log_;
    const std::chrono::milliseconds idle_timeout_; // no complete request for this long: closed
    modbus_t* ctx_ = nullptr;
    modbus_mapping_t* map_ = nullptr;
    std::array<std::vector<std::uint16_t>, 4> writable_; // per table, the cells a client may write
    std::array<unsigned, 4> size_{};                     // per table, one past its last address
    std::array<std::vector<bool>, 4> mapped_;            // per table, the cells the map names (the gaps are not)
    std::vector<Connection> conns_;
    std::atomic<bool> stop_{false};
    bool refusing_ = false; // one log line per burst of refused connections
    std::thread thread_;
    // Shared with the simulation thread.
    std::mutex mutex_;
    Image image_;
    std::vector<Write> writes_;
    std::uint64_t issued_ = 0, taken_ = 0;

    void loop() {
        while (!stop_) {
            std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
            for (const Connection& c : conns_) fds.push_back({c.fd, POLLIN, 0});
            if (::poll(fds.data(), fds.size(), kPollMs) < 0 && errno != EINTR) break;
            // Connections first read, then accepted, so the indices of fds match conns_.
            for (std::size_t i = conns_.size(); i-- > 0;)
                if ((fds[i + 1].revents & (POLLIN | POLLHUP | POLLERR)) && !read(conns_[i])) drop(i, "");
            if (fds[0].revents & POLLIN) accept();
            const auto now = Clock::now();
            for (std::size_t i = conns_.size(); i-- > 0;)
                if (now - conns_[i].last > idle_timeout_) drop(i, "idle for " + duration_text(idle_timeout_));
        }
    }

    void accept() {
        sockaddr_in a{};
        socklen_t len = sizeof a;
        const int fd = ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;
        char ip[INET_ADDRSTRLEN] = "?";
        ::inet_ntop(AF_INET, &a.sin_addr, ip, sizeof ip);
        const std::string peer = std::string(ip) + ":" + std::to_string(ntohs(a.sin_port));
        if (conns_.size() >= kMaxConnections) {
            if (!refusing_) log_ << "modbus: connection from " << peer << " refused: " << kMaxConnections << " already open" << std::endl;
            refusing_ = true;
            ::close(fd);
            return;
        }
        refusing_ = false;
        conns_.push_back({fd, peer, {}, Clock::now()});
    }

    void drop(std::size_t i, const std::string& why) {
        if (!why.empty()) log_ << "modbus: client " << conns_[i].peer << " dropped: " << why << std::endl;
        ::close(conns_[i].fd);
        conns_.erase(conns_.begin() + static_cast<std::ptrdiff_t>(i));
    }

    // Reads what is there (never more than one ADU is buffered) and answers every complete
    // request. False: the connection is to be closed (the peer closed it, or broke the framing).
    bool read(Connection& c) {
        std::uint8_t tmp[kMaxAdu];
        const ssize_t n = ::recv(c.fd, tmp, kMaxAdu - c.buf.size(), 0);
        if (n == 0) return false;
        if (n < 0) return errno == EAGAIN || errno == EINTR;
        c.buf.insert(c.buf.end(), tmp, tmp + n);
        while (c.buf.size() >= kMbap) {
            const std::uint16_t protocol = be16(&c.buf[2]), length = be16(&c.buf[4]);
            if (protocol != 0 || length < 2 || length > kMaxAdu - 6) {
                log_ << "modbus: client " << c.peer << " dropped: malformed MBAP header (protocol " << protocol
                     << ", length " << length << ")" << std::endl;
                return false;
            }
            const std::size_t adu = 6u + length;
            if (c.buf.size() < adu) break;
            std::array<std::uint8_t, kMaxAdu> req{}; // zero beyond the ADU: libmodbus reads no further than checked
            std::copy_n(c.buf.begin(), adu, req.begin());
            c.buf.erase(c.buf.begin(), c.buf.begin() + static_cast<std::ptrdiff_t>(adu));
            c.last = Clock::now();
            if (!answer(c.fd, req.data(), adu)) {
                log_ << "modbus: client " << c.peer << " dropped: a reply could not be sent (it does not read them)" << std::endl;
                return false;
            }
        }
        return true;
    }

    // The exception a request gets, 0 when it is good. Lengths first: modbus_reply() trusts them.
    int check(const std::uint8_t* req, std::size_t len) {
        const std::uint8_t unit = req[6], fc = req[7];
        const std::size_t pdu = len - kMbap; // function code and data
        if (unit != kUnitId && unit != 0xFF) return kGatewayTarget;
        Table t;
        unsigned max_qty = 0;
        switch (fc) {
        case MODBUS_FC_READ_COILS: t = Table::coil; max_qty = MODBUS_MAX_READ_BITS; break;
        case MODBUS_FC_READ_DISCRETE_INPUTS: t = Table::discrete_input; max_qty = MODBUS_MAX_READ_BITS; break;
        case MODBUS_FC_READ_HOLDING_REGISTERS: t = Table::holding_register; max_qty = MODBUS_MAX_READ_REGISTERS; break;
        case MODBUS_FC_READ_INPUT_REGISTERS: t = Table::input_register; max_qty = MODBUS_MAX_READ_REGISTERS; break;
        case MODBUS_FC_WRITE_SINGLE_COIL: t = Table::coil; break;
        case MODBUS_FC_WRITE_SINGLE_REGISTER: t = Table::holding_register; break;
        case MODBUS_FC_WRITE_MULTIPLE_COILS: t = Table::coil; max_qty = MODBUS_MAX_WRITE_BITS; break;
        case MODBUS_FC_WRITE_MULTIPLE_REGISTERS: t = Table::holding_register; max_qty = MODBUS_MAX_WRITE_REGISTERS; break;
        default: return kIllegalFunction;
        }
        if (pdu < 5) return kIllegalValue;
        const std::uint16_t addr = be16(req + 8), qty_or_value = be16(req + 10);
        const bool single = fc == MODBUS_FC_WRITE_SINGLE_COIL || fc == MODBUS_FC_WRITE_SINGLE_REGISTER;
        const bool multiple = fc == MODBUS_FC_WRITE_MULTIPLE_COILS || fc == MODBUS_FC_WRITE_MULTIPLE_REGISTERS;
        const unsigned qty = single ? 1 : qty_or_value;
        if (!multiple && pdu != 5) return kIllegalValue;
        if (!single && (qty < 1 || qty > max_qty)) return kIllegalValue;
        if (multiple) {
            const unsigned bytes = t == Table::coil ? (qty + 7) / 8 : 2 * qty;
            if (pdu < 6 || req[12] != bytes || pdu != 6 + bytes) return kIllegalValue;
        }
        if (addr + qty > size_[static_cast<unsigned>(t)]) return kIllegalAddress;
        if (fc == MODBUS_FC_WRITE_SINGLE_COIL && qty_or_value != 0xFF00 && qty_or_value != 0) return kIllegalValue;
        if (!single && !multiple) { // a read: every cell must be one the map names, as a write's must
            const auto& m = mapped_[static_cast<unsigned>(t)];
            return std::all_of(m.begin() + addr, m.begin() + addr + qty, [](bool b) { return b; }) ? 0 : kIllegalAddress;
        }
        const auto& w = writable_[static_cast<unsigned>(t)];
        for (unsigned k = 0; k < qty; ++k) {
            const auto cell = static_cast<std::uint16_t>(addr + k);
            if (std::find(w.begin(), w.end(), cell) == w.end()) return kIllegalAddress;
            if (t == Table::holding_register && !accepts(t, cell, single ? qty_or_value : be16(req + 13 + 2 * k)))
                return kIllegalValue;
        }
        return 0;
    }

    // The cells a (checked) write request writes.
    static std::vector<Write> writes_of(const std::uint8_t* req) {
        const std::uint8_t fc = req[7];
        const std::uint16_t addr = be16(req + 8), v = be16(req + 10);
        switch (fc) {
        case MODBUS_FC_WRITE_SINGLE_COIL: return {{Table::coil, addr, static_cast<std::uint16_t>(v ? 1 : 0)}};
        case MODBUS_FC_WRITE_SINGLE_REGISTER: return {{Table::holding_register, addr, v}};
        case MODBUS_FC_WRITE_MULTIPLE_COILS: {
            std::vector<Write> w;
            for (unsigned k = 0; k < v; ++k)
                w.push_back({Table::coil, static_cast<std::uint16_t>(addr + k), static_cast<std::uint16_t>(req[13 + k / 8] >> (k % 8) & 1)});
            return w;
        }
        case MODBUS_FC_WRITE_MULTIPLE_REGISTERS: {
            std::vector<Write> w;
            for (unsigned k = 0; k < v; ++k) w.push_back({Table::holding_register, static_cast<std::uint16_t>(addr + k), be16(req + 13 + 2 * k)});
            return w;
        }
        default: return {};
        }
    }

    // The tables as the simulation published them; coils and holding registers only once it has
    // taken every write (until then they hold what the clients wrote).
    void refresh_locked() {
        auto copy = [](const auto& from, auto* to, std::size_t n) { std::copy_n(from.begin(), std::min(n, from.size()), to); };
        copy(image_.discrete_inputs, map_->tab_input_bits, static_cast<std::size_t>(map_->nb_input_bits));
        copy(image_.input_registers, map_->tab_input_registers, static_cast<std::size_t>(map_->nb_input_registers));
        if (image_.writes_taken != issued_) return;
        copy(image_.coils, map_->tab_bits, static_cast<std::size_t>(map_->nb_bits));
        copy(image_.holding_registers, map_->tab_registers, static_cast<std::size_t>(map_->nb_registers));
    }

    // False: the reply could not be sent (the client does not read): close the connection.
    bool answer(int fd, const std::uint8_t* req, std::size_t len) {
        modbus_set_socket(ctx_, fd);
        int exception = check(req, len);
        std::vector<Write> w;
        if (exception == 0) {
            w = writes_of(req);
            std::lock_guard<std::mutex> lock(mutex_);
            if (writes_.size() + w.size() > kMaxPendingWrites) exception = kBusy;
            else {
                refresh_locked();
                writes_.insert(writes_.end(), w.begin(), w.end());
                issued_ += w.size();
            }
        }
        if (exception != 0) return send_exception(fd, req, static_cast<std::uint8_t>(exception));
        return modbus_reply(ctx_, req, static_cast<int>(len), map_) >= 0;
    }

    // An exception response: the request's function code with its high bit set. A request whose
    // code has it already (0x80..0xFF: the codes of exception responses, no request's) gets
    // exception 01 with its code as it came; libmodbus adds 0x80 and a byte wraps it (0x80 -> 0x00).
    static bool send_exception(int fd, const std::uint8_t* req, std::uint8_t code) {
        const std::uint8_t rsp[9] = {req[0], req[1], 0, 0, 0, 3, req[6], static_cast<std::uint8_t>(req[7] | 0x80), code};
        return ::send(fd, rsp, sizeof rsp, MSG_NOSIGNAL) == static_cast<ssize_t>(sizeof rsp);
    }
};

ModbusServer::ModbusServer(const std::string& host, unsigned port, std::ostream& log,
                           std::chrono::milliseconds idle_timeout) {
    const std::string where = "--modbus '" + host + ":" + std::to_string(port) + "'";
    in_addr ip{};
    if (::inet_pton(AF_INET, host.c_str(), &ip) != 1) throw ConfigError(where + ": HOST must be a numeric IPv4 address");
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr = ip;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(fd, 64) != 0) {
        const std::string why = std::strerror(errno);
        if (fd >= 0) ::close(fd);
        throw ConfigError(where + ": cannot listen: " + why);
    }
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    impl_ = std::make_unique<Impl>(fd, log, idle_timeout);
}

ModbusServer::~ModbusServer() = default;

std::vector<ModbusServer::Write> ModbusServer::take_writes(std::uint64_t& taken) { return impl_->take_writes(taken); }
void ModbusServer::publish(Image image) { impl_->publish(std::move(image)); }

} // namespace rcsim::modbus
