// rcsim — the Modbus TCP server's simulation side (docs/monitor.md "Modbus TCP"): between two
// slices of the monitor's run (BoardMonitor::between_slices) it takes what the clients wrote,
// acts on it through the monitor's own controls (pause, step, the main CPU's token dispatcher),
// and publishes the register map's values for the io thread to answer reads with.
//
// While the run is paused, the pause and step coils act at once; a servo coil or a mailbox "go"
// written meanwhile is held and takes effect on resume, or at the start of the next step (the
// mailbox's registers themselves are stored at once).
#pragma once

#include "models/plumbing/log_limiter.h"
#include "scenarios/modbus/modbus_server.h"
#include "scenarios/monitor/board_monitor.h"

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace rcsim::modbus {

/// The log of what the clients' writes did, as "modbus: ..." lines: at most kLinesPerSecond in a
/// second of wall time (a client writing the pause coil in a loop would flood stderr); the lines
/// left out are counted and summed up in one line once the second is over.
class WriteLog {
public:
    static constexpr unsigned kLinesPerSecond = 10;
    explicit WriteLog(std::ostream& out);
    ~WriteLog() { flush(true); }
    WriteLog(const WriteLog&) = delete;
    WriteLog& operator=(const WriteLog&) = delete;
    void line(const std::string& text) { lines_.line("modbus: " + text); }
    /// The summary of a second that is over (`now`: whatever the second).
    void flush(bool now = false) { lines_.flush(now); }

private:
    LogLimiter lines_;
};

class ModbusBridge {
public:
    /// Starts the server on HOST:PORT and attaches to `mon`'s slices.
    ModbusBridge(monitor::BoardMonitor& mon, const std::string& host, unsigned port, std::ostream& log);
    unsigned port() const { return server_.port(); }

private:
    monitor::BoardMonitor& mon_;
    ModbusServer server_;
    WriteLog log_;
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
    std::string now_text() const;
};

} // namespace rcsim::modbus
