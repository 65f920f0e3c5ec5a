// rcsim — IDT7130 1K x 8 dual-port static RAM. See idt7130.h and README.md.
#include "dpram/idt7130.h"

#include "models/clock.h"
#include "models/plumbing/hex.h"

#include <algorithm>
#include <string>

namespace rcsim {

namespace {

constexpr const char* kMsgType = "rcsim/idt7130";

// Whole clocks needed to cover t (t > 0), in exact integer picoseconds.
unsigned clocks_to_cover(const sc_core::sc_time& t, const sc_core::sc_time& clock) {
    return static_cast<unsigned>((t.value() + clock.value() - 1) / clock.value());
}

} // namespace

const char* to_string(Idt7130::Port port) { return port == Idt7130::left_port ? "left" : "right"; }

Idt7130::Idt7130(sc_core::sc_module_name name, unsigned speed_grade_ns)
    : sc_module(name), left("left"), right("right"), int_l("int_l"), int_r("int_r") {
    left.register_b_transport(this, &Idt7130::b_transport_left);
    left.register_transport_dbg(this, &Idt7130::transport_dbg);
    right.register_b_transport(this, &Idt7130::b_transport_right);
    right.register_transport_dbg(this, &Idt7130::transport_dbg);
    for (auto& p : ports) p = PortTiming{ns(125), 4};
    set_speed_grade(speed_grade_ns);

    SC_HAS_PROCESS(Idt7130);
    SC_METHOD(drive_pins);
    sensitive << pins_event_;
    dont_initialize();
}

// BUSY timing assumed per grade (unconfirmed, see dpram/README.md): the IDT70121/7016 figures,
// tAPS 5 ns; tBAA/tBDA 20 ns up to the 35 ns grade, 30 ns at 55 ns, 50 ns at 100 ns; tBDD 30-60 ns;
// tWH 15-20 ns. The 20 ns grade (PLCC/TQFP only) is given the 25 ns grade's figures.
Idt7130::BusyTiming Idt7130::grade_timing(unsigned speed_grade_ns) {
    switch (speed_grade_ns) {
    case 20:
    case 25: return {ns(5), ns(20), ns(20), ns(30), ns(15)};
    case 35: return {ns(5), ns(20), ns(20), ns(35), ns(20)};
    case 55: return {ns(5), ns(30), ns(30), ns(45), ns(20)};
    case 100: return {ns(5), ns(50), ns(50), ns(60), ns(20)};
    default:
        SC_REPORT_ERROR(kMsgType, ("speed grade " + std::to_string(speed_grade_ns) +
                                   " ns does not exist (IDT7130: 20, 25, 35, 55 or 100 ns)").c_str());
        return grade_timing(55); // only reached when errors are configured not to throw
    }
}

void Idt7130::set_speed_grade(unsigned speed_grade_ns) {
    timing = grade_timing(speed_grade_ns);
    grade_ = speed_grade_ns;
}

void Idt7130::end_of_elaboration() {
    for (unsigned p = 0; p < 2; ++p) {
        const auto& t = ports[p];
        if (t.clock == sc_core::SC_ZERO_TIME || t.cycle_clocks == 0)
            SC_REPORT_ERROR(kMsgType, (std::string(name()) + ": " + to_string(Port(p)) + " port timing (clock " +
                                       t.clock.to_string() + ", " + std::to_string(t.cycle_clocks) +
                                       " clocks per cycle) must be non-zero").c_str());
    }
}

void Idt7130::reset() {
    int_l_ = int_r_ = false;
    pin_changes_.clear();
    if (sc_core::sc_is_running()) {
        schedule_pin(true, false, sc_core::sc_time_stamp());
        schedule_pin(false, false, sc_core::sc_time_stamp());
    }
}

// ---------------------------------------------------------------------------------------------
// Functional access

bool Idt7130::check(Port port, tlm::tlm_generic_payload& gp) {
    const std::uint64_t address = gp.get_address();
    const unsigned len = gp.get_data_length();
    std::string problem;
    tlm::tlm_response_status status = tlm::TLM_OK_RESPONSE;
    if (!gp.is_read() && !gp.is_write()) {
        problem = "a command other than read or write";
        status = tlm::TLM_COMMAND_ERROR_RESPONSE;
    } else if (len < 1 || len > 2 || gp.get_streaming_width() < len) {
        problem = "a " + std::to_string(len) + "-byte access (a bus cycle moves 1 or 2 bytes)";
        status = tlm::TLM_BURST_ERROR_RESPONSE;
    } else if (gp.get_byte_enable_ptr() != nullptr) {
        problem = "byte enables (not supported: use 1-byte accesses)";
        status = tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE;
    } else if (address >= kSize || address + len > kSize) {
        problem = "address 0x" + hex(address, 3) + " (+" + std::to_string(len) + " bytes), outside 0x000-0x3FF";
        status = tlm::TLM_ADDRESS_ERROR_RESPONSE;
    }
    if (status == tlm::TLM_OK_RESPONSE) return true;
    SC_REPORT_WARNING(kMsgType, (std::string(name()) + ": " + to_string(port) + " port: " + problem).c_str());
    gp.set_response_status(status);
    return false;
}

void Idt7130::access(Port port, tlm::tlm_generic_payload& gp) {
    if (!check(port, gp)) return;
    BusView view(gp, false);
    const PortTiming& pt = ports[port];
    const bool write = gp.is_write();

    Window mine;
    mine.valid = true;
    mine.first = static_cast<unsigned>(gp.get_address());
    mine.last = mine.first + gp.get_data_length() - 1;
    mine.start = view->start;
    mine.end = mine.start + ps(pt.clock.value() * pt.cycle_clocks);

    const unsigned waits = arbitrate(port, mine, write);
    mine.end = mine.start + ps(pt.clock.value() * (pt.cycle_clocks + waits));
    last_[port] = mine;

    // The access lands now, after every access decided before it: a losing write therefore lands
    // after the winner's, and a losing read sees the winner's write.
    std::uint8_t* data = gp.get_data_ptr();
    for (unsigned a = mine.first; a <= mine.last; ++a) {
        if (write)
            mem_[a] = data[a - mine.first];
        else
            data[a - mine.first] = mem_[a];
        mailbox(port, a, write, mine.end);
    }

    ++stats_[port].accesses;
    view->wait_states = waits;
    gp.set_response_status(tlm::TLM_OK_RESPONSE);
}

// Decides BUSY for the access of `port` against the other port's latest cycle and returns the
// wait states it costs. The other port's cycle was decided first, so if the two collide this one
// is the later and loses (never both).
unsigned Idt7130::arbitrate(Port port, const Window& mine, bool write) {
    const Window& other = last_[port ^ 1];
    const bool same_location = other.valid && mine.first <= other.last && other.first <= mine.last;
    const bool overlap = same_location && mine.start < other.end && other.start < mine.end;
    if (!overlap) return 0;

    const PortTiming& pt = ports[port];
    const sc_core::sc_time match = std::max(mine.start, other.start);
    const sc_core::sc_time busy_high = other.end + timing.t_bda;
    const sc_core::sc_time done = busy_high + (write ? timing.t_wh : timing.t_bdd);
    // Tw states go between T3 and T4: the data phase ends with the second-to-last clock.
    const sc_core::sc_time data_end = mine.start + ps(pt.clock.value() * (pt.cycle_clocks - 1));
    const unsigned waits = done > data_end ? clocks_to_cover(done - data_end, pt.clock) : 0;

    const sc_core::sc_time gap = mine.start > other.start ? mine.start - other.start : other.start - mine.start;
    if (gap < timing.t_aps) ++inside_aps_;
    PortStats& st = stats_[port];
    ++st.busy;
    st.wait_states += waits;
    st.busy_wait += ps(pt.clock.value() * waits);
    if (on_busy) {
        const unsigned where = std::max(mine.first, other.first);
        on_busy(BusyEvent{port, where, write, match + timing.t_baa, busy_high, waits});
    }
    return waits;
}

// Mailbox flags follow the accesses in decision order; the INT pins move when the access that
// set or cleared them ends (write strobe / read completed).
void Idt7130::mailbox(Port port, unsigned address, bool write, const sc_core::sc_time& end) {
    if (port == right_port && write && address == kMailboxLeft) {
        int_l_ = true;
        schedule_pin(true, true, end);
    } else if (port == left_port && !write && address == kMailboxLeft) {
        int_l_ = false;
        schedule_pin(true, false, end);
    } else if (port == left_port && write && address == kMailboxRight) {
        int_r_ = true;
        schedule_pin(false, true, end);
    } else if (port == right_port && !write && address == kMailboxRight) {
        int_r_ = false;
        schedule_pin(false, false, end);
    }
}

void Idt7130::schedule_pin(bool left_pin, bool value, const sc_core::sc_time& when) {
    pin_changes_.push_back(PinChange{when, left_pin, value});
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    pins_event_.notify(when > now ? when - now : sc_core::SC_ZERO_TIME); // the earliest pending wins
}

void Idt7130::drive_pins() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    std::stable_sort(pin_changes_.begin(), pin_changes_.end(),
                     [](const PinChange& a, const PinChange& b) { return a.when < b.when; });
    auto due_end = pin_changes_.begin();
    for (; due_end != pin_changes_.end() && due_end->when <= now; ++due_end)
        (due_end->left ? int_l : int_r).write(due_end->value);
    pin_changes_.erase(pin_changes_.begin(), due_end);
    if (!pin_changes_.empty()) pins_event_.notify(pin_changes_.front().when - now);
}

// ---------------------------------------------------------------------------------------------
// Debug access: memory only, no arbitration, no mailbox side effects. Clipped to the array.

unsigned Idt7130::transport_dbg(tlm::tlm_generic_payload& gp) {
    const std::uint64_t address = gp.get_address();
    if (address >= kSize || (!gp.is_read() && !gp.is_write())) return 0;
    const unsigned len = static_cast<unsigned>(std::min<std::uint64_t>(gp.get_data_length(), kSize - address));
    std::uint8_t* data = gp.get_data_ptr();
    for (unsigned i = 0; i < len; ++i) {
        if (gp.is_write())
            mem_[address + i] = data[i];
        else
            data[i] = mem_[address + i];
    }
    return len;
}

} // namespace rcsim
