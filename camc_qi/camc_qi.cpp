// rcsim — CAMC-QI 4-axis pulse/interpolation motion chip: the module, its bus interface, the
// commands and registers, the pins and what can be observed. Drives themselves (start, stops,
// sensor edges, the pulse trace) are drive.cpp. See camc_qi.h and README.md.
#include "camc_qi/camc_qi.h"
#include "camc_qi/drive.h"

#include "models/bus.h"
#include "models/plumbing/hex.h"

#include <cmath>
#include <string>

namespace rcsim::camc {

CamcQi::CamcQi(sc_core::sc_module_name name, unsigned wait_states)
    : sc_module(name), socket("socket"), irq("irq"), wait_states_(wait_states), wake_("wake") {
    socket.register_b_transport(this, &CamcQi::b_transport);
    SC_HAS_PROCESS(CamcQi);
    SC_METHOD(settle);
    sensitive << wake_;
    dont_initialize();
}

CamcQi::~CamcQi() = default;

CamcQi::Axis& CamcQi::ax(unsigned a) {
    if (a >= axes) throw std::out_of_range("CAMC-QI: axis " + std::to_string(a) + " does not exist (0..3)");
    return ax_[a];
}
const CamcQi::Axis& CamcQi::ax(unsigned a) const {
    if (a >= axes) throw std::out_of_range("CAMC-QI: axis " + std::to_string(a) + " does not exist (0..3)");
    return ax_[a];
}

// ---------------------------------------------------------------------------------------------
// Bus interface

void CamcQi::b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
    BusView ext(gp, false);
    const std::uint64_t addr = gp.get_address();
    const unsigned len = gp.get_data_length();
    if (len == 0 || len > 4 || addr + len > win::size || gp.get_byte_enable_ptr()) {
        gp.set_response_status(len > 4 ? tlm::TLM_BURST_ERROR_RESPONSE : tlm::TLM_ADDRESS_ERROR_RESPONSE);
        return;
    }
    std::uint8_t* data = gp.get_data_ptr();
    // Bytes in ascending address order: a 32-bit write of DATA completes before a following
    // command byte, and a command written with DATA in one access executes last.
    for (unsigned i = 0; i < len; ++i) {
        const unsigned off = static_cast<unsigned>(addr) + i;
        if (gp.is_write())
            write_byte(off, data[i]);
        else
            data[i] = read_byte(off);
    }
    ext->wait_states = wait_states_;
    gp.set_response_status(tlm::TLM_OK_RESPONSE);
}

std::uint8_t CamcQi::read_byte(unsigned off) {
    if (off == win::irq_pending) {
        std::uint8_t m = 0;
        for (unsigned a = 0; a < axes; ++a)
            if (ax_[a].iflag & ax_[a].imask1) m |= static_cast<std::uint8_t>(1u << a);
        return m;
    }
    if (off == win::chip_id) return 0x06;
    if (off >= 0x40) return 0;
    const unsigned a = off / win::stride, f = off % win::stride;
    auto byte_of = [](std::uint32_t v, unsigned i) { return static_cast<std::uint8_t>(v >> (8 * i)); };
    if (f < 4) return byte_of(ax_[a].data, f);
    if (f == win::command) return ax_[a].last_cmd;
    if (f == win::drive_status || f == win::drive_status + 1) return byte_of(drive_status(a), f - win::drive_status);
    if (f == win::end_status || f == win::end_status + 1) return byte_of(ax_[a].end_status, f - win::end_status);
    if (f == win::mech_status || f == win::mech_status + 1) return byte_of(mech_status(a), f - win::mech_status);
    return 0;
}

void CamcQi::write_byte(unsigned off, std::uint8_t v) {
    if (off >= 0x40) return; // global registers are read-only
    const unsigned a = off / win::stride, f = off % win::stride;
    if (f < 4) {
        const unsigned sh = 8 * f;
        ax_[a].data = (ax_[a].data & ~(0xFFu << sh)) | (std::uint32_t{v} << sh);
    } else if (f == win::command) {
        ax_[a].last_cmd = v;
        execute(a, v);
    }
}

// ---------------------------------------------------------------------------------------------
// Commands and registers

void CamcQi::command(unsigned axis, std::uint8_t code, std::uint32_t data) {
    ax(axis).data = data;
    ax(axis).last_cmd = code;
    execute(axis, code);
}

std::uint32_t CamcQi::read_register(unsigned axis, std::uint8_t code) {
    command(axis, code, 0);
    return ax(axis).data;
}

void CamcQi::execute(unsigned axis, std::uint8_t code) {
    Axis& a = ax(axis);
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    switch (code) {
    case qi::STRN: start(axis); break;
    case qi::SSTOP:
        if (a.drive) {
            // The ramp down uses RATE2 as it is now (the host may lower it for this stop), of the
            // axis that holds the drive's rates: an interpolation's master, whichever member
            // axis the stop is written to (the others' RATE registers are not the path's).
            const ProfileParams now = params(ax_[a.drive->master], false);
            a.drive->params.decel = now.decel;
            a.drive->params.decel_jerk = now.decel_jerk;
            stop_drive(a.drive, true, endst::slowdown_cmd);
        }
        break;
    case qi::STOP:
        if (a.drive) stop_drive(a.drive, false, endst::stop_cmd);
        break;
    case qi::ESTOP:
        for (Axis& x : ax_)
            if (x.drive) stop_drive(x.drive, false, endst::estop_cmd);
        break;
    case qi::SWRESET:
        for (Axis& x : ax_)
            if (x.drive) stop_drive(x.drive, false, 0);
        for (Axis& x : ax_) {
            auto pins = x.pins;
            auto enc = std::move(x.encoder);
            const bool tr = x.trace;
            x = Axis{};
            x.pins = pins;
            x.encoder = std::move(enc);
            x.trace = tr;
        }
        break;
    case qi::INTGEN: a.iflag |= intf::user; break;
    case qi::ESCLR: a.end_status = 0; break;
    case qi::IFCLR1: a.iflag &= ~a.data; break;
    default:
        if (code & qi::write)
            write_register(axis, static_cast<std::uint8_t>(code & 0x7F), a.data);
        else
            a.data = [&]() -> std::uint32_t {
                switch (code) {
                case qi::RANGE: return a.range;
                case qi::STD: return a.std_speed;
                case qi::OBJ: return a.obj;
                case qi::RATE1: return a.rate1;
                case qi::RATE2: return a.rate2;
                case qi::SW1: return a.sw1;
                case qi::SW2: return a.sw2;
                case qi::DCFG: return a.dcfg;
                case qi::POS: return static_cast<std::uint32_t>(a.pos);
                case qi::CENT: return static_cast<std::uint32_t>(a.cent);
                case qi::ISNUM: return a.isnum;
                case qi::REMAIN: return static_cast<std::uint32_t>(a.remain);
                case qi::UIO: return a.uio;
                case qi::OBJORG: return a.objorg;
                case qi::JSPD: return a.jspd;
                case qi::JEXIT: return a.jexit;
                case qi::CURSPD: return static_cast<std::uint32_t>(std::lround(current_speed(axis)));
                case qi::DRPCNT: return static_cast<std::uint32_t>(a.driven);
                case qi::CNT1: return static_cast<std::uint32_t>(command_position(axis));
                case qi::CNT2: return static_cast<std::uint32_t>(encoder_position(axis));
                case qi::CNT3: return static_cast<std::uint32_t>(command_position(axis) - encoder_position(axis));
                case qi::UCFG1: return a.ucfg1;
                case qi::IMASK1: return a.imask1;
                case qi::STAT1: return a.end_status;
                case qi::STAT2: return drive_status(axis);
                case qi::STAT3: return mech_status(axis);
                case qi::IFLAG1: return a.iflag;
                default:
                    SC_REPORT_WARNING(name(), ("read command code 0x" + hex(code) + " is not modelled").c_str());
                    return 0;
                }
            }();
    }
    (void)now;
    wake_.notify(sc_core::SC_ZERO_TIME); // INT may change
}

void CamcQi::write_register(unsigned axis, std::uint8_t reg, std::uint32_t v) {
    Axis& a = ax(axis);
    switch (reg) {
    case qi::RANGE: a.range = v; break;
    case qi::STD: a.std_speed = v; break;
    case qi::OBJ: a.obj = v; break;
    case qi::RATE1: a.rate1 = v; break;
    case qi::RATE2: a.rate2 = v; break;
    case qi::SW1: a.sw1 = v; break;
    case qi::SW2: a.sw2 = v; break;
    case qi::DCFG: a.dcfg = v; break;
    case qi::POS: a.pos = static_cast<std::int32_t>(v); break;
    case qi::CENT: a.cent = static_cast<std::int32_t>(v); break;
    case qi::ISNUM: a.isnum = v; break;
    case qi::UIO: a.uio = v & 0x3; break;
    case qi::OBJORG: a.objorg = v; break;
    case qi::JSPD: a.jspd = v; break;
    case qi::JEXIT: a.jexit = v; break;
    case qi::CNT1:
        // Presetting the command counter while pulsing would tear the path: the chip ignores it.
        if (!a.drive) {
            a.preset_shift += static_cast<std::int32_t>(v) - a.cnt1;
            a.cnt1 = static_cast<std::int32_t>(v);
        }
        break;
    case qi::CNT2: {
        const std::int64_t raw = a.encoder ? a.encoder() : command_position(axis);
        a.enc_offset = static_cast<std::int32_t>(v) - raw;
        break;
    }
    case qi::UCFG1:
        a.ucfg1 = v;
        check_inputs(axis);
        if (a.drive) plan_edges(*a.drive);
        schedule();
        break;
    case qi::IMASK1: a.imask1 = v; break;
    default:
        SC_REPORT_WARNING(name(), ("write command code 0x" + hex(reg | qi::write) + " is not modelled").c_str());
    }
}

ProfileParams CamcQi::params(const Axis& a, bool origin) const {
    ProfileParams p;
    const double r = a.range;
    p.start_speed = a.std_speed * r;
    p.object_speed = (origin ? a.objorg : a.obj) * r;
    p.accel = a.rate1 * r;
    const unsigned prof = a.dcfg & dcfg::profile_mask;
    p.decel = (prof == 1 || prof == 3) ? a.rate2 * r : p.accel;
    if (prof >= 2) {
        p.accel_jerk = a.sw1 / 100.0;
        p.decel_jerk = (prof == 3 ? a.sw2 : a.sw1) / 100.0;
    }
    return p;
}

// ---------------------------------------------------------------------------------------------
// Pins and observation

void CamcQi::set_pin(unsigned axis, Pin p, bool level) {
    ax(axis).pins[static_cast<unsigned>(p)] = level;
    check_inputs(axis);
    if (auto d = ax_[axis].drive) plan_edges(*d);
    schedule();
    wake_.notify(sc_core::SC_ZERO_TIME);
}

void CamcQi::set_sensors(unsigned axis, const Sensors& s) {
    ax(axis).sensors = s;
    check_inputs(axis);
    if (auto d = ax_[axis].drive) plan_edges(*d);
    schedule();
    wake_.notify(sc_core::SC_ZERO_TIME);
}

bool CamcQi::pin(unsigned axis, Pin p) const { return ax(axis).pins[static_cast<unsigned>(p)]; }

void CamcQi::set_estop_pin(bool active) {
    estop_pin_ = active;
    if (active)
        for (Axis& a : ax_)
            if (a.drive) stop_drive(a.drive, false, endst::estop_signal);
    wake_.notify(sc_core::SC_ZERO_TIME);
}

void CamcQi::check_inputs(unsigned axis) {
    Axis& a = ax_[axis];
    if (!a.drive) return;
    auto d = a.drive;
    if (limit_active(a, Pin::alarm)) {
        stop_drive(d, false, endst::alarm);
        return;
    }
    const int dir = direction(axis);
    const bool slow = a.ucfg1 & ucfg::limit_slowdown;
    // A limit acts once (a slow-down stop runs on into it); a search for it is not stopped by it.
    auto acts = [&](Pin p, std::uint32_t bit) {
        return !(d->cause & bit) && !(d->search && d->search_pin == p) && limit_active(a, p);
    };
    if (dir > 0 && acts(Pin::pelm, endst::pelm)) {
        stop_drive(d, slow, endst::pelm);
        return;
    }
    if (dir < 0 && acts(Pin::nelm, endst::nelm)) {
        stop_drive(d, slow, endst::nelm);
        return;
    }
    if (d->search && limit_active(a, d->search_pin) != d->search_inactive) {
        d->search = false;
        stop_drive(d, !d->search_immediate, d->search_pin == Pin::org ? endst::home_ok : endst::signal_ok);
    }
}

int CamcQi::direction(unsigned axis) const {
    const Axis& a = ax(axis);
    if (!a.drive) return 0;
    return a.drive->direction(axis, a.drive->steps_at(sc_core::sc_time_stamp()));
}

void CamcQi::set_encoder_source(unsigned axis, std::function<std::int64_t()> src) {
    ax(axis).encoder = std::move(src);
}

void CamcQi::trace_pulses(unsigned axis, bool on) { ax(axis).trace = on; }

std::int64_t CamcQi::command_position(unsigned axis) const {
    const Axis& a = ax(axis);
    if (!a.drive) return a.cnt1;
    return a.drive->base[axis] + a.drive->offset(axis, a.drive->steps_at(sc_core::sc_time_stamp()));
}

std::int64_t CamcQi::encoder_position(unsigned axis) const {
    const Axis& a = ax(axis);
    return (a.encoder ? a.encoder() : command_position(axis)) + a.enc_offset;
}

bool CamcQi::busy(unsigned axis) const { return ax(axis).drive != nullptr; }

double CamcQi::current_speed(unsigned axis) const {
    const Axis& a = ax(axis);
    if (!a.drive) return 0;
    const double t = a.drive->rel(sc_core::sc_time_stamp());
    return t >= a.drive->end_t ? 0 : a.drive->profile.velocity(t);
}

std::uint32_t CamcQi::drive_status(unsigned axis) const {
    const Axis& a = ax(axis);
    std::uint32_t s = drvst::queue_empty;
    if (!a.drive) return s;
    const Drive& d = *a.drive;
    if (d.next) s &= ~drvst::queue_empty; // a blended drive waits
    const double t = d.rel(sc_core::sc_time_stamp());
    s |= drvst::busy | drvst::pulsing;
    switch (t >= d.end_t ? SpeedProfile::Phase::idle : d.profile.phase(t)) {
    case SpeedProfile::Phase::up: s |= drvst::up; break;
    case SpeedProfile::Phase::down: s |= drvst::down; break;
    case SpeedProfile::Phase::constant: s |= drvst::constant; break;
    default: break;
    }
    switch (d.mode) {
    case dcfg::preset: s |= drvst::preset; break;
    case dcfg::cont_pos: case dcfg::cont_neg: s |= drvst::continuous; break;
    case dcfg::origin_pos: case dcfg::origin_neg: s |= drvst::home; break;
    case dcfg::linear: s |= drvst::interpolating | drvst::linear; break;
    default: s |= drvst::interpolating | drvst::circular; break;
    }
    if (direction(axis) < 0) s |= drvst::negative;
    return s;
}

std::uint32_t CamcQi::mech_status(unsigned axis) const {
    const Axis& a = ax(axis);
    std::uint32_t s = 0;
    if (limit_active(a, Pin::pelm)) s |= mech::pelm;
    if (limit_active(a, Pin::nelm)) s |= mech::nelm;
    if (limit_active(a, Pin::alarm)) s |= mech::alarm;
    if (limit_active(a, Pin::org)) s |= mech::org;
    if (a.pins[static_cast<unsigned>(Pin::inp)]) s |= mech::inp;
    if (level(axis, Pin::zphase, pulse_count(axis))) s |= mech::zphase;
    if (estop_pin_) s |= mech::estop;
    return s;
}

} // namespace rcsim::camc
