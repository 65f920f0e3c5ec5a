// rcsim — CAMC-QI 4-axis pulse/interpolation motion chip (Ajinextek/Samsung CAMC family).
//
// Documentation source: no datasheet is public; the register/command codes follow the QICOMMAND
// map of Ajinextek's AXL headers (AXHD.h/AXHS.h/AXM.h, camc_qi/README.md "Sources"); bit layouts
// the headers leave open (DCFG, UCFG1) are our decisions, listed in camc_qi/README.md.
// Algorithms: interpolation.h; speed profiles: profile.h.
//
// Host interface: one 16-byte window per axis (DATA 32-bit, COMMAND 8-bit, quick status words);
// a command code with bit 7 set writes DATA into a register, bit 7 clear copies a register into
// DATA, codes 0xA0-0xAF/0xB1/0xF9/0xFE are actions (start, stops, reset, clear). TLM-2.0 target,
// blocking transport, never calls wait(); latency is reported as BusExtension::wait_states.
//
// Event-driven: a drive is a speed profile plus a path, and every counter is computed from them
// at the time it is read. The only kernel events are drive ends (one timed notification per
// drive) and zero-time re-evaluations of the INT output. Pulse-level tracing, when switched on,
// is reconstructed analytically at the end of each drive.
#pragma once

#include "camc_qi/interpolation.h"
#include "camc_qi/profile.h"
#include "models/irq.h"

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace rcsim::camc {

/// QICOMMAND codes (read code; write code = read | 0x80) and action codes.
namespace qi {
constexpr std::uint8_t write = 0x80;
constexpr std::uint8_t CURSPD = 0x0F; // current speed, steps/s (read)
constexpr std::uint8_t RANGE = 0x10;  // speed multiplier: steps/s = register * RANGE
constexpr std::uint8_t STD = 0x11;    // start/stop speed
constexpr std::uint8_t OBJ = 0x12;    // object speed
constexpr std::uint8_t RATE1 = 0x13;  // acceleration, steps/s^2 (* RANGE)
constexpr std::uint8_t RATE2 = 0x14;  // deceleration
constexpr std::uint8_t SW1 = 0x15;    // S-curve: accel jerk share, percent 0..100
constexpr std::uint8_t SW2 = 0x16;    // S-curve: decel jerk share, percent
constexpr std::uint8_t DCFG = 0x17;   // drive configuration (README: profile, drive mode, axis mask)
constexpr std::uint8_t JSPD = 0x18;   // blending: the speed a blended drive starts at (README "Blending")
constexpr std::uint8_t POS = 0x19;    // preset distance / interpolation end (relative, signed)
constexpr std::uint8_t CENT = 0x1A;   // circle centre (relative to the start, signed)
constexpr std::uint8_t ISNUM = 0x1B;  // interpolation step number (host-computed, for deceleration)
constexpr std::uint8_t REMAIN = 0x1C; // pulses left after an abnormal stop of a preset drive (read)
constexpr std::uint8_t JEXIT = 0x1D;  // blending: the speed the running drive ends at, in its units
constexpr std::uint8_t UIO = 0x1E;    // universal outputs: b0 SVON, b1 ALMRST
constexpr std::uint8_t OBJORG = 0x1F; // origin search speed
constexpr std::uint8_t DRPCNT = 0x30; // pulses driven in the last drive (read)
constexpr std::uint8_t CNT1 = 0x66;   // command position
constexpr std::uint8_t CNT2 = 0x67;   // encoder (actual) position
constexpr std::uint8_t CNT3 = 0x68;   // deviation CNT1 - CNT2 (read)
constexpr std::uint8_t UCFG1 = 0x70;  // signal configuration (README)
constexpr std::uint8_t IMASK1 = 0x77; // interrupt mask
constexpr std::uint8_t STAT1 = 0x79;  // end status (read); write code 0xF9 = ESCLR clears it
constexpr std::uint8_t STAT2 = 0x7A;  // drive status (read)
constexpr std::uint8_t STAT3 = 0x7B;  // mechanical signals (read)
constexpr std::uint8_t IFLAG1 = 0x7E; // interrupt flags (read); 0xFE clears the DATA bits
// Actions.
constexpr std::uint8_t STRN = 0xA0;    // start the drive configured in DCFG
constexpr std::uint8_t SSTOP = 0xA4;   // slow-down stop
constexpr std::uint8_t STOP = 0xA5;    // immediate stop
constexpr std::uint8_t ESTOP = 0xAE;   // emergency stop, all axes
constexpr std::uint8_t SWRESET = 0xAF; // software reset, all axes
constexpr std::uint8_t INTGEN = 0xB1;  // raise the user interrupt flag
constexpr std::uint8_t ESCLR = 0xF9;   // clear end status
constexpr std::uint8_t IFCLR1 = 0xFE;  // clear interrupt flags given in DATA
} // namespace qi

/// Window layout (per axis at axis * 0x10) and the global registers.
namespace win {
constexpr unsigned stride = 0x10;
constexpr unsigned data = 0x0;   // 4 bytes, little-endian
constexpr unsigned command = 0x4;
constexpr unsigned drive_status = 0x8; // STAT2 low 16 bits (read-only)
constexpr unsigned end_status = 0xA;   // STAT1 low 16 bits (read-only)
constexpr unsigned mech_status = 0xC;  // STAT3 low 16 bits (read-only)
constexpr unsigned irq_pending = 0x40; // bit n: axis n has an unmasked interrupt flag
constexpr unsigned chip_id = 0x41;     // 0x06 = AXT_SMC_4V04 (CAMC-QI, 4 axes)
constexpr unsigned size = 0x80;
} // namespace win

/// DCFG fields (our layout; the AXL headers only say "DCFG7..0 select the profile").
namespace dcfg {
constexpr std::uint32_t profile_mask = 0x3;      // 0 sym trapezoid, 1 asym trapezoid, 2 sym S, 3 asym S
constexpr unsigned mode_shift = 4;               // bits 6:4
constexpr std::uint32_t mode_mask = 0x7u << mode_shift;
enum Mode : std::uint32_t {
    preset = 0, cont_pos = 1, cont_neg = 2, origin_pos = 3, origin_neg = 4,
    linear = 5, circle_cw = 6, circle_ccw = 7,
};
constexpr unsigned axes_shift = 8;               // bits 11:8: interpolation axis mask
// Signal search (modes 3/4, our layout after CAMC-IP's +-SIGNAL SEARCH 1/2): the drive runs at
// OBJORG until the chosen signal takes the chosen edge, then stops slow-down or immediately.
constexpr unsigned signal_shift = 12;            // bits 13:12: 0 ORG, 1 Z phase, 2 PELM, 3 NELM
constexpr std::uint32_t signal_mask = 0x3u << signal_shift;
enum Signal : std::uint32_t { sig_org = 0, sig_z = 1, sig_pelm = 2, sig_nelm = 3 };
constexpr std::uint32_t search_inactive = 1u << 14;  // 0: until the signal becomes active, 1: inactive
constexpr std::uint32_t search_immediate = 1u << 15; // 0: slow-down stop at the edge, 1: immediate stop
// Constant vector speed (circles; README "Constant vector speed"): STD/OBJ/RATE1/RATE2 are speeds
// and rates along the arc, and the steps follow the arc length, so the path speed is OBJ whatever
// the mix of one- and two-axis steps. Lines ignore it (their step length is constant anyway).
constexpr std::uint32_t vector_speed = 1u << 16;
// Blending (README "Blending"): STRN while the same axes drive a preset or interpolation queues
// this drive; the running one re-plans to end at JEXIT, and this one starts at that instant at JSPD.
constexpr std::uint32_t blend = 1u << 17;
// Take-over (README "Blending"): STRN while the axis runs a preset or continuous drive the same
// way replaces it at once, starting at its current speed; POS is then the absolute target (CNT1).
constexpr std::uint32_t take_over = 1u << 18;
} // namespace dcfg

/// UCFG1 fields (our layout).
namespace ucfg {
constexpr std::uint32_t pelm_high = 1u << 0, pelm_used = 1u << 1;
constexpr std::uint32_t nelm_high = 1u << 2, nelm_used = 1u << 3;
constexpr std::uint32_t limit_slowdown = 1u << 4; // 0: emergency (immediate) stop, 1: slow-down
constexpr std::uint32_t org_high = 1u << 5;
constexpr std::uint32_t alarm_high = 1u << 6, alarm_used = 1u << 7;
constexpr std::uint32_t reset_value = pelm_high | pelm_used | nelm_high | nelm_used | org_high |
                                      alarm_high | alarm_used;
} // namespace ucfg

/// End status (STAT1) bits, AXHS.h.
namespace endst {
constexpr std::uint32_t pelm = 1u << 0, nelm = 1u << 1, alarm = 1u << 8, estop_signal = 1u << 9;
constexpr std::uint32_t stop_cmd = 1u << 10, slowdown_cmd = 1u << 11, estop_cmd = 1u << 12;
constexpr std::uint32_t home_ok = 1u << 17, signal_ok = 1u << 18, interp_data = 1u << 19, data_error = 1u << 31;
} // namespace endst

/// Drive status (STAT2) bits, AXHS.h.
namespace drvst {
constexpr std::uint32_t busy = 1u << 0, down = 1u << 1, constant = 1u << 2, up = 1u << 3;
constexpr std::uint32_t continuous = 1u << 4, preset = 1u << 5, home = 1u << 7, interpolating = 1u << 9;
constexpr std::uint32_t negative = 1u << 11, linear = 1u << 13, circular = 1u << 14, pulsing = 1u << 15;
constexpr std::uint32_t queue_empty = 1u << 19;
} // namespace drvst

/// Mechanical signal (STAT3) bits, AXHS.h (active = after the level configuration).
namespace mech {
constexpr std::uint32_t pelm = 1u << 0, nelm = 1u << 1, alarm = 1u << 4, inp = 1u << 5;
constexpr std::uint32_t estop = 1u << 6, org = 1u << 7, zphase = 1u << 8;
} // namespace mech

/// Interrupt flags (IFLAG1).
namespace intf {
constexpr std::uint32_t drive_end = 1u << 0, drive_start = 1u << 1, error_stop = 1u << 2, user = 1u << 3;
} // namespace intf

/// Per-axis input pins (electrical level; the configured level decides "active").
enum class Pin : std::uint8_t { pelm, nelm, org, alarm, inp, zphase };

/// Sensors fixed on the mechanism, at positions of the axis' pulse output (net pulses since reset,
/// `pulse_count()`, so CNT1/CNT2 presets do not move them). Each drives its input pin high while
/// the axis is in its range (wired-OR with the level given by set_pin); the chip computes the
/// exact time a drive's profile reaches a range edge and acts at that time.
struct Sensors {
    std::optional<std::int64_t> pelm; // PELM: on at and above this position
    std::optional<std::int64_t> nelm; // NELM: on at and below
    std::optional<std::int64_t> org;  // home switch: on at and below (its one edge is here)
    std::int64_t z_pitch = 0;         // encoder Z: on where (position - z_offset) % z_pitch == 0; 0 = none
    std::int64_t z_offset = 0;
};

/// One pulse on the PULSE output (with the DIR level) when tracing is on.
struct PulseEvent {
    sc_core::sc_time time;
    unsigned axis;
    int dir; // +1 / -1
};

class CamcQi : public sc_core::sc_module {
public:
    static constexpr unsigned axes = 4;
    static constexpr double max_pps = 10e6; // PCI-N404 ceiling, AXM.h

    tlm_utils::simple_target_socket<CamcQi> socket;
    IrqLine irq; // INT output, asserted = true

    CamcQi(sc_core::sc_module_name name, unsigned wait_states = 1);
    ~CamcQi() override;

    // --- pins (the board side) ---
    void set_pin(unsigned axis, Pin pin, bool level);
    bool pin(unsigned axis, Pin pin) const;
    void set_sensors(unsigned axis, const Sensors& s);
    /// The chip's ESTOP input (all axes).
    void set_estop_pin(bool active);
    bool servo_on(unsigned axis) const { return ax(axis).uio & 1u; }       // UIO0 = SVON
    bool alarm_reset(unsigned axis) const { return ax(axis).uio & 2u; }    // UIO1 = ALMRST
    /// The encoder A/B input as a counter source (the drive's reported actual position); without
    /// one the encoder counter follows the command position (a loop-back board).
    void set_encoder_source(unsigned axis, std::function<std::int64_t()> src);

    // --- observation (tests, tracing, the trajectory recorder) ---
    std::int64_t command_position(unsigned axis) const; // CNT1 now
    std::int64_t encoder_position(unsigned axis) const; // CNT2 now
    /// Net pulses emitted on PULSE/DIR since reset (CNT1 without its presets): what a drive counts.
    std::int64_t pulse_count(unsigned axis) const { return command_position(axis) - ax(axis).preset_shift; }
    bool busy(unsigned axis) const;
    double current_speed(unsigned axis) const;          // steps/s of the drive the axis is in
    std::uint32_t end_status(unsigned axis) const { return ax(axis).end_status; }
    std::uint32_t drive_status(unsigned axis) const;
    void trace_pulses(unsigned axis, bool on);
    const std::vector<PulseEvent>& pulse_trace() const { return trace_; }

    /// Register access by code, as through the bus (for the driver's unit tests).
    std::uint32_t read_register(unsigned axis, std::uint8_t code);
    void command(unsigned axis, std::uint8_t code, std::uint32_t data = 0);

private:
    struct Drive; // drive.h
    struct Axis {
        // registers
        std::uint32_t range = 1, std_speed = 100, obj = 1000, rate1 = 10000, rate2 = 10000;
        std::uint32_t sw1 = 0, sw2 = 0, dcfg = 0, isnum = 0, uio = 0, objorg = 1000;
        std::uint32_t jspd = 0, jexit = 0;
        std::int32_t pos = 0, cent = 0;
        std::uint32_t ucfg1 = ucfg::reset_value, imask1 = 0;
        std::uint32_t end_status = 0, iflag = 0;
        std::uint32_t data = 0;       // the DATA latch of this axis' window
        std::uint8_t last_cmd = 0;
        // counters
        std::int64_t cnt1 = 0;        // command position while idle / at drive start
        std::int64_t enc_offset = 0;  // CNT2 = source() + enc_offset
        std::int64_t preset_shift = 0; // sum of CNT1 preset jumps (no pulses emitted)
        std::int64_t remain = 0, driven = 0;
        std::array<bool, 6> pins{};   // electrical levels from set_pin
        Sensors sensors;
        std::function<std::int64_t()> encoder;
        std::shared_ptr<Drive> drive; // shared by every axis of an interpolation
        bool trace = false;
    };

    std::array<Axis, axes> ax_;
    bool estop_pin_ = false;
    unsigned wait_states_;
    sc_core::sc_event wake_;      // drive end times and register changes
    std::vector<PulseEvent> trace_;

    Axis& ax(unsigned a);
    const Axis& ax(unsigned a) const;
    void b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time& delay);
    std::uint8_t read_byte(unsigned offset);
    void write_byte(unsigned offset, std::uint8_t value);

    void execute(unsigned axis, std::uint8_t code);
    void write_register(unsigned axis, std::uint8_t code, std::uint32_t value);
    ProfileParams params(const Axis& a, bool origin) const;
    void start(unsigned axis);
    /// Puts a built drive on its axes at `at` (a blended one when the drive before it ends).
    void attach(std::shared_ptr<Drive> d, sc_core::sc_time at);
    bool start_check(unsigned axis, int dir_hint, std::optional<Pin> searched);
    void stop_drive(std::shared_ptr<Drive> d, bool slow, std::uint32_t cause);
    /// The stop at a sensor edge, at the edge's exact time `t` (drive time) after `k` steps.
    void stop_at(std::shared_ptr<Drive> d, bool slow, std::uint32_t cause, double t, std::uint64_t k);
    // Sensor edges (camc_qi/README.md "Sensors and homing").
    bool level(unsigned axis, Pin p, std::int64_t pos) const;
    bool active_at(unsigned axis, Pin p, std::int64_t pos) const;
    std::optional<std::int64_t> next_level(unsigned axis, Pin p, std::int64_t cur, int dir, bool want) const;
    std::optional<std::uint64_t> step_reaching(const Drive& d, unsigned axis, std::int64_t q, std::uint64_t from) const;
    void plan_edges(Drive& d) const;
    void on_edge(std::shared_ptr<Drive> d);
    void finish(std::shared_ptr<Drive> d, sc_core::sc_time at);
    void check_inputs(unsigned axis);
    void settle();       // SC_METHOD: drive ends, INT output
    void schedule();
    bool limit_active(const Axis& a, Pin p) const; // now, at the axis' position
    std::uint32_t mech_status(unsigned axis) const;
    int direction(unsigned axis) const;
    void record_trace(const Drive& d);
};

} // namespace rcsim::camc
