// rcsim — the Modbus TCP server's network side (docs/monitor.md "Modbus TCP"): its own thread,
// poll(2) over non-blocking sockets, libmodbus (Debian libmodbus-dev) for the protocol data units.
//
// It knows the register map (register_map.h) but nothing of the simulation. The simulation
// thread and the io thread meet in two places only, neither of which makes the simulation wait:
//   - the image: every table as the simulation last published it (mutex-guarded); a request is
//     answered from it at once;
//   - the writes: every cell a client wrote, queued (mutex-guarded, bounded) for the simulation
//     thread, which takes them between two slices.
// The io thread frames the requests itself (MBAP header checked: protocol 0, length 2..254) so
// that a slow or broken client never holds it: bytes are gathered per connection without
// blocking, at most one ADU (260 bytes) each. Only a request whose length, function, unit,
// addresses and values all check goes to modbus_reply(); the rest get an exception response or,
// for a malformed header, a closed connection.
#pragma once

#include "scenarios/modbus/register_map.h"

#include <chrono>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace rcsim::modbus {

class ModbusServer {
public:
    static constexpr std::size_t kMaxConnections = 16;         // the 17th is closed at once
    static constexpr std::chrono::milliseconds kIdleTimeout{60000}; // no complete request: closed
    static constexpr std::size_t kMaxPendingWrites = 4096;      // cells not yet taken: exception 06
    static constexpr std::uint8_t kUnitId = 1;                  // 255 is taken too (TCP's "none")

    struct Write {
        Table table;
        std::uint16_t address, value;
    };
    /// What the clients read: each table as the simulation last published it. `writes_taken`:
    /// how many writes the simulation had taken when it made the image; until it has taken every
    /// write, coils and holding registers keep what the clients wrote.
    struct Image {
        std::vector<std::uint8_t> coils, discrete_inputs;
        std::vector<std::uint16_t> input_registers, holding_registers;
        std::uint64_t writes_taken = 0;
    };

    /// Binds HOST:PORT (numeric IPv4; port 0 = ephemeral) and starts the io thread. Throws
    /// ConfigError naming the address when it cannot be bound. `idle_timeout`: a connection
    /// without a complete request for that long is closed (`rcsim run` keeps the default; a
    /// test gives a short one).
    ModbusServer(const std::string& host, unsigned port, std::ostream& log,
                 std::chrono::milliseconds idle_timeout = kIdleTimeout);
    ~ModbusServer();
    ModbusServer(const ModbusServer&) = delete;
    ModbusServer& operator=(const ModbusServer&) = delete;

    unsigned port() const { return port_; }

    // ---- the simulation thread's side; none of these waits for a client ----
    /// The cells written since the last call, in arrival order; `taken` becomes the count of all
    /// writes taken so far (for the next image).
    std::vector<Write> take_writes(std::uint64_t& taken);
    void publish(Image image);

    class Impl;

private:
    std::unique_ptr<Impl> impl_;
    unsigned port_ = 0;
};

} // namespace rcsim::modbus
