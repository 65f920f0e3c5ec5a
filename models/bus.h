// rcsim — the 8086-side bus as seen by peripherals.
//
// Peripherals are TLM-2.0 targets (blocking transport). Every transaction carries a BusExtension
// that says what the 8086 bus cycle is (status S2..S0 decoded), which byte lanes are active (A0 and
// BHE#), and when T1 of the cycle starts in absolute simulated time. The target answers with the
// number of Tw wait states it inserts: READY held low, or an IDT7130 BUSY stretching the cycle.
//
// Convention (see docs/architecture.md "Time model"):
// - The initiator syncs its local time before an I/O or DP-RAM access, so sc_time_stamp() equals
//   `start` and the `delay` argument of b_transport is SC_ZERO_TIME on entry.
// - The target never calls wait(); it reports its latency in `wait_states` only and leaves `delay`
//   alone. The initiator turns wait states into cycles of its own clock.
// - Addresses reaching a target are local offsets (the router subtracts the mapped base).
#pragma once

#include <systemc>
#include <tlm>

#include <cstdint>
#include <string>

namespace rcsim {

/// The kind of bus cycle, as decoded from the 8086 status lines S2..S0 (minimum mode: M/IO, DT/R).
enum class BusCycle : std::uint8_t {
    int_ack,    // S=000, INTA
    io_read,    // S=001
    io_write,   // S=010
    halt,       // S=011
    code_fetch, // S=100
    mem_read,   // S=101
    mem_write,  // S=110
    passive,    // S=111
};

const char* to_string(BusCycle kind);
inline bool is_write(BusCycle k) { return k == BusCycle::io_write || k == BusCycle::mem_write; }
inline bool is_io(BusCycle k) { return k == BusCycle::io_read || k == BusCycle::io_write; }

/// What a bus transaction carries besides address and data.
struct BusExtension : tlm::tlm_extension<BusExtension> {
    BusCycle kind = BusCycle::passive;
    bool a0 = false;           // address bit 0 as driven in T1
    bool bhe = false;          // BHE# asserted (odd byte lane D8..D15 active)
    sc_core::sc_time start;    // absolute time of T1
    unsigned wait_states = 0;  // out: Tw states the target inserted (READY/BUSY)
    int initiator = 0;         // which port/master issued the cycle (DP-RAM: 0 left, 1 right)

    tlm::tlm_extension_base* clone() const override { return new BusExtension(*this); }
    void copy_from(const tlm::tlm_extension_base& other) override {
        *this = static_cast<const BusExtension&>(other);
    }
};

/// A target's declaration of the reads an initiator may make without first syncing kernel time
/// to the cycle's T1 (docs/architecture.md "Stable reads"). A read of [address, address + len)
/// (a local offset) is stable when the target answers it, and leaves itself in, exactly what it
/// would at T1 however early in kernel time the access is made, provided nothing the kernel
/// schedules runs in between: its value depends on the target's state only (never on
/// sc_time_stamp()), that state changes only at the target's own events or by other agents'
/// accesses (each one a kernel event of theirs), and the read changes nothing another agent can
/// observe before T1. The initiator makes such a read early only when T1 lies before the next
/// pending kernel event. A timer count, a status that follows the time, a read that clears a flag
/// or an interrupt: not stable.
class StableReads {
public:
    virtual bool read_is_stable(std::uint64_t address, unsigned len) const = 0;

protected:
    ~StableReads() = default;
};

/// Result of one bus access made through bus_access().
struct BusResult {
    tlm::tlm_response_status status = tlm::TLM_INCOMPLETE_RESPONSE;
    unsigned wait_states = 0;
    bool ok() const { return status == tlm::TLM_OK_RESPONSE; }
};

/// Performs one blocking bus cycle through `socket` with a stack-allocated payload and extension.
/// `len` is 1 or 2 (byte or word); data is little-endian as on the 8086 data bus.
template <typename Socket>
BusResult bus_access(Socket& socket, BusCycle kind, std::uint64_t address, std::uint8_t* data,
                     unsigned len, const sc_core::sc_time& start, int initiator = 0) {
    tlm::tlm_generic_payload gp;
    BusExtension ext;
    ext.kind = kind;
    ext.a0 = address & 1;
    ext.bhe = (len == 2) || (address & 1);
    ext.start = start;
    ext.initiator = initiator;
    gp.set_command(is_write(kind) ? tlm::TLM_WRITE_COMMAND : tlm::TLM_READ_COMMAND);
    if (kind == BusCycle::int_ack) gp.set_command(tlm::TLM_READ_COMMAND);
    gp.set_address(address);
    gp.set_data_ptr(data);
    gp.set_data_length(len);
    gp.set_streaming_width(len);
    gp.set_byte_enable_ptr(nullptr);
    gp.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
    gp.set_extension(&ext);
    // Detach the stack extension however b_transport returns: if a target raises an SC_REPORT_ERROR
    // (thrown), the payload's destructor must not free it.
    struct Detach {
        tlm::tlm_generic_payload& gp;
        BusExtension* ext;
        ~Detach() { gp.clear_extension(ext); }
    } detach{gp, &ext};
    sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
    socket->b_transport(gp, delay);
    return BusResult{gp.get_response_status(), ext.wait_states};
}

/// A target's view of a transaction's extension: the initiator's own (so wait states written
/// here reach it), or, for initiators that sent none (plain TLM test benches), a local default
/// with the kind derived from the command and start = now.
class BusView {
public:
    BusView(tlm::tlm_generic_payload& gp, bool io_space);
    BusExtension& operator*() { return *ext_; }
    BusExtension* operator->() { return ext_; }

private:
    BusExtension fallback_;
    BusExtension* ext_;
};

} // namespace rcsim
