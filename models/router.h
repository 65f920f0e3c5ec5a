// rcsim — address decoder for the 8086 bus (one for memory-mapped targets, one for I/O space).
//
// Maps [base, base+size) to one of its initiator sockets and forwards the transaction with the
// address rebased to the target's local offset (a chip select plus the low address lines). An
// access to no mapped range answers TLM_ADDRESS_ERROR_RESPONSE and is counted; the CPU model then
// sees an open bus (0xFF on reads), as on a board without a pull-down.
#pragma once

#include "models/bus.h"

#include <systemc>
#include <tlm>
#include <tlm_utils/multi_passthrough_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include <cstdint>
#include <string>
#include <vector>

namespace rcsim {

class Router : public sc_core::sc_module, public StableReads {
public:
    tlm_utils::simple_target_socket<Router> in;
    tlm_utils::multi_passthrough_initiator_socket<Router> out;

    /// io_space: decoded transactions without a BusExtension are treated as I/O cycles.
    Router(sc_core::sc_module_name name, bool io_space = false);

    /// Routes [base, base+size) to the target bound as out[port] (in bind order), adding
    /// `wait_states` Tw to every cycle into it (the board's READY logic for that chip select, on
    /// top of what the target itself answers). Throws std::invalid_argument on overlap.
    void map(std::uint64_t base, std::uint64_t size, unsigned port, const std::string& what,
             unsigned wait_states = 0);
    /// The stable-read declaration of the target mapped at `base` (nullptr: none of its reads is).
    void declare_stable(std::uint64_t base, const StableReads* target);
    /// The declaration of the target the address decodes to, for its local offset; false for an
    /// unmapped address or a target that declared nothing.
    bool read_is_stable(std::uint64_t address, unsigned len) const override;

    std::uint64_t unmapped_accesses() const { return unmapped_; }

private:
    struct Range {
        std::uint64_t base, size;
        unsigned port;
        std::string what;
        unsigned wait_states;
        const StableReads* stable = nullptr;
    };
    std::vector<Range> ranges_;
    std::uint64_t unmapped_ = 0;
    bool io_space_;

    const Range* decode(std::uint64_t addr) const;
    void b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time& delay);
    unsigned transport_dbg(tlm::tlm_generic_payload& gp);
};

} // namespace rcsim
