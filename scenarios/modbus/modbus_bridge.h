// rcsim — the Modbus TCP server's simulation side (docs/monitor.md "Modbus TCP"): between two
// slices of the monitor's run (BoardMonitor::between_slices) it takes what the clients wrote,
// acts on it through the monitor's own controls (pause, step, the main CPU's token dispatcher),
// and publishes the register map's values for the io thread to answer reads with.
//
// While the run is paused, the pause and step coils act at once; a servo coil or a mailbox "go"
// written meanwhile is held and takes effect on resume, or at the start of the next step (the
// mailbox's registers themselves are stored at once).
#pragma once

#include "scenarios/modbus/modbus_server.h"
#include "scenarios/monitor/board_monitor.h"

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace rcsim::modbus {

class ModbusBridge {
public:
    /// Starts the server on HOST:PORT and attaches to `mon`'s slices.
    ModbusBridge(monitor::BoardMonitor& mon, const std::string& host, unsigned port, std::ostream& log);
    unsigned port() const { return server_.port(); }

private:
    monitor::BoardMonitor& mon_;
    ModbusServer server_;
    std::ostream& log_;
    std::vector<std::uint16_t> holding_;      // as the clients wrote them, and the mailbox's results
    std::vector<ModbusServer::Write> held_;   // servo coils and "go" written while paused
    std::uint64_t taken_ = 0;
    std::chrono::steady_clock::time_point last_publish_;

    void serve();
    void apply(const ModbusServer::Write& w);
    /// A servo coil or "go": now when running or `held` (released by a resume or a step), else held.
    void act(const ModbusServer::Write& w, bool held = false);
    void release_held();
    void execute_mailbox();
    void publish();
};

} // namespace rcsim::modbus
