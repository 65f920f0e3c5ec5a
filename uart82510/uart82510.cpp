// rcsim — Intel 82510 Asynchronous Serial Controller (see uart82510.h and README.md).
#include "uart82510/uart82510.h"

#include "models/bus.h"
#include "models/clock.h"

#include <stdexcept>
#include <string>

namespace rcsim {

using namespace i82510;

namespace {
// Priority order of the GIR vector, highest first.
constexpr Source priority[] = {timer, tx_machine, rx_machine, rx_fifo, tx_fifo, modem};
constexpr std::uint8_t RST_LATCHED = 0xFE; // OE PE FE BKD BKT PCRF CRF: cleared by a read of RST
constexpr std::uint8_t LSR_SHARED = RST_OE | RST_PE | RST_FE | RST_BKD; // cleared by a read of LSR
} // namespace

Uart82510::Uart82510(sc_core::sc_module_name name, const Config& cfg)
    : sc_module(name), bus("bus"), int_out("int_out"), cfg_(cfg) {
    const std::string me = std::string(this->name()) + ": ";
    if (cfg_.clock_hz == 0 || cfg_.clock_hz >= (1ULL << 32))
        throw std::invalid_argument(me + "clock " + std::to_string(cfg_.clock_hz) + " Hz out of range");
    if (cfg_.addr_shift > 8)
        throw std::invalid_argument(me + "address shift " + std::to_string(cfg_.addr_shift) + " (0..8)");
    if (cfg_.timer_prescale == 0 || cfg_.timer_prescale > 1024)
        throw std::invalid_argument(me + "timer prescale " + std::to_string(cfg_.timer_prescale) + " (1..1024)");
    if (cfg_.inta_low_cycles == 0 || cfg_.inta_low_cycles > 1'000'000)
        throw std::invalid_argument(me + "INTA low time " + std::to_string(cfg_.inta_low_cycles) +
                                    " cycles (1..1000000)");
    if (cfg_.fifo_depth == 0 || cfg_.fifo_depth > rx_fifo_.size())
        throw std::invalid_argument(me + "FIFO depth " + std::to_string(cfg_.fifo_depth) + " (1..16)");

    bus.register_b_transport(this, &Uart82510::b_transport);
    bus.register_transport_dbg(this, &Uart82510::transport_dbg);

    SC_HAS_PROCESS(Uart82510);
    SC_METHOD(on_tx_done);
    sensitive << tx_done_ev_;
    dont_initialize();
    SC_METHOD(on_timer_a);
    sensitive << timers_[0].ev;
    dont_initialize();
    SC_METHOD(on_timer_b);
    sensitive << timers_[1].ev;
    dont_initialize();
    SC_METHOD(drive_int); // also runs once at start to drive the initial INT level
    sensitive << drive_ev_;
    SC_METHOD(on_inta_release);
    sensitive << inta_release_ev_;
    dont_initialize();

    reset_registers();
}

void Uart82510::connect(SerialLine& line, SerialLine::Side side) {
    line.attach(side, *this);
    line_ = &line;
    side_ = side;
}

// ---------------------------------------------------------------------------------------------
// Reset

void Uart82510::reset() {
    reset_registers();
    update_int();
}

void Uart82510::reset_registers() {
    // Values after RESET and after ICM software reset; [U] choices are listed in README.md.
    bank_ = 0;
    ger_ = 0;
    lcr_ = 0;
    lcr_written_ = divisor_written_ = false;
    mcr_ = 0;
    msr_ = modem_in_; // deltas cleared
    acr0_ = 0;
    brga_ = brgb_ = 0;
    txf_ = 0;
    rst_ = 0;
    fmd_ = 0;
    tmd_ = 0;
    imd_ = IMD_RFD; // 1-byte RX FIFO, 8250-like
    acr1_ = 0;
    rie_ = RST_OE | RST_PE | RST_FE | RST_BKD; // 8250 line-status interrupt causes
    rmd_ = 0;
    clcf_ = CLCF_RXBRGA | CLCF_TXBRGA; // 0x50: RX and TX clocked by BRGA, 16x
    bacf_ = BxCF_BRG;                  // BRGA: baud generator
    bbcf_ = 0;                         // BRGB: timer
    pmd_ = 0;
    mie_ = 0x0F;
    tmie_ = 0;
    rxd_last_ = 0;
    flush_rx();
    tx_head_ = tx_count_ = 0;
    rx_enabled_ = tx_enabled_ = true;
    if (tx_busy_) tx_done_ev_.cancel(); // a character already on the wire still completes there
    tx_busy_ = false;
    loop_pending_ = false;
    if (break_sent_) set_line_break(false);
    for (auto& t : timers_) {
        t.ev.cancel();
        t.armed = t.gate = t.expired = t.counting = false;
        t.remaining = sc_core::SC_ZERO_TIME;
    }
    int_latched_ = false;
}

// ---------------------------------------------------------------------------------------------
// Bus

std::optional<unsigned> Uart82510::register_at(std::uint64_t address) const {
    const std::uint64_t lane = (1ULL << cfg_.addr_shift) - 1;
    if ((address & lane) || (address >> cfg_.addr_shift) > 7) return std::nullopt;
    return static_cast<unsigned>(address >> cfg_.addr_shift);
}

void Uart82510::b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
    BusView view(gp, true);
    view->wait_states = 0;
    const unsigned len = gp.get_data_length();
    const std::optional<unsigned> off = register_at(gp.get_address());
    if (view->kind == BusCycle::int_ack || !off) {
        gp.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE); // not wired to this lane / cycle
        return;
    }
    if (len == 0 || len > 2) {
        gp.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
        return;
    }
    if (gp.get_byte_enable_ptr()) {
        gp.set_response_status(tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE);
        return;
    }
    unsigned char* data = gp.get_data_ptr();
    if (gp.is_read()) {
        data[0] = read(*off);
        if (len == 2) data[1] = 0xFF; // the high byte lane floats
    } else if (gp.is_write()) {
        write(*off, data[0]);
    }
    gp.set_response_status(tlm::TLM_OK_RESPONSE);
}

unsigned Uart82510::transport_dbg(tlm::tlm_generic_payload& gp) {
    const std::optional<unsigned> off = register_at(gp.get_address());
    if (!gp.is_read() || gp.get_data_length() == 0 || !off) return 0;
    gp.get_data_ptr()[0] = peek(*off);
    return 1;
}

// ---------------------------------------------------------------------------------------------
// Register reads

std::uint8_t Uart82510::read(unsigned offset) { return read_reg(offset & 7, true); }
std::uint8_t Uart82510::peek(unsigned offset) const {
    return const_cast<Uart82510*>(this)->read_reg(offset & 7, false);
}
std::uint8_t Uart82510::peek(unsigned bank, unsigned offset) const {
    // read_reg without effects changes nothing; only the bank it decodes is switched round it.
    auto* self = const_cast<Uart82510*>(this);
    const unsigned saved = self->bank_;
    self->bank_ = bank & 3;
    const std::uint8_t v = self->read_reg(offset & 7, false);
    self->bank_ = saved;
    return v;
}

bool Uart82510::read_is_stable(std::uint64_t address, unsigned len) const {
    const std::optional<unsigned> off = register_at(address);
    if (len != 1 || !off) return false;
    if (*off == GIR) return true;
    switch (bank_) { // the reads with an effect in read_bank0 / read_bank1
    case 0: return !((*off == RXD && !(lcr_ & LCR_DLAB)) || *off == LSR || *off == MSR);
    case 1: return !(*off == RXD || *off == TMST || *off == RST || *off == MSR); // MSR again at 6
    default: return true; // banks 2 and 3: configuration only
    }
}

std::uint8_t Uart82510::read_reg(unsigned off, bool effects) {
    if (off == GIR) return gir();
    const bool dlab = lcr_ & LCR_DLAB;
    switch (bank_) {
    case 0: return read_bank0(off, effects);
    case 1: return read_bank1(off, effects);
    case 2:
        switch (off) {
        case FMD: return fmd_;
        case TMD: return tmd_;
        case IMD: return imd_;
        case ACR1: return acr1_;
        case RIE: return rie_;
        case RMD: return rmd_;
        default: return 0xFF; // offset 0: unused
        }
    default:
        switch (off) {
        case CLCF: return dlab ? static_cast<std::uint8_t>(brgb_) : clcf_;
        case BACF: return dlab ? static_cast<std::uint8_t>(brgb_ >> 8) : bacf_;
        case BBCF: return bbcf_;
        case PMD: return pmd_;
        case MIE: return mie_;
        case TMIE: return tmie_;
        default: return 0xFF; // offset 7: unused
        }
    }
}

std::uint8_t Uart82510::read_bank0(unsigned off, bool effects) {
    const bool dlab = lcr_ & LCR_DLAB;
    switch (off) {
    case RXD:
        if (dlab) return static_cast<std::uint8_t>(brga_);
        return effects ? pop_rx() : (rx_count_ ? static_cast<std::uint8_t>(rx_fifo_[rx_head_].data) : rxd_last_);
    case GER: return dlab ? static_cast<std::uint8_t>(brga_ >> 8) : ger_;
    case LCR: return lcr_;
    case MCR: return mcr_;
    case LSR: {
        const std::uint8_t v = lsr();
        if (effects) {
            rst_ &= static_cast<std::uint8_t>(~LSR_SHARED);
            update_int();
        }
        return v;
    }
    case MSR: {
        const std::uint8_t v = msr_;
        if (effects) {
            msr_ &= 0xF0;
            update_int();
        }
        return v;
    }
    default: return acr0_;
    }
}

std::uint8_t Uart82510::read_bank1(unsigned off, bool effects) {
    switch (off) {
    case RXD:
        return effects ? pop_rx() : (rx_count_ ? static_cast<std::uint8_t>(rx_fifo_[rx_head_].data) : rxd_last_);
    case RXF: return rx_count_ ? rx_fifo_[rx_head_].flags : 0;
    case TMST: {
        const std::uint8_t v = tmst();
        if (effects) {
            timers_[0].expired = timers_[1].expired = false;
            update_int();
        }
        return v;
    }
    case FLR: return flr();
    case RST: {
        const std::uint8_t v = static_cast<std::uint8_t>(rst_ | (rx_count_ ? RST_RFIR : 0));
        if (effects) {
            rst_ &= static_cast<std::uint8_t>(~RST_LATCHED);
            update_int();
        }
        return v;
    }
    case 6: // MSR, as in bank 0 (writes here are TCM)
        return read_bank0(MSR, effects);
    default: return gsr();
    }
}

// ---------------------------------------------------------------------------------------------
// Register writes

void Uart82510::write(unsigned offset, std::uint8_t v) {
    offset &= 7;
    if (offset == BANK) {
        bank_ = (v >> 5) & 3; // bits 6:5; the others are ignored
        return;
    }
    switch (bank_) {
    case 0: write_bank0(offset, v); break;
    case 1: write_bank1(offset, v); break;
    case 2: write_bank2(offset, v); break;
    default: write_bank3(offset, v); break;
    }
    update_int();
}

void Uart82510::write_bank0(unsigned off, std::uint8_t v) {
    const bool dlab = lcr_ & LCR_DLAB;
    switch (off) {
    case TXD:
        if (dlab) brga_ = static_cast<std::uint16_t>((brga_ & 0xFF00) | v);
        else push_tx(v);
        divisor_written_ = divisor_written_ || dlab;
        break;
    case GER:
        if (dlab) brga_ = static_cast<std::uint16_t>((brga_ & 0x00FF) | (v << 8));
        else ger_ = v & 0x3F;
        divisor_written_ = divisor_written_ || dlab;
        break;
    case LCR: {
        lcr_written_ = true;
        const bool was_break = lcr_ & LCR_SBK;
        lcr_ = v;
        if (was_break != bool(v & LCR_SBK)) set_line_break(v & LCR_SBK);
        start_tx(); // a held transmitter resumes when the break ends
        break;
    }
    case MCR:
        mcr_ = v & 0x1F;
        update_modem_inputs();
        break;
    case ACR0: acr0_ = v; break;
    default: break; // LSR and MSR are read-only
    }
}

void Uart82510::write_bank1(unsigned off, std::uint8_t v) {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    switch (off) {
    case TXD: push_tx(v); break;
    case TXF: txf_ = v; break;
    case TMCR: write_tmcr(v); break;
    case RCM:
        if (v & RCM_FRF) flush_rx();
        if (v & RCM_FRM) rx_flush_time_ = now; // drop the character being assembled
        if (v & RCM_RXDI) rx_enabled_ = false;
        if (v & RCM_RXE) rx_enabled_ = true;
        break;
    case TCM:
        if (v & TCM_FTF) tx_head_ = tx_count_ = 0;
        if ((v & TCM_FTM) && tx_busy_) {
            tx_done_ev_.cancel(); // the shifter is free now; what left it completes on the wire
            tx_busy_ = false;
            loop_pending_ = false;
        }
        if (v & TCM_TXDI) tx_enabled_ = false;
        if (v & TCM_TXEN) tx_enabled_ = true;
        start_tx();
        break;
    case ICM:
        if (v & ICM_RESET) reset_registers();
        if (v & ICM_STC) {
            rst_ = 0;
            msr_ &= 0xF0;
            timers_[0].expired = timers_[1].expired = false;
        }
        if (v & ICM_INTA) {
            // Drop INT and re-raise it after a short low time if anything is still pending,
            // so an edge-triggered 8259A sees a fresh request.
            int_latched_ = false;
            inta_hold_ = true;
            update_int();
            inta_release_ev_.cancel();
            inta_release_ev_.notify(ratio_time(cfg_.inta_low_cycles, cfg_.clock_hz)); // [U]
        }
        break;
    default: break; // FLR is read-only
    }
}

void Uart82510::write_bank2(unsigned off, std::uint8_t v) {
    switch (off) {
    case FMD: fmd_ = v & 0x33; break;
    case TMD: tmd_ = v; break;
    case IMD: imd_ = v & 0x0F; break;
    case ACR1: acr1_ = v; break;
    case RIE: rie_ = v & 0xFE; break;
    case RMD: rmd_ = v; break;
    default: break;
    }
}

void Uart82510::write_bank3(unsigned off, std::uint8_t v) {
    const bool dlab = lcr_ & LCR_DLAB;
    switch (off) {
    case CLCF:
        if (dlab) brgb_ = static_cast<std::uint16_t>((brgb_ & 0xFF00) | v);
        else clcf_ = v & 0xF0;
        divisor_written_ = divisor_written_ || dlab;
        break;
    case BACF:
        divisor_written_ = divisor_written_ || dlab;
        if (dlab) brgb_ = static_cast<std::uint16_t>((brgb_ & 0x00FF) | (v << 8));
        else {
            bacf_ = v;
            update_timer(0);
        }
        break;
    case BBCF:
        bbcf_ = v;
        update_timer(1);
        break;
    case PMD: pmd_ = v; break;
    case MIE: mie_ = v & 0x0F; break;
    case TMIE: tmie_ = v & 0x03; break;
    default: break;
    }
}

// ---------------------------------------------------------------------------------------------
// Status registers

unsigned Uart82510::rx_threshold() const {
    const unsigned t = ((fmd_ >> 4) & 3) + 1; // RFT 0..3: request at 1..4 characters
    return t < rx_depth() ? t : rx_depth();
}

std::uint8_t Uart82510::gsr() const {
    std::uint8_t v = 0;
    if (rx_count_ >= rx_threshold()) v |= 1u << rx_fifo;
    if (tx_count_ <= (fmd_ & 3u)) v |= 1u << tx_fifo;
    if (rst_ & rie_ & RST_LATCHED) v |= 1u << rx_machine;
    if (msr_ & mie_ & 0x0F) v |= 1u << modem;
    if (tx_idle()) v |= 1u << tx_machine;
    if (tmst() & tmie_ & 0x03) v |= 1u << timer;
    return v;
}

std::uint8_t Uart82510::gir() const {
    const std::uint8_t pending = gsr() & ger_;
    const auto bank = static_cast<std::uint8_t>(bank_ << 5);
    for (Source s : priority)
        if (pending & (1u << s)) return bank | vector_of(s); // IP (bit 0) = 0: pending
    return bank | 0x01;
}

std::uint8_t Uart82510::lsr() const {
    std::uint8_t v = rst_ & LSR_SHARED;
    if (rx_count_) v |= LSR_DR;
    if (tx_count_ <= (fmd_ & 3u)) v |= LSR_TFST;
    if (tx_idle()) v |= LSR_TXST;
    return v;
}

std::uint8_t Uart82510::flr() const { return static_cast<std::uint8_t>((rx_count_ << 4) | tx_count_); }

std::uint8_t Uart82510::tmst() const {
    std::uint8_t v = 0;
    if (timers_[0].expired) v |= 0x01;
    if (timers_[1].expired) v |= 0x02;
    if (timers_[0].gate) v |= 0x10;
    if (timers_[1].gate) v |= 0x20;
    return v;
}

// ---------------------------------------------------------------------------------------------
// Receiver

SerialFormat Uart82510::rx_format() const { return format(true); }
SerialFormat Uart82510::tx_format() const { return format(false); }

void Uart82510::rx_char(const SerialRx& c) {
    if (!rx_enabled_) {
        ++stats_.rx_disabled_drops;
        return;
    }
    if (c.start < rx_flush_time_) return; // was in the RX machine when RCM.FRM flushed it
    std::uint8_t flags = 0;
    if (c.data & 0x100) flags |= RXF_RND;
    if (c.parity) flags |= RXF_RPB;
    if (c.framing_error) {
        flags |= RXF_RFE;
        rst_ |= RST_FE;
        ++stats_.framing_errors;
    }
    if (c.parity_error) {
        flags |= RXF_RPE;
        rst_ |= RST_PE;
        ++stats_.parity_errors;
    }
    if (!(flags & (RXF_RFE | RXF_RPE))) flags |= RXF_ROK;
    push_rx(c.data, flags, c.stop);
    update_int();
}

void Uart82510::rx_break(bool active) {
    if (!rx_enabled_) return;
    if (active) {
        // One all-zero character marks the break in the FIFO (drivers drain it by RXF.BKF).
        rst_ |= RST_BKD;
        ++stats_.break_detects;
        push_rx(0, RXF_BKF | RXF_RFE, sc_core::sc_time_stamp());
    } else {
        rst_ |= RST_BKT;
    }
    update_int();
}

void Uart82510::push_rx(std::uint16_t data, std::uint8_t flags, const sc_core::sc_time& stop) {
    if (rx_count_ >= rx_depth()) {
        rst_ |= RST_OE; // the new character is lost
        ++stats_.overruns;
        if (!first_overrun_) first_overrun_ = stop;
        return;
    }
    rx_fifo_[(rx_head_ + rx_count_) % rx_fifo_.size()] = RxEntry{data, flags, stop};
    ++rx_count_;
    ++stats_.chars_received;
    if (rx_count_ > stats_.rx_fifo_high_water) stats_.rx_fifo_high_water = rx_count_;
}

std::uint8_t Uart82510::pop_rx() {
    if (!rx_count_) return rxd_last_; // an empty FIFO repeats the last character
    const RxEntry e = rx_fifo_[rx_head_];
    rx_head_ = (rx_head_ + 1) % rx_fifo_.size();
    --rx_count_;
    rxd_last_ = static_cast<std::uint8_t>(e.data);
    if (on_char_read) on_char_read(CharTiming{e.data, e.stop, sc_core::sc_time_stamp()});
    update_int();
    return rxd_last_;
}

// ---------------------------------------------------------------------------------------------
// Transmitter

void Uart82510::push_tx(std::uint8_t v) {
    if (tx_count_ >= cfg_.fifo_depth) {
        ++stats_.tx_overflows;
        return;
    }
    const auto data = static_cast<std::uint16_t>(v | ((txf_ & 0x20) ? 0x100 : 0)); // TXF.D8
    tx_fifo_[(tx_head_ + tx_count_) % tx_fifo_.size()] = TxEntry{data, txf_};
    ++tx_count_;
    start_tx();
}

void Uart82510::start_tx() {
    if (tx_busy_ || !tx_enabled_ || !tx_count_ || (lcr_ & LCR_SBK)) return;
    const TxEntry e = tx_fifo_[tx_head_];
    tx_head_ = (tx_head_ + 1) % tx_fifo_.size();
    --tx_count_;
    const SerialFormat f = tx_format();
    // Software parity (TMD.SPF): the parity cell is TXF.SP as written with the character.
    const int parity = (tmd_ & TMD_SPF) && f.parity != Parity::none ? ((e.txf >> 6) & 1) : -1;
    const SerialWord w = SerialWord::encode(e.data, f, parity);
    tx_busy_ = true;
    ++stats_.chars_sent;
    if (mcr_ & MCR_LOOP) {
        loop_pending_ = true; // local loopback: TXD stays at MARK, the receiver gets the shifter
        loop_word_ = w;
        loop_start_ = sc_core::sc_time_stamp();
    } else if (line_) {
        line_->transmit(side_, w);
    }
    tx_done_ev_.notify(w.frame);
}

void Uart82510::on_tx_done() {
    tx_busy_ = false;
    if (loop_pending_) {
        loop_pending_ = false;
        SerialRx c;
        if (sample_word(loop_word_, rx_format(), c)) {
            c.start = loop_start_;
            c.stop = sc_core::sc_time_stamp();
            rx_char(c);
        }
    }
    start_tx();
    update_int();
}

void Uart82510::set_line_break(bool on) {
    if (on == break_sent_) return;
    break_sent_ = on;
    if (line_) line_->set_break(side_, on);
}

void Uart82510::set_modem_inputs(bool cts, bool dsr, bool ri, bool dcd) {
    modem_in_ = static_cast<std::uint8_t>((cts << 4) | (dsr << 5) | (ri << 6) | (dcd << 7));
    update_modem_inputs();
    update_int();
}

void Uart82510::update_modem_inputs() {
    // In loopback the modem outputs feed the inputs: RTS->CTS, DTR->DSR, OUT1->RI, OUT2->DCD.
    std::uint8_t in = modem_in_;
    if (mcr_ & MCR_LOOP)
        in = static_cast<std::uint8_t>(((mcr_ & 0x02) << 3) | ((mcr_ & 0x01) << 5) | ((mcr_ & 0x04) << 4) |
                                       ((mcr_ & 0x08) << 4));
    const std::uint8_t old = msr_ & 0xF0;
    const std::uint8_t changed = old ^ in;
    std::uint8_t delta = msr_ & 0x0F;
    if (changed & 0x10) delta |= 0x01;               // DCTS
    if (changed & 0x20) delta |= 0x02;               // DDSR
    if ((old & 0x40) && !(in & 0x40)) delta |= 0x04; // TERI: RI went inactive
    if (changed & 0x80) delta |= 0x08;               // DDCD
    msr_ = static_cast<std::uint8_t>(in | delta);
}

// ---------------------------------------------------------------------------------------------
// Baud-rate generators and timers

std::uint32_t Uart82510::divisor(unsigned brg) const {
    const std::uint16_t d = brg == 0 ? brga_ : brgb_;
    return d ? d : 0x10000u; // [U] 0 counts as 65536
}

bool Uart82510::timer_mode(unsigned brg) const { return !((brg == 0 ? bacf_ : bbcf_) & BxCF_BRG); }

SerialFormat Uart82510::format(bool rx) const {
    SerialFormat f;
    const bool brga = clcf_ & (rx ? CLCF_RXBRGA : CLCF_TXBRGA);
    const bool one_x = clcf_ & (rx ? CLCF_RX1X : CLCF_TX1X);
    // BRG input = clock / 2; the bit clock is 16x the BRG output (1x mode: the BRG output).
    f.bit = BitTime::clocked(cfg_.clock_hz, 2ULL * divisor(brga ? 0 : 1) * (one_x ? 1 : 16));
    const unsigned cl = lcr_ & 3;
    f.data_bits = (cl == 0 && (tmd_ & TMD_NBCL)) ? 9 : 5 + cl;
    if (!(lcr_ & LCR_PEN)) f.parity = Parity::none;
    else {
        constexpr Parity pm[] = {Parity::odd, Parity::even, Parity::mark, Parity::space};
        f.parity = pm[(lcr_ >> 4) & 3];
    }
    switch (tmd_ & 3) {
    case 1: f.stop_halves = 2; break;
    case 2: f.stop_halves = 3; break;
    case 3: f.stop_halves = 4; break;
    default: f.stop_halves = (lcr_ & LCR_SBL0) ? (f.data_bits == 5 ? 3 : 4) : 2; break;
    }
    return f;
}

sc_core::sc_time Uart82510::timer_period(unsigned brg) const {
    return ratio_time(static_cast<std::uint64_t>(divisor(brg)) * cfg_.timer_prescale, cfg_.clock_hz);
}

void Uart82510::write_tmcr(std::uint8_t v) {
    for (unsigned t = 0; t < 2; ++t) {
        Timer& tm = timers_[t];
        if (v & (0x01u << t)) { // STx: load the divisor, start a fresh period
            tm.armed = true;
            tm.remaining = sc_core::SC_ZERO_TIME;
            if (tm.counting) {
                tm.ev.cancel();
                tm.counting = false;
            }
        }
        tm.gate = v & (0x10u << t); // TGx: counting enabled
        update_timer(t);
    }
}

void Uart82510::update_timer(unsigned t) {
    Timer& tm = timers_[t];
    const bool run = tm.armed && tm.gate && timer_mode(t);
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    if (run && !tm.counting) {
        const sc_core::sc_time left = tm.remaining > sc_core::SC_ZERO_TIME ? tm.remaining : timer_period(t);
        tm.counting = true;
        tm.next = now + left;
        tm.ev.notify(left);
    } else if (!run && tm.counting) {
        tm.counting = false;
        tm.remaining = tm.next - now; // frozen until the gate opens again
        tm.ev.cancel();
    }
}

void Uart82510::on_timer(unsigned t) {
    Timer& tm = timers_[t];
    if (!tm.counting) return;
    tm.expired = true;
    // Auto-reload from the current divisor: a periodic tick.
    const sc_core::sc_time period = timer_period(t);
    tm.next = sc_core::sc_time_stamp() + period;
    tm.ev.notify(period);
    update_int();
}

// ---------------------------------------------------------------------------------------------
// Interrupt output

void Uart82510::update_int() {
    // Every change of the FIFOs' levels ends in update_int() (their thresholds are sources).
    if (on_fifo_change) on_fifo_change();
    const bool pending = gsr() & ger_;
    bool want;
    if (imd_ & IMD_IAM) {
        // Manual acknowledge: INT, once raised, stays until ICM.INTA.
        if (pending) int_latched_ = true;
        want = int_latched_;
    } else {
        int_latched_ = false;
        want = pending;
    }
    if (inta_hold_) want = false;
    if (want != int_state_) {
        int_state_ = want;
        drive_ev_.notify(sc_core::SC_ZERO_TIME); // one writer for the signal: drive_int
    }
}

void Uart82510::drive_int() { int_out.write(int_state_); }

void Uart82510::on_inta_release() {
    inta_hold_ = false;
    update_int();
}

} // namespace rcsim
