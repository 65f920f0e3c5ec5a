// rcsim — what every simulated host shares: its end of a SerialLine (which line, which side).
#pragma once

#include "models/serial_line.h"

#include <stdexcept>
#include <string>

namespace rcsim {

/// A simulated host's connection to its line. The host transmits with line_->transmit(side_, ...).
class HostLineEnd : public SerialEndpoint {
public:
    /// Attaches the host to `side` of `line`; it transmits from and receives on that side.
    void connect(SerialLine& line, SerialLine::Side side) {
        line.attach(side, *this);
        line_ = &line;
        side_ = side;
    }

protected:
    /// For end_of_elaboration(): a host nobody connected is an elaboration error naming it.
    void require_connected(const char* host_name) const {
        if (!line_) throw std::invalid_argument(std::string(host_name) + ": not connected to a serial line");
    }

    SerialLine* line_ = nullptr;
    SerialLine::Side side_ = SerialLine::b;
};

} // namespace rcsim
