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

/// A generic payload with a BusExtension attached, for bus_access(). An initiator that makes
/// many accesses keeps one: a tlm_generic_payload allocates its extension array when it is
/// constructed and frees it when destroyed (about 300 host instructions per access, 4 % of an
/// idle controller's run). Every field an access sets is set again by the next; one blocking
/// access at a time (its process waits inside b_transport; no other process uses the payload).
class BusPayload {
public:
    BusPayload() { gp_.set_extension(&ext_); }
    // The extension is ours: detached before the payload's destructor would free it.
    ~BusPayload() { gp_.clear_extension(&ext_); }
    BusPayload(const BusPayload&) = delete;
    BusPayload& operator=(const BusPayload&) = delete;

    /// Performs one blocking bus cycle through `socket`. `len` is 1 or 2 (byte or word); data is
    /// little-endian as on the 8086 data bus.
    template <typename Socket>
    BusResult access(Socket& socket, BusCycle kind, std::uint64_t address, std::uint8_t* data, unsigned len,
                     const sc_core::sc_time& start, int initiator = 0) {
        ext_.kind = kind;
        ext_.a0 = address & 1;
        ext_.bhe = (len == 2) || (address & 1);
        ext_.start = start;
        ext_.wait_states = 0;
        ext_.initiator = initiator;
        gp_.set_command(is_write(kind) ? tlm::TLM_WRITE_COMMAND : tlm::TLM_READ_COMMAND);
        gp_.set_address(address);
        gp_.set_data_ptr(data);
        gp_.set_data_length(len);
        gp_.set_streaming_width(len);
        gp_.set_byte_enable_ptr(nullptr);
        gp_.set_byte_enable_length(0);
        gp_.set_dmi_allowed(false);
        gp_.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
        sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
        socket->b_transport(gp_, delay);
        return BusResult{gp_.get_response_status(), ext_.wait_states};
    }

private:
    tlm::tlm_generic_payload gp_;
    BusExtension ext_;
};

/// One blocking bus cycle through `socket` with a payload of its own (BusPayload::access).
template <typename Socket>
BusResult bus_access(Socket& socket, BusCycle kind, std::uint64_t address, std::uint8_t* data,
                     unsigned len, const sc_core::sc_time& start, int initiator = 0) {
    BusPayload payload;
    return payload.access(socket, kind, address, data, len, start, initiator);
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
