// rcsim — behavioural main CPU of the robot controller (no ISS).
//
// The main board's processor as the communication board sees it through the IDT7130's right
// port: an INT_R handler that takes mailbox words, a DP-RAM driver doing byte accesses (stretched
// by BUSY wait states), frame reassembly from 339-byte chunks, a token dispatcher (docs/system.md §7)
// whose responses go back through the DP-RAM chunk by chunk, and a periodic control cycle that
// calls the motion layer and whose start jitter is measured.
//
// The processor is modelled as one resource (Processor): handler, command processing, response
// writing and control cycle each hold it while busy, so they delay each other. See README.md for
// the properties and their defaults.
#pragma once

#include "main_cpu/dispatcher.h"
#include "models/dpram_layout.h"
#include "models/frame_codec.h"
#include "main_cpu/motion_interface.h"
#include "main_cpu/processor.h"
#include "models/bus.h"
#include "models/clock.h"
#include "models/stats.h"

#include <nlohmann/json.hpp>
#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

namespace rcsim {

/// Timing properties of the main CPU. validate() rejects nonsense with a message naming the value.
struct MainCpuConfig {
    std::uint64_t bus_clock_hz = 16'000'000; // main CPU bus clock; BUSY wait states count in it
    unsigned access_cycles = 4;              // one DP-RAM byte bus cycle without wait states
    unsigned copy_loop_cycles = 4;           // per-byte instruction overhead of a copy loop
    sc_core::sc_time irq_entry = us(5);          // INT_R acknowledge + context save
    sc_core::sc_time command_time = us(50);      // processing of one command
    sc_core::sc_time cycle_period = us(1000);    // control cycle period
    sc_core::sc_time cycle_time = us(100);       // processor time of one control cycle
    sc_core::sc_time ack_timeout = us(500000);   // response chunk -> its ACK word
    sc_core::sc_time poll_interval = us(100);    // retry while pflag[p] != 0
    sc_core::sc_time mailbox_gap = sc_core::SC_ZERO_TIME; // least time between int2ext words
    // Mailbox handshake, as the comm firmware does it (README "Mailbox words"): the reader of a
    // mailbox writes 0 to it after reading, and a writer waits until its mailbox reads 0.
    bool mailbox_handshake = true;
    sc_core::sc_time mailbox_poll = us(10); // handshake: retry while int2ext != 0
    // The motion layer's cost when the main CPU hosts one (docs/motion.md "Main-CPU cost"): its
    // CAMC-QI accesses run on this bus clock with access_cycles each, plus this per block call.
    sc_core::sc_time fb_call = us(5);
    // A loaded program's cost (docs/st.md "Cost in the control cycle"): this per statement it
    // executes (the statement budget's count), and fb_call per motion block it calls. A model
    // parameter, not a measurement: 32 clocks of the 16 MHz bus clock, a statement compiled to
    // about 8 instructions of about 4 clocks each.
    sc_core::sc_time statement_time = us(2);

    void validate() const;
};

/// Counters of one port (port p = DP-RAM area p, docs/system.md §4.1).
struct MainCpuPortStats {
    std::uint64_t frames_received = 0; // valid frames reassembled and dispatched
    std::uint64_t bytes_received = 0;  // bytes of those frames, SOH..ETX
    std::uint64_t chunks_received = 0;
    std::uint64_t malformed = 0;       // reassembled but invalid: counted, not dispatched
    std::uint64_t frames_sent = 0;     // response frames whose every chunk was ACKed
    std::uint64_t bytes_sent = 0;
    std::uint64_t chunks_sent = 0;
    std::uint64_t resets_received = 0; // 0x3p words from the comm CPU
    std::uint64_t resets_sent = 0;     // 0x3p words to the comm CPU
    std::uint64_t partial_dropped = 0; // incomplete incoming frames dropped by a reset
    std::uint64_t tx_aborted = 0;      // outgoing frames abandoned because of a reset
    std::uint64_t ack_timeouts = 0;    // outgoing frames abandoned because no ACK came
    std::uint64_t unexpected_acks = 0; // ACK words while no chunk of ours was outstanding
    // Response frames the comm CPU gave up on after its retries (0x4p + 0x5p words), one each;
    // of those, the ones that had left whole at least once (0x5p: the host may have them).
    std::uint64_t responses_dropped = 0;
    std::uint64_t responses_dropped_sent = 0;
};

/// A frame as the main CPU received (valid, dispatched) or sent it.
struct FrameRecord {
    unsigned port = 0;
    sc_core::sc_time time; // received: last chunk copied; sent: last chunk ACKed
    std::string token;
    std::uint8_t bch = 0;
    std::string data;
};

/// A reassembled frame that failed validation.
struct MalformedRecord {
    unsigned port = 0;
    sc_core::sc_time time;
    std::string reason;
};

class MainCpu : public sc_core::sc_module {
public:
    tlm_utils::simple_initiator_socket<MainCpu> dpram; // IDT7130 right port
    sc_core::sc_in<bool> int_r;                        // INT_R, true = asserted

    SC_HAS_PROCESS(MainCpu);
    explicit MainCpu(sc_core::sc_module_name name, const MainCpuConfig& config = MainCpuConfig());

    /// The motion layer for motion tokens and the control cycle; nullptr = none (BCH 04).
    void set_motion(MotionInterface* motion) { dispatcher_.set_motion(motion); }
    /// The loaded user program (docs/st.md), run once per control cycle after the motion layer.
    void set_program(ProgramInterface* program) { dispatcher_.set_program(program); }

    /// Queues a controller-initiated frame to port p (sent like a response). Throws
    /// std::invalid_argument for a bad port or a frame that cannot be encoded.
    void send(unsigned port, const std::string& token, const std::string& data,
              std::uint8_t bch = bch::ok);
    /// Asks the comm CPU to reset port p (0x3p in int2ext); drops our partial and in-flight
    /// frames of that port. Throws std::invalid_argument for a bad port.
    void request_port_reset(unsigned port);

    const MainCpuConfig& config() const { return config_; }
    const Dispatcher& dispatcher() const { return dispatcher_; }
    /// A command from the main board's own console (the remote monitor, docs/monitor.md): the
    /// token dispatcher executes it at once, as it would a frame's, but no frame is received and
    /// no response is sent; the caller gets the outcome. Call between sc_start()s or from a process.
    Outcome execute_local(const std::string& token, const std::string& data) {
        return dispatcher_.execute(token, data);
    }
    const MainCpuPortStats& port_stats(unsigned port) const { return ports_.at(port).stats; }
    /// received() and sent() keep every frame while `keep_history` is on (the default, for
    /// tests); a long run turns it off and listens to on_received and on_sent.
    void keep_history(bool on) { keep_history_ = on; }
    const std::vector<FrameRecord>& received() const { return received_; }
    const std::vector<FrameRecord>& sent() const { return sent_; }
    /// Called with each valid frame received, in order.
    std::function<void(const FrameRecord&)> on_received;
    /// Called with each response frame as it is handed to DP-RAM, in order.
    std::function<void(const FrameRecord&)> on_sent;
    const std::vector<MalformedRecord>& malformed() const { return malformed_; }

    /// Control-cycle start jitter (actual start - ideal start), microseconds, one per cycle.
    const Samples& cycle_jitter_us() const { return cycle_jitter_us_; }
    /// Control-cycle duration (start to the end of its work, cycle_time included), microseconds.
    const Samples& cycle_duration_us() const { return cycle_duration_us_; }
    /// INT_R rise to the first handler instruction, microseconds, one per handler run.
    const Samples& irq_latency_us() const { return irq_latency_us_; }
    std::uint64_t control_cycles() const { return control_cycles_; }
    /// What the loaded program executed in all, and the processor time charged for it.
    std::uint64_t program_statements() const { return program_work_.statements; }
    std::uint64_t program_motion_calls() const { return program_work_.motion_calls; }
    sc_core::sc_time program_time() const { return program_time_; }
    std::uint64_t cycle_overruns() const { return cycle_overruns_; }
    std::uint64_t mailbox_words() const { return mailbox_words_; }
    std::uint64_t unknown_words() const { return unknown_words_; }
    /// Handshake mode: int2ext words written although the previous one was still unread after
    /// ack_timeout (the comm CPU does not clear it).
    std::uint64_t mailbox_overwrites() const { return mailbox_overwrites_; }
    std::uint64_t dpram_accesses() const { return dpram_accesses_; }
    /// Time added to DP-RAM accesses by BUSY wait states.
    sc_core::sc_time busy_wait() const { return busy_wait_; }

    /// Everything above for a report: main_cpu.{cycle_jitter_us, irq_latency_us, ports[], ...}.
    nlohmann::json report() const;

private:
    struct Outgoing {
        std::string bytes;
        FrameRecord record;
    };
    struct Port {
        // receive side
        std::string rx;          // bytes of the frame being reassembled
        bool rx_overflow = false; // the frame outgrew max_frame; drain until ETX, then count it
        // transmit side
        std::deque<Outgoing> queue;
        sc_core::sc_event wake;    // queue push, ACK, reset
        bool awaiting_ack = false;
        bool acked = false;
        std::uint64_t epoch = 0;   // bumped by every reset; an in-flight frame of an older epoch aborts
        bool reset_request = false;
        MainCpuPortStats stats;
    };
    struct Received {
        unsigned port;
        proto::Frame frame;
    };

    // processes
    void irq_thread();
    void on_int_r_rise();
    void dispatch_thread();
    void tx_thread0() { tx_thread(0); }
    void tx_thread1() { tx_thread(1); }
    void tx_thread2() { tx_thread(2); }
    void tx_thread(unsigned p);
    void cycle_thread();
    void run_program(ProgramInterface& p, const sc_core::sc_time& start);

    // INT_R handler parts (called with the processor held)
    void handle_word(std::uint8_t word);
    void receive_chunk(unsigned p);
    void finish_frame(unsigned p);
    void drop_partial(unsigned p);

    // transmit parts
    bool claim_and_write_chunk(unsigned p, const std::string& chunk, bool first, std::uint64_t epoch);
    enum class AckResult { acked, reset, timeout };
    AckResult wait_ack(unsigned p, std::uint64_t epoch);
    void send_reset(unsigned p, bool release_area);
    void enqueue(unsigned p, const proto::Frame& f);

    // bus
    std::uint8_t read_byte(std::uint16_t addr, unsigned extra_cycles = 0);
    void write_byte(std::uint16_t addr, std::uint8_t value, unsigned extra_cycles = 0);
    void access(BusCycle kind, std::uint16_t addr, std::uint8_t& value, unsigned extra_cycles);
    void write_mailbox(std::uint8_t word, Processor::Priority prio);
    void wait_mailbox_empty(Processor::Priority prio);

    void log(const std::string& msg) const;
    void check_port(unsigned port, const char* what) const;

    MainCpuConfig config_;
    Clock clock_;
    Processor cpu_;
    Dispatcher dispatcher_;
    std::array<Port, dpram_layout::ports> ports_;

    std::deque<Received> rx_frames_;
    sc_core::sc_event rx_frame_event_;
    sc_core::sc_time int_r_rise_;
    sc_core::sc_time next_mailbox_slot_;

    bool keep_history_ = true;
    std::vector<FrameRecord> received_;
    std::vector<FrameRecord> sent_;
    std::vector<MalformedRecord> malformed_;
    Samples cycle_jitter_us_;
    Samples cycle_duration_us_;
    Samples irq_latency_us_;
    std::uint64_t control_cycles_ = 0;
    ProgramWork program_work_;
    sc_core::sc_time program_time_;
    std::uint64_t cycle_overruns_ = 0;
    std::uint64_t mailbox_words_ = 0;
    std::uint64_t unknown_words_ = 0;
    std::uint64_t mailbox_overwrites_ = 0;
    std::uint64_t dpram_accesses_ = 0;
    BusPayload payload_; // every DP-RAM access (one at a time: the control thread waits in it)
    sc_core::sc_time busy_wait_;
};

} // namespace rcsim
