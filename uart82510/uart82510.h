// rcsim — Intel 82510 Asynchronous Serial Controller (ASC).
//
// Sources: no 82510 data sheet text is public; the facts come from Intel's i960 QT960 driver, the
// VxWorks i82510.h register map, the Sharp LH75400 "82510-compatible" UART2 bitfields, FAS/SAS and
// Solaris asy drivers, listed with their confidence tags on the doc page uart82510/README.md.
// Every choice made where those are uncertain ([U]) is listed there too, and the cheap ones are
// Config values.
//
// The part: four banks of eight registers (bank select written at offset 2 of every bank; GIR
// read there), 4-byte TX and RX FIFOs with thresholds, two baud-rate generators BRGA/BRGB that
// each serve as a baud clock or as a timer with its own interrupt, six prioritised interrupt
// sources behind one INT pin.
//
// Model: a TLM-2.0 target (register r at local offset r << addr_shift, byte lane 0; no wait
// states: the board adds its I/O wait states on the CPU side), an INT output (true = asserted),
// and a SerialEndpoint on a SerialLine. Nothing ticks: a character costs one event when its last
// stop bit leaves the transmitter, and a timer one event per expiry.
#pragma once

#include "models/bus.h"
#include "models/irq.h"
#include "models/serial_line.h"

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>

namespace rcsim {

namespace i82510 {
// Register offsets (A2..A0) per bank. Offset 2 is GIR (read) / BANK (write) in every bank.
enum Offset : unsigned {
    // bank 0 "NAS" (8250A compatible)
    RXD = 0, TXD = 0, BAL = 0, GER = 1, BAH = 1, GIR = 2, BANK = 2, LCR = 3, MCR = 4, LSR = 5, MSR = 6, ACR0 = 7,
    // bank 1 "WORK"
    RXF = 1, TXF = 1, TMST = 3, TMCR = 3, FLR = 4, RST = 5, RCM = 5, TCM = 6, GSR = 7, ICM = 7,
    // bank 2 "GEN"
    FMD = 1, TMD = 3, IMD = 4, ACR1 = 5, RIE = 6, RMD = 7,
    // bank 3 "MODM"
    CLCF = 0, BBL = 0, BACF = 1, BBH = 1, BBCF = 3, PMD = 4, MIE = 5, TMIE = 6,
};

// Interrupt sources: bit position in GER and GSR, and the GIR vector (bits 3:1) of each.
enum Source : unsigned { rx_fifo = 0, tx_fifo = 1, rx_machine = 2, modem = 3, tx_machine = 4, timer = 5 };
constexpr std::uint8_t vector_of(Source s) {
    // timer 0x0A > Tx machine 0x08 > Rx machine 0x06 > Rx FIFO 0x04 > Tx FIFO 0x02 > modem 0x00
    constexpr std::uint8_t v[] = {0x04, 0x02, 0x06, 0x00, 0x08, 0x0A};
    return v[s];
}

// Bits used by several registers.
constexpr std::uint8_t LCR_DLAB = 0x80, LCR_SBK = 0x40, LCR_PEN = 0x08, LCR_SBL0 = 0x04;
constexpr std::uint8_t MCR_LOOP = 0x10;
constexpr std::uint8_t RST_RFIR = 0x01, RST_OE = 0x02, RST_PE = 0x04, RST_FE = 0x08, RST_BKD = 0x10,
                       RST_BKT = 0x20;
constexpr std::uint8_t RXF_RND = 0x01, RXF_RFE = 0x02, RXF_BKF = 0x04, RXF_RPE = 0x10, RXF_RPB = 0x20,
                       RXF_ROK = 0x40;
constexpr std::uint8_t LSR_DR = 0x01, LSR_TFST = 0x20, LSR_TXST = 0x40;
constexpr std::uint8_t IMD_RFD = 0x04, IMD_IAM = 0x08;
constexpr std::uint8_t ICM_STC = 0x04, ICM_INTA = 0x08, ICM_RESET = 0x10;
constexpr std::uint8_t RCM_FRF = 0x10, RCM_FRM = 0x20, RCM_RXDI = 0x40, RCM_RXE = 0x80;
constexpr std::uint8_t TCM_TXDI = 0x01, TCM_TXEN = 0x02, TCM_FTF = 0x04, TCM_FTM = 0x08;
constexpr std::uint8_t TMD_SPF = 0x04, TMD_NBCL = 0x20;
constexpr std::uint8_t CLCF_RX1X = 0x80, CLCF_RXBRGA = 0x40, CLCF_TX1X = 0x20, CLCF_TXBRGA = 0x10;
constexpr std::uint8_t BxCF_BRG = 0x04; // BACF.BAM / BBCF.BBM: 1 = baud generator, 0 = timer
} // namespace i82510

class Uart82510 : public sc_core::sc_module, public SerialEndpoint, public StableReads {
public:
    struct Config {
        std::uint64_t clock_hz = 18'432'000; // crystal; BRG input is clock/2, 16x sampling
        unsigned addr_shift = 1;             // register r at local offset r << addr_shift
        unsigned timer_prescale = 2;         // [U] clock cycles per timer count (BRG input)
        unsigned fifo_depth = 4;             // TX and RX FIFO bytes
        unsigned inta_low_cycles = 2;        // [U] clock cycles INT stays low after ICM.INTA
    };

    /// Per-port figures for reports.
    struct Stats {
        std::uint64_t chars_received = 0; // into the RX FIFO (errors included, overruns not)
        std::uint64_t chars_sent = 0;     // START bits put on the line
        std::uint64_t overruns = 0;
        std::uint64_t parity_errors = 0;
        std::uint64_t framing_errors = 0;
        std::uint64_t break_detects = 0;
        std::uint64_t tx_overflows = 0;   // TXD written with the TX FIFO full (byte lost)
        std::uint64_t rx_disabled_drops = 0;
        unsigned rx_fifo_high_water = 0;
    };

    /// One received character, reported when the CPU reads it out of the RX FIFO.
    struct CharTiming {
        std::uint16_t data;
        sc_core::sc_time stop; // the end of its first stop bit (into the FIFO)
        sc_core::sc_time read; // the RXD read that took it out
    };

    tlm_utils::simple_target_socket<Uart82510> bus;
    IrqOut int_out;

    explicit Uart82510(sc_core::sc_module_name name) : Uart82510(name, Config{}) {}
    Uart82510(sc_core::sc_module_name name, const Config& cfg);

    /// Puts the serial pins on `side` of `line`.
    void connect(SerialLine& line, SerialLine::Side side);

    /// Register access as the bus does it (side effects included): bank-relative offset 0..7.
    std::uint8_t read(unsigned offset);
    void write(unsigned offset, std::uint8_t value);
    /// Register value without side effects (debug transport, traces).
    std::uint8_t peek(unsigned offset) const;
    /// The same for a register of any bank (a debugger's register dump): the bank pointer is
    /// left as it is.
    std::uint8_t peek(unsigned bank, unsigned offset) const;
    /// Stable reads (models/bus.h, docs/architecture.md "Stable reads"): a byte read of a
    /// register in the bank selected now whose read has no effect. Its value follows the
    /// registers, FIFOs and timers only, which change at this part's own events (a character
    /// in, the transmitter, a timer) or by accesses, never with the time alone: GIR in every
    /// bank, GSR, FLR, RXF and the configuration registers. Not stable: the reads that pop the
    /// RX FIFO or clear a status (RXD, LSR, MSR, TMST, RST), which may move INT.
    bool read_is_stable(std::uint64_t address, unsigned len) const override;

    /// The RESET pin: every register, FIFO, timer and the bank pointer (not the Stats).
    void reset();
    /// Modem inputs (CTS, DSR, RI, DCD), true = asserted; the board leaves them open by default.
    void set_modem_inputs(bool cts, bool dsr, bool ri, bool dcd);

    SerialFormat tx_format() const;
    SerialFormat rx_format() const override;
    void rx_char(const SerialRx& c) override;
    void rx_break(bool active) override;

    const Stats& stats() const { return stats_; }
    /// When the first character was lost to an overrun (its stop bit found the RX FIFO full);
    /// none without one. A failed `overruns` check names it.
    const std::optional<sc_core::sc_time>& first_overrun() const { return first_overrun_; }
    const Config& config() const { return cfg_; }
    /// The CPU has written the character format (LCR) and a baud-rate divisor (BAL/BAH with
    /// DLAB) since the last RESET: rx_format() is then the firmware's choice, not the reset
    /// state. The verdict computes the budget from a port only once this holds.
    bool format_programmed() const { return lcr_written_ && divisor_written_; }
    unsigned bank() const { return bank_; }
    unsigned rx_level() const { return rx_count_; }
    unsigned tx_level() const { return tx_count_; }
    std::uint8_t mcr() const { return mcr_; }

    /// Called for every character the CPU reads from the RX FIFO (character latency probe).
    std::function<void(const CharTiming&)> on_char_read;
    /// Called after anything that may have changed rx_level() or tx_level() (trace counters);
    /// the levels may also be unchanged.
    std::function<void()> on_fifo_change;

private:
    struct RxEntry {
        std::uint16_t data;
        std::uint8_t flags; // RXF bits
        sc_core::sc_time stop;
    };
    struct TxEntry {
        std::uint16_t data; // 9th bit from TXF.D8
        std::uint8_t txf;   // TXF at the time of the TXD write (software parity bit)
    };
    struct Timer {
        bool armed = false;   // loaded by TMCR.STx
        bool gate = false;    // TMCR.TGx: counting enabled
        bool expired = false; // TMST.TxEx
        bool counting = false;
        sc_core::sc_time next;      // expiry while counting
        sc_core::sc_time remaining; // left when the gate closed
        sc_core::sc_event ev;
    };

    Config cfg_;
    SerialLine* line_ = nullptr;
    SerialLine::Side side_ = SerialLine::a;

    // registers
    unsigned bank_ = 0;
    std::uint8_t ger_ = 0, lcr_ = 0, mcr_ = 0, msr_ = 0, acr0_ = 0;
    bool lcr_written_ = false, divisor_written_ = false; // since RESET (format_programmed)
    std::uint16_t brga_ = 0, brgb_ = 0;
    std::uint8_t txf_ = 0, rst_ = 0;
    std::uint8_t fmd_ = 0, tmd_ = 0, imd_ = 0, acr1_ = 0, rie_ = 0, rmd_ = 0;
    std::uint8_t clcf_ = 0, bacf_ = 0, bbcf_ = 0, pmd_ = 0, mie_ = 0, tmie_ = 0;
    std::uint8_t rxd_last_ = 0;
    std::uint8_t modem_in_ = 0; // external CTS, DSR, RI, DCD as MSR bits 7:4

    // FIFOs and machines
    std::array<RxEntry, 16> rx_fifo_{};
    std::array<TxEntry, 16> tx_fifo_{};
    unsigned rx_head_ = 0, rx_count_ = 0, tx_head_ = 0, tx_count_ = 0;
    bool rx_enabled_ = true, tx_enabled_ = true, tx_busy_ = false;
    bool break_sent_ = false;
    bool loop_pending_ = false;
    SerialWord loop_word_;
    sc_core::sc_time loop_start_;
    sc_core::sc_time rx_flush_time_;
    sc_core::sc_event tx_done_ev_;
    std::array<Timer, 2> timers_;

    // interrupt output: every process may change the sources, one process drives the pin
    bool int_state_ = false;   // the level int_out is (about to be) driven to
    bool int_latched_ = false; // manual-acknowledge mode: held until ICM.INTA
    bool inta_hold_ = false;   // INT held low for a moment after ICM.INTA
    sc_core::sc_event drive_ev_, inta_release_ev_;

    Stats stats_;
    std::optional<sc_core::sc_time> first_overrun_;

    /// The register (A2..A0) an address selects: on byte lane 0 (register r at r << addr_shift)
    /// and not past offset 7, else none (not wired to this part).
    std::optional<unsigned> register_at(std::uint64_t address) const;
    void b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time& delay);
    unsigned transport_dbg(tlm::tlm_generic_payload& gp);

    std::uint8_t read_reg(unsigned off, bool effects);
    std::uint8_t read_bank0(unsigned off, bool effects);
    std::uint8_t read_bank1(unsigned off, bool effects);
    void write_bank0(unsigned off, std::uint8_t v);
    void write_bank1(unsigned off, std::uint8_t v);
    void write_bank2(unsigned off, std::uint8_t v);
    void write_bank3(unsigned off, std::uint8_t v);
    void reset_registers();

    // status
    unsigned rx_depth() const { return (imd_ & i82510::IMD_RFD) ? 1u : cfg_.fifo_depth; }
    unsigned rx_threshold() const;
    std::uint8_t gsr() const;
    std::uint8_t gir() const;
    std::uint8_t lsr() const;
    std::uint8_t flr() const;
    std::uint8_t tmst() const;
    bool tx_idle() const { return tx_count_ == 0 && !tx_busy_; }

    // receiver
    std::uint8_t pop_rx();
    void push_rx(std::uint16_t data, std::uint8_t flags, const sc_core::sc_time& stop);
    void flush_rx() { rx_head_ = rx_count_ = 0; }

    // transmitter
    void push_tx(std::uint8_t v);
    void start_tx();
    void on_tx_done();
    void set_line_break(bool on);
    void update_modem_inputs();

    // baud-rate generators and timers
    std::uint32_t divisor(unsigned brg) const;
    bool timer_mode(unsigned brg) const;
    SerialFormat format(bool rx) const;
    sc_core::sc_time timer_period(unsigned brg) const;
    void write_tmcr(std::uint8_t v);
    void update_timer(unsigned t);
    void on_timer(unsigned t);
    void on_timer_a() { on_timer(0); }
    void on_timer_b() { on_timer(1); }

    // interrupts
    void update_int();
    void drive_int();
    void on_inta_release();
};

} // namespace rcsim
