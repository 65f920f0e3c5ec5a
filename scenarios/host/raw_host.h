// rcsim — a raw serial host: sends given byte strings at given simulation times and records
// every byte it receives. For tests, and for users who bring their own ROM and protocol.
//
// Byte strings are written with escapes (\x05, \n, \r, \t, \0, \\, and \ENQ, \ACK, ... by name;
// see proto::unescape). The record file gets every received byte, raw, in arrival order; the
// optional log file one text line per byte: "<time ps> <hex> <P><F>" (parity, framing error),
// and "<time ps> BREAK on|off".
#pragma once

#include "models/plumbing/output_file.h"
#include "models/serial_line.h"
#include "scenarios/host/host_line.h"

#include <systemc>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

struct RawHostConfig {
    struct Send {
        sc_core::sc_time at; // START edge of the first byte (later if the previous send still runs)
        std::string bytes;   // raw bytes (already unescaped)
    };
    SerialFormat format = SerialFormat::rs232(9600);
    std::vector<Send> sends;
    std::string record_path; // "" = no file
    std::string log_path;    // "" = no file

    /// Adds a send from escaped text; throws std::invalid_argument naming a bad escape.
    void add(const sc_core::sc_time& at, const std::string& escaped);
};

class RawHost : public sc_core::sc_module, public HostLineEnd {
public:
    struct Received {
        sc_core::sc_time at; // end of the first stop bit
        std::uint8_t byte;
        bool parity_error;
        bool framing_error;
    };

    /// Throws rcsim::ConfigError naming a file that cannot be opened.
    RawHost(sc_core::sc_module_name name, const RawHostConfig& cfg);

    const std::vector<Received>& received() const { return received_; }
    /// The received bytes as a string.
    std::string text() const;
    const std::vector<std::pair<sc_core::sc_time, bool>>& breaks() const { return breaks_; }
    std::uint64_t bytes_sent() const { return sent_; }
    /// Flushes the record and log files; throws rcsim::ConfigError naming one that could not be
    /// written completely.
    void finish_files();

    SerialFormat rx_format() const override { return cfg_.format; }
    void rx_char(const SerialRx& c) override;
    void rx_break(bool active) override;

private:
    RawHostConfig cfg_;
    std::vector<Received> received_;
    std::vector<std::pair<sc_core::sc_time, bool>> breaks_;
    std::uint64_t sent_ = 0;
    std::optional<OutputFile> record_, log_; // models/plumbing/output_file.h

    void end_of_elaboration() override;
    void run();
};

} // namespace rcsim
