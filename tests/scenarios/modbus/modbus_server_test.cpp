// The Modbus TCP server's limits (scenarios/modbus/modbus_server.h, docs/monitor.md "Modbus
// TCP", Limits), on the server alone with libmodbus's own client: writes the simulation has not
// taken are capped (the next write gets exception 06, server busy, until the simulation takes
// them), and a connection without a complete request for the idle timeout is closed while one
// that keeps asking stays open.
#include "scenarios/modbus/modbus_server.h"

#include <gtest/gtest.h>
#include <modbus.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <sstream>
#include <thread>

namespace rcsim::modbus {
namespace {

using Clock = std::chrono::steady_clock;

// A libmodbus client of the server at `port`, unit 1 (the server's unit id).
struct Client {
    modbus_t* ctx;
    explicit Client(unsigned port) : ctx(modbus_new_tcp("127.0.0.1", static_cast<int>(port))) {
        modbus_set_slave(ctx, ModbusServer::kUnitId);
        modbus_set_response_timeout(ctx, 5, 0);
    }
    ~Client() {
        modbus_close(ctx);
        modbus_free(ctx);
    }
    bool connect() { return modbus_connect(ctx) == 0; }
};

// A plain TCP connection that sends nothing.
int silent_connection(unsigned port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    return ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 ? fd : -1;
}

// Waits up to `limit` for the server to close `fd` (end of stream): true if it did.
bool closed_within(int fd, std::chrono::milliseconds limit) {
    const auto end = Clock::now() + limit;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
        if (left.count() <= 0) return false;
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left.count())) > 0) {
            char b;
            return ::recv(fd, &b, 1, 0) == 0;
        }
    }
}

TEST(ModbusServer, WritesNotTakenAreCappedWithExceptionSixUntilTheSimulationTakesThem) {
    std::ostringstream log;
    ModbusServer server("127.0.0.1", 0, log);
    Client c(server.port());
    ASSERT_TRUE(c.connect());
    // mailbox.param0..7: holding registers 2..17, writable, any value.
    constexpr int kCells = 16;
    std::uint16_t values[kCells] = {};
    static_assert(ModbusServer::kMaxPendingWrites % kCells == 0, "the cap is reached by whole requests");
    for (std::size_t i = 0; i < ModbusServer::kMaxPendingWrites / kCells; ++i) {
        values[0] = static_cast<std::uint16_t>(i);
        ASSERT_EQ(modbus_write_registers(c.ctx, 2, kCells, values), kCells) << "request " << i;
    }
    // The cap reached: the next write is refused with exception 06 and queues nothing.
    EXPECT_EQ(modbus_write_register(c.ctx, 2, 0xBEEF), -1);
    EXPECT_EQ(errno, EMBXSBUSY);
    // Reads are still served.
    std::uint16_t r[2];
    EXPECT_EQ(modbus_read_registers(c.ctx, 0, 2, r), 2);

    std::uint64_t taken = 0;
    const std::vector<ModbusServer::Write> w = server.take_writes(taken);
    ASSERT_EQ(w.size(), ModbusServer::kMaxPendingWrites);
    EXPECT_EQ(taken, ModbusServer::kMaxPendingWrites);
    EXPECT_EQ(w.front().table, Table::holding_register);
    EXPECT_EQ(w.front().address, 2);
    EXPECT_EQ(w.back().address, 17);
    EXPECT_EQ(w[w.size() - kCells].value, ModbusServer::kMaxPendingWrites / kCells - 1); // the last request, in order
    // Taken: writes are accepted again.
    EXPECT_EQ(modbus_write_register(c.ctx, 2, 0xBEEF), 1);
    const std::vector<ModbusServer::Write> next = server.take_writes(taken);
    ASSERT_EQ(next.size(), 1u);
    EXPECT_EQ(next[0].value, 0xBEEF);
}

TEST(ModbusServer, AConnectionWithoutARequestForTheIdleTimeoutIsClosedAnAskingOneStays) {
    // (long beside the asking client's 50 ms, so that a loaded machine does not drop it)
    constexpr std::chrono::milliseconds kIdle{1500};
    std::ostringstream log;
    {
        ModbusServer server("127.0.0.1", 0, log, kIdle);
        Client asking(server.port());
        ASSERT_TRUE(asking.connect());
        const int silent = silent_connection(server.port());
        ASSERT_GE(silent, 0);
        const auto start = Clock::now();
        // The asking client reads every 50 ms, for two idle timeouts.
        std::uint16_t r[1];
        while (Clock::now() - start < 2 * kIdle) {
            ASSERT_EQ(modbus_read_registers(asking.ctx, 0, 1, r), 1) << "the asking client was dropped";
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        // The silent one was closed, and not before the timeout.
        ASSERT_TRUE(closed_within(silent, std::chrono::milliseconds(10000)));
        EXPECT_GE(Clock::now() - start, kIdle);
        ::close(silent);
        EXPECT_EQ(modbus_read_registers(asking.ctx, 0, 1, r), 1);
    } // (the server's thread joined: its log is complete)
    const std::string text = log.str();
    EXPECT_NE(text.find("dropped: idle for 1500 ms"), std::string::npos) << text;
    EXPECT_EQ(text.find("dropped"), text.rfind("dropped")) << "only the silent client: " << text;
}

} // namespace
} // namespace rcsim::modbus
