// rcsim — Intel 8259A Programmable Interrupt Controller (single chip, 8086 mode).
//
// Source: Intel 8259A/8259A-2 data sheet (programming model, priority cell, 8086 INTA sequence);
// the sources and the behaviours other models get wrong are listed in pic8259/README.md.
//
//             +---------+
//   CS/A0 --->|  bus    |  two registers: A0=0 ICW1/OCW2/OCW3, IRR/ISR/poll; A0=1 ICW2-4/OCW1, IMR
//   INTA# --->|  inta   |  1st INTA: ISR set, IRR/edge latch cleared; 2nd: vector, AEOI
//   IR0..7 -->|  ir[n]  |  true = request
//             |  intr   |---> INT (true = asserted)
//             +---------+
//
// Pin changes are not decided inline: IR changes and register writes call Settler::request(),
// and one SC_METHOD recomputes INT after every line that moved in that instant has settled.
// The model never calls wait() and inserts no wait states (the board's I/O wait state is the
// CPU's business). Everything the model cannot represent faithfully (MCS-80/85 mode, cascade)
// is refused with SC_REPORT_ERROR naming the offending ICW; sequencing mistakes a real chip
// would silently mis-decode are ignored with an SC_REPORT_WARNING. See pic8259/README.md.
#pragma once

#include "models/bus.h"
#include "models/irq.h"

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include <array>
#include <cstdint>
#include <functional>

namespace rcsim {

class Pic8259 : public sc_core::sc_module {
public:
    // clang-format off
    enum Icw1Bits : std::uint8_t {
        ICW1_IC4  = 1 << 0,  // ICW4 follows
        ICW1_SNGL = 1 << 1,  // single chip, no ICW3
        ICW1_ADI  = 1 << 2,  // call address interval (MCS-80/85 only)
        ICW1_LTIM = 1 << 3,  // level-triggered inputs
        ICW1_INIT = 1 << 4,  // D4 = 1 marks ICW1 on A0 = 0
    };
    enum Icw4Bits : std::uint8_t {
        ICW4_UPM  = 1 << 0,  // 8086/8088 mode
        ICW4_AEOI = 1 << 1,  // automatic EOI at the end of the second INTA
        ICW4_MS   = 1 << 2,  // buffered master (only with BUF)
        ICW4_BUF  = 1 << 3,  // buffered mode: SP/EN# becomes a transceiver enable
        ICW4_SFNM = 1 << 4,  // special fully nested mode (cascade masters)
    };
    enum Ocw3Bits : std::uint8_t {
        OCW3_RIS  = 1 << 0,  // with RR: 1 = read ISR, 0 = read IRR
        OCW3_RR   = 1 << 1,  // RIS is valid (0 = no change)
        OCW3_P    = 1 << 2,  // poll: the next read is an acknowledge
        OCW3_SEL  = 1 << 3,  // D4:D3 = 01 selects OCW3 (00 = OCW2)
        OCW3_SMM  = 1 << 5,  // with ESMM: 1 = set, 0 = reset special mask mode
        OCW3_ESMM = 1 << 6,  // SMM is valid (0 = no change)
    };
    /// OCW2 command field R SL EOI (bits 7:5).
    enum Ocw2Command : std::uint8_t {
        OCW2_ROTATE_AEOI_CLEAR  = 0b000,
        OCW2_NONSPECIFIC_EOI    = 0b001,
        OCW2_NOP                = 0b010,
        OCW2_SPECIFIC_EOI       = 0b011,
        OCW2_ROTATE_AEOI_SET    = 0b100,
        OCW2_ROTATE_NONSPEC_EOI = 0b101,
        OCW2_SET_PRIORITY       = 0b110,
        OCW2_ROTATE_SPEC_EOI    = 0b111,
    };
    // clang-format on

    /// Where the initialization sequence stands.
    enum class InitState { power_on, icw2, icw3, icw4, ready };

    /// One INTA bus cycle as the chip saw it (for probes and reports).
    struct IntaEvent {
        sc_core::sc_time time;    // T1 of the INTA cycle
        unsigned cycle = 1;       // 1 = first INTA (ISR set), 2 = second (vector driven)
        unsigned level = 7;       // the level acknowledged (7 when spurious)
        bool spurious = false;    // no request at the first INTA: IR7 vector, ISR7 not set
        std::uint8_t data = 0xFF; // what the chip drove: 0xFF (floating) on the first, the vector on the second
    };

    tlm_utils::simple_target_socket<Pic8259> bus;  // CS# region; A0 = bit a0_shift of the offset
    tlm_utils::simple_target_socket<Pic8259> inta; // INTA#: each transaction is one INTA cycle
    sc_core::sc_vector<IrqIn> ir;                  // IR0..IR7, true = request
    IrqOut intr;                                   // INT, true = asserted

    /// Property: which bit of the local offset is the chip's A0 (1: the board maps it at 0xC0/0xC2,
    /// the 8-bit chip on the low byte lane). Checked at end of elaboration (0..15).
    unsigned a0_shift = 1;

    /// Probe hook, called at every INTA cycle after the chip has acted on it.
    std::function<void(const IntaEvent&)> on_inta;
    /// Probe hook, called after every re-evaluation of INT (an IR change, a register write, an
    /// INTA cycle or a poll, once it has settled), with the new state in place: where a probe
    /// asks hold() again.
    std::function<void()> on_update;

    /// Why a request of `level` is not the one INT presents now, the level taken as requested
    /// (its own IRR bit is not looked at): what holds an interrupt in the chip (probes).
    struct Hold {
        enum class Kind : std::uint8_t {
            none,       // presented: INT is (or, after the settle, will be) up for this level
            not_ready,  // the chip is not initialised (INT held low)
            masked,     // the level's IMR bit is set
            in_service, // `by` is in service and blocks it: a higher priority, or the level itself
            priority,   // `by`, a higher-priority request, is presented first
        };
        Kind kind = Kind::none;
        int by = -1; // in_service, priority: the level
        bool operator==(const Hold& o) const { return kind == o.kind && by == o.by; }
        bool operator!=(const Hold& o) const { return !(*this == o); }
    };
    Hold hold(unsigned level) const;

    explicit Pic8259(sc_core::sc_module_name name);

    /// Power-on state: not initialised (INT held low until ICW1..ICW4 complete), all registers 0.
    void reset();

    // Side-effect-free state, for tests, probes and reports.
    std::uint8_t irr() const;
    std::uint8_t isr() const { return isr_; }
    std::uint8_t imr() const { return imr_; }
    /// The level that currently has the lowest priority (7 after ICW1: IR0 highest).
    unsigned lowest_priority() const { return lowest_; }
    InitState init_state() const { return init_; }
    bool level_triggered() const { return icw1_ & ICW1_LTIM; }
    bool auto_eoi() const { return icw4_ & ICW4_AEOI; }
    bool rotate_in_auto_eoi() const { return rotate_aeoi_; }
    bool special_mask_mode() const { return smm_; }
    bool poll_pending() const { return poll_; }
    std::uint8_t vector_base() const { return icw2_ & 0xF8; }
    /// The level the priority resolver presents now, or -1 when none may interrupt.
    int pending_level() const { return resolve(); }

    // Counters.
    /// Times `level` entered service through an INTA sequence or a poll read.
    std::uint64_t acks(unsigned level) const { return acks_.at(level); }
    std::uint64_t spurious_acks() const { return spurious_; }
    std::uint64_t polls() const { return polls_; }
    std::uint64_t eoi_commands() const { return eois_; }
    /// Last first-INTA cycle: its time and the level it acknowledged (7 when spurious; -1 if none yet).
    const sc_core::sc_time& last_ack_time() const { return last_ack_time_; }
    int last_ack_level() const { return last_ack_level_; }

private:
    // Register file.
    std::uint8_t icw1_ = 0, icw2_ = 0, icw3_ = 0, icw4_ = 0;
    std::uint8_t imr_ = 0, isr_ = 0;
    std::uint8_t edge_ = 0;  // edge-sense latches (set by a rising IR, cleared at acknowledge/ICW1)
    std::uint8_t level_ = 0; // IR pin levels as last sampled
    unsigned lowest_ = 7;
    bool rotate_aeoi_ = false, smm_ = false, read_isr_ = false, poll_ = false;
    InitState init_ = InitState::power_on;

    // INTA sequence: the first cycle latches the level the second one reports.
    bool second_inta_ = false;
    unsigned inta_level_ = 7;
    bool inta_spurious_ = false;

    std::array<std::uint64_t, 8> acks_{};
    std::uint64_t spurious_ = 0, polls_ = 0, eois_ = 0;
    sc_core::sc_time last_ack_time_;
    int last_ack_level_ = -1;

    Settler settle_;

    void end_of_elaboration() override;

    // Processes.
    void sample_ir();
    void update_intr();

    // Bus side.
    void b_transport_bus(tlm::tlm_generic_payload& gp, sc_core::sc_time& delay);
    void b_transport_inta(tlm::tlm_generic_payload& gp, sc_core::sc_time& delay);
    unsigned transport_dbg(tlm::tlm_generic_payload& gp);
    std::uint8_t read_register(bool a0);
    void write_register(bool a0, std::uint8_t value);

    void write_icw1(std::uint8_t value);
    void write_icw2(std::uint8_t value);
    void write_icw3(std::uint8_t value);
    void write_icw4(std::uint8_t value);
    void write_ocw1(std::uint8_t value);
    void write_ocw2(std::uint8_t value);
    void write_ocw3(std::uint8_t value);

    std::uint8_t inta_cycle(const sc_core::sc_time& start);
    std::uint8_t poll_read();
    void acknowledge(unsigned level);

    // Priority resolver.
    unsigned level_at(unsigned priority) const { return (lowest_ + 1 + priority) & 7; }
    std::uint8_t blocking_isr() const { return smm_ ? (isr_ & ~imr_) : isr_; }
    int resolve() const;
    int highest_in_service() const;
    void non_specific_eoi(bool rotate);
};

const char* to_string(Pic8259::InitState state);

} // namespace rcsim
