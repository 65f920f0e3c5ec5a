// rcsim — Intel 8259A Programmable Interrupt Controller. See pic8259.h and README.md.
#include "pic8259/pic8259.h"

#include "models/plumbing/hex.h"

#include <string>

namespace rcsim {

namespace {

constexpr const char* kMsgType = "rcsim/pic8259";
// Legal 8259A modes this model does not implement: a ROM that selects one is not wrong, the
// model cannot follow it (rcsim reports "unsupported by the model", exit code 3).
constexpr const char* kUnsupported = "rcsim/pic8259/unsupported";

std::uint8_t bit(unsigned n) { return static_cast<std::uint8_t>(1u << n); }

const char* expected_icw(Pic8259::InitState s) {
    switch (s) {
    case Pic8259::InitState::icw2: return "ICW2";
    case Pic8259::InitState::icw3: return "ICW3";
    case Pic8259::InitState::icw4: return "ICW4";
    default: return "an OCW";
    }
}

} // namespace

const char* to_string(Pic8259::InitState state) {
    switch (state) {
    case Pic8259::InitState::power_on: return "power-on (not initialised)";
    case Pic8259::InitState::icw2: return "waiting for ICW2";
    case Pic8259::InitState::icw3: return "waiting for ICW3";
    case Pic8259::InitState::icw4: return "waiting for ICW4";
    case Pic8259::InitState::ready: return "ready";
    }
    return "?";
}

Pic8259::Pic8259(sc_core::sc_module_name name)
    : sc_module(name), bus("bus"), inta("inta"), ir("ir", 8), intr("intr"), settle_("settle") {
    bus.register_b_transport(this, &Pic8259::b_transport_bus);
    bus.register_transport_dbg(this, &Pic8259::transport_dbg);
    inta.register_b_transport(this, &Pic8259::b_transport_inta);

    SC_HAS_PROCESS(Pic8259);
    SC_METHOD(sample_ir);
    for (auto& pin : ir) sensitive << pin.value_changed();
    SC_METHOD(update_intr);
    sensitive << settle_.event();
}

void Pic8259::end_of_elaboration() {
    if (a0_shift > 15)
        SC_REPORT_ERROR(kMsgType, (std::string(name()) + ": a0_shift " + std::to_string(a0_shift) +
                                   " is out of range (0..15)").c_str());
}

void Pic8259::reset() {
    icw1_ = icw2_ = icw3_ = icw4_ = 0;
    imr_ = isr_ = edge_ = 0;
    lowest_ = 7;
    rotate_aeoi_ = smm_ = read_isr_ = poll_ = false;
    init_ = InitState::power_on;
    second_inta_ = false;
    settle_.request();
}

// In edge mode the request is the edge latch ANDed with the pin (data sheet priority cell): a
// request that goes away before the first INTA is no longer in IRR, which is what makes the
// spurious IR7 happen. In level mode the pin is the request.
std::uint8_t Pic8259::irr() const { return level_triggered() ? level_ : (edge_ & level_); }

// ---------------------------------------------------------------------------------------------
// Processes

void Pic8259::sample_ir() {
    std::uint8_t now = 0;
    for (unsigned n = 0; n < 8; ++n)
        if (ir[n].read()) now |= bit(n);
    edge_ |= now & ~level_; // low->high transitions arm the edge latch
    level_ = now;
    settle_.request();
}

void Pic8259::update_intr() {
    const bool asserted = init_ == InitState::ready && resolve() >= 0;
    if (intr.read() != asserted) intr.write(asserted);
    if (on_update) on_update();
}

// ---------------------------------------------------------------------------------------------
// Priority resolver

// Walk the levels from highest to lowest priority; an in-service level blocks itself and
// everything below it. In special mask mode a masked in-service level does not block (that is
// what lets lower levels through while a handler runs with its own level masked).
int Pic8259::resolve() const {
    const std::uint8_t requests = irr() & ~imr_;
    const std::uint8_t in_service = blocking_isr();
    for (unsigned p = 0; p < 8; ++p) {
        const unsigned level = level_at(p);
        if (in_service & bit(level)) return -1;
        if (requests & bit(level)) return static_cast<int>(level);
    }
    return -1;
}

// The walk of resolve() for one level taken as requested: the first in-service level (blocking
// it and everything below) or request met before it says what holds it.
Pic8259::Hold Pic8259::hold(unsigned level) const {
    Hold h;
    level &= 7;
    if (init_ != InitState::ready) {
        h.kind = Hold::Kind::not_ready;
    } else if (imr_ & bit(level)) {
        h.kind = Hold::Kind::masked;
    } else {
        const std::uint8_t requests = irr() & ~imr_;
        const std::uint8_t in_service = blocking_isr();
        for (unsigned p = 0; p < 8; ++p) {
            const unsigned l = level_at(p);
            if (in_service & bit(l)) {
                h.kind = Hold::Kind::in_service;
                h.by = static_cast<int>(l);
                break;
            }
            if (l == level) break;
            if (requests & bit(l)) {
                h.kind = Hold::Kind::priority;
                h.by = static_cast<int>(l);
                break;
            }
        }
    }
    return h;
}

// The IS bit a non-specific EOI clears. In special mask mode an IS bit masked in IMR is skipped
// (data sheet: "will not be cleared by a non-specific EOI if the 8259A is in the Special Mask Mode").
int Pic8259::highest_in_service() const {
    const std::uint8_t candidates = blocking_isr();
    for (unsigned p = 0; p < 8; ++p)
        if (candidates & bit(level_at(p))) return static_cast<int>(level_at(p));
    return -1;
}

void Pic8259::non_specific_eoi(bool rotate) {
    const int level = highest_in_service();
    if (level < 0) return; // nothing in service: neither EOI nor rotation has anything to act on
    isr_ &= ~bit(level);
    if (rotate) lowest_ = static_cast<unsigned>(level);
}

void Pic8259::acknowledge(unsigned level) {
    isr_ |= bit(level);
    edge_ &= ~bit(level); // edge lock-out: the line must go low before it can request again
    ++acks_[level];
}

// ---------------------------------------------------------------------------------------------
// Register interface

std::uint8_t Pic8259::read_register(bool a0) {
    if (poll_) return poll_read(); // a poll command turns the next read, A0 either, into an INTA
    if (a0) return imr_;
    return read_isr_ ? isr_ : irr();
}

void Pic8259::write_register(bool a0, std::uint8_t value) {
    if (!a0 && (value & ICW1_INIT)) {
        write_icw1(value);
    } else if (a0) {
        switch (init_) {
        case InitState::icw2: write_icw2(value); break;
        case InitState::icw3: write_icw3(value); break;
        case InitState::icw4: write_icw4(value); break;
        case InitState::ready: write_ocw1(value); break;
        case InitState::power_on:
            SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": OCW1 0x" + hex(value) +
                                         " written before ICW1 (chip not initialised): ignored").c_str());
            break;
        }
    } else if (init_ != InitState::ready) {
        const char* which = (value & OCW3_SEL) ? "OCW3" : "OCW2";
        const std::string why = init_ == InitState::power_on
                                    ? "before ICW1 (chip not initialised)"
                                    : std::string("while ") + expected_icw(init_) + " is expected";
        SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": " + which + " 0x" + hex(value) + " written " +
                                     why + ": ignored").c_str());
    } else if (value & OCW3_SEL) {
        write_ocw3(value);
    } else {
        write_ocw2(value);
    }
    settle_.request();
}

// ICW1 starts initialisation. Its side effects are the data sheet's list, no more: ISR and the
// rotate-in-AEOI flag are not touched.
void Pic8259::write_icw1(std::uint8_t value) {
    if (!(value & ICW1_IC4)) {
        SC_REPORT_ERROR(kUnsupported, (std::string(name()) + ": ICW1 0x" + hex(value) +
                                       " has IC4=0, which selects MCS-80/85 mode; only 8086 mode is "
                                       "modelled (set IC4 and ICW4.uPM, e.g. ICW1 0x13)").c_str());
        return; // only reached when errors are configured not to throw: the write is dropped
    }
    if (!(value & ICW1_SNGL)) {
        SC_REPORT_ERROR(kUnsupported, (std::string(name()) + ": ICW1 0x" + hex(value) +
                                       " has SNGL=0 (cascade mode), which is not modelled: the board has "
                                       "one 8259A (set SNGL, e.g. ICW1 0x13)").c_str());
        return;
    }
    icw1_ = value;
    edge_ = 0;        // edge-sense circuit reset: a line already high must go low and high again
    imr_ = 0;         // every level unmasked: OCW1 must follow before STI
    lowest_ = 7;      // IR0 highest ... IR7 lowest
    smm_ = false;     // special mask mode cleared
    read_isr_ = false; // status read selects IRR
    poll_ = false;
    init_ = InitState::icw2;
}

// 8086 mode: T7..T3 give the vector, the chip supplies bits 2..0; bits 2..0 of ICW2 are ignored.
void Pic8259::write_icw2(std::uint8_t value) {
    icw2_ = value;
    if (!(icw1_ & ICW1_SNGL))
        init_ = InitState::icw3;
    else
        init_ = (icw1_ & ICW1_IC4) ? InitState::icw4 : InitState::ready;
}

void Pic8259::write_icw3(std::uint8_t value) {
    icw3_ = value;
    init_ = (icw1_ & ICW1_IC4) ? InitState::icw4 : InitState::ready;
}

void Pic8259::write_icw4(std::uint8_t value) {
    if (!(value & ICW4_UPM)) {
        SC_REPORT_ERROR(kUnsupported, (std::string(name()) + ": ICW4 0x" + hex(value) +
                                       " has uPM=0, which selects MCS-80/85 mode; only 8086 mode is "
                                       "modelled (e.g. ICW4 0x01)").c_str());
        return;
    }
    icw4_ = value; // BUF, M/S and SFNM are stored; with a single chip and no transceiver they do nothing
    init_ = InitState::ready;
}

void Pic8259::write_ocw1(std::uint8_t value) { imr_ = value; }

void Pic8259::write_ocw2(std::uint8_t value) {
    const unsigned level = value & 7;
    switch (static_cast<Ocw2Command>(value >> 5)) {
    case OCW2_NONSPECIFIC_EOI: ++eois_; non_specific_eoi(false); break;
    case OCW2_ROTATE_NONSPEC_EOI: ++eois_; non_specific_eoi(true); break;
    case OCW2_SPECIFIC_EOI: ++eois_; isr_ &= ~bit(level); break;
    case OCW2_ROTATE_SPEC_EOI: ++eois_; isr_ &= ~bit(level); lowest_ = level; break;
    case OCW2_SET_PRIORITY: lowest_ = level; break;
    // The AEOI-rotation flag only: neither command touches the priority order (MAME resets it on 0x00).
    case OCW2_ROTATE_AEOI_SET: rotate_aeoi_ = true; break;
    case OCW2_ROTATE_AEOI_CLEAR: rotate_aeoi_ = false; break;
    case OCW2_NOP: break;
    }
}

// RR=0 and ESMM=0 mean "no change" for their fields; P wins over a register-read request because
// the poll is checked first at the next read.
void Pic8259::write_ocw3(std::uint8_t value) {
    if (value & OCW3_RR) read_isr_ = value & OCW3_RIS;
    if (value & OCW3_ESMM) smm_ = value & OCW3_SMM;
    if (value & OCW3_P) poll_ = true;
}

// Poll word: I 0 0 0 0 W2 W1 W0. A pending request is acknowledged as by a first INTA (ISR set,
// edge latch cleared); there is no second INTA, so no automatic EOI happens.
std::uint8_t Pic8259::poll_read() {
    poll_ = false;
    ++polls_;
    const int level = resolve();
    if (level < 0) return 0x00;
    acknowledge(static_cast<unsigned>(level));
    settle_.request();
    return static_cast<std::uint8_t>(0x80 | level);
}

// ---------------------------------------------------------------------------------------------
// INTA sequence (8086 mode: two cycles)

std::uint8_t Pic8259::inta_cycle(const sc_core::sc_time& start) {
    IntaEvent ev;
    ev.time = start;
    if (!second_inta_) {
        // First INTA: freeze the resolver's choice. A request that has gone away by now leaves
        // nothing to acknowledge: the chip answers as for IR7 but sets no IS bit.
        const int level = resolve();
        inta_spurious_ = level < 0;
        inta_level_ = inta_spurious_ ? 7 : static_cast<unsigned>(level);
        if (inta_spurious_)
            ++spurious_;
        else
            acknowledge(inta_level_);
        last_ack_time_ = start;
        last_ack_level_ = static_cast<int>(inta_level_);
        second_inta_ = true;
        ev.cycle = 1;
        ev.data = 0xFF; // the 8259A does not drive the bus in the first 8086 INTA
    } else {
        // Second INTA: drive the vector; AEOI happens at its trailing edge.
        ev.cycle = 2;
        ev.data = static_cast<std::uint8_t>(vector_base() | inta_level_);
        if (auto_eoi() && !inta_spurious_) {
            isr_ &= ~bit(inta_level_);
            if (rotate_aeoi_) lowest_ = inta_level_;
        }
        second_inta_ = false;
    }
    ev.level = inta_level_;
    ev.spurious = inta_spurious_;
    settle_.request();
    if (on_inta) on_inta(ev);
    return ev.data;
}

// ---------------------------------------------------------------------------------------------
// TLM

void Pic8259::b_transport_bus(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
    BusView view(gp, true);
    const std::uint64_t offset = gp.get_address();
    const std::uint64_t below_a0 = (std::uint64_t{1} << a0_shift) - 1;
    if (gp.get_data_length() != 1 || gp.get_byte_enable_ptr() != nullptr) {
        SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": " + std::to_string(gp.get_data_length()) +
                                     "-byte access at offset " + std::to_string(offset) +
                                     ": the 8259A is an 8-bit device, use byte accesses").c_str());
        gp.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
        return;
    }
    if ((offset & below_a0) != 0 || (offset >> a0_shift) > 1) {
        SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": offset " + std::to_string(offset) +
                                     " decodes to no register (A0 is offset bit " +
                                     std::to_string(a0_shift) + ")").c_str());
        gp.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
        return;
    }
    const bool a0 = (offset >> a0_shift) & 1;
    std::uint8_t* data = gp.get_data_ptr();
    if (gp.is_write())
        write_register(a0, data[0]);
    else if (gp.is_read())
        data[0] = read_register(a0);
    view->wait_states = 0;
    gp.set_response_status(tlm::TLM_OK_RESPONSE);
}

void Pic8259::b_transport_inta(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
    BusView view(gp, false);
    const auto* ext = gp.get_extension<BusExtension>();
    if (!gp.is_read() || (ext && ext->kind != BusCycle::int_ack) || gp.get_data_length() < 1) {
        SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": inta socket got a " + to_string(view->kind) +
                                     " cycle; only INTA read cycles belong there").c_str());
        gp.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
        return;
    }
    std::uint8_t* data = gp.get_data_ptr();
    for (unsigned i = 0; i < gp.get_data_length(); ++i) data[i] = 0xFF; // D15..D8 float
    if (init_ != InitState::ready) {
        SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": INTA cycle while the chip is " +
                                     to_string(init_) + ": bus left floating (0xFF)").c_str());
    } else {
        data[0] = inta_cycle(view->start);
    }
    view->wait_states = 0;
    gp.set_response_status(tlm::TLM_OK_RESPONSE);
}

// Debug reads see the register the next read would return, without acknowledging a poll;
// debug writes are refused (a write to an 8259A always has side effects).
unsigned Pic8259::transport_dbg(tlm::tlm_generic_payload& gp) {
    const std::uint64_t offset = gp.get_address();
    if (!gp.is_read() || gp.get_data_length() < 1 || (offset & ((std::uint64_t{1} << a0_shift) - 1)) ||
        (offset >> a0_shift) > 1)
        return 0;
    const bool a0 = (offset >> a0_shift) & 1;
    gp.get_data_ptr()[0] = a0 ? imr_ : (read_isr_ ? isr_ : irr());
    return 1;
}

} // namespace rcsim
