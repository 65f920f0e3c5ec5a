// rcsim — the main CPU as one processor shared by its activities.
//
// The main CPU is behavioural: its activities (control cycle, INT_R handler, command processing,
// response transmission) are separate SystemC threads, but the real board has one processor, so
// each activity holds the Processor for the time it computes or drives the bus and releases it
// when it waits for something else (an ACK, the next period). Busy periods do not preempt each
// other: the INT_R handler runs with interrupts masked, and the control cycle is a timer task that
// must wait for the handler to return. That is what makes DP-RAM traffic delay the control cycle
// (start jitter) and the control cycle delay the INT_R handler.
//
// When the processor is released and several activities wait, the highest priority wins
// (control cycle > interrupt > command > transmit), first come first served among equals. The
// choice is made a delta cycle after the processor becomes free (or is asked for while free), so
// the activities that release and ask at the same instant compete by priority, never in the order
// the kernel happened to run them.
#pragma once

#include <systemc>

#include <cstdint>
#include <vector>

namespace rcsim {

class Processor {
public:
    enum class Priority : int { control_cycle = 0, interrupt = 1, command = 2, transmit = 3 };

    explicit Processor(const char* name);

    /// Blocks the calling SC_THREAD until it owns the processor.
    void acquire(Priority prio);
    /// Gives the processor to the best waiter (or leaves it idle).
    void release();

    bool busy() const { return owned_; }
    /// The activity that holds the processor (meaningful while busy()).
    Priority owner() const { return owner_prio_; }
    /// The activity in words, for a verdict's cause ("the INT_R handler").
    static const char* activity(Priority p);
    /// Total simulated time the processor was owned, up to now.
    sc_core::sc_time busy_time() const;

private:
    struct Waiter {
        int prio;
        std::uint64_t ticket;
    };

    void choose_soon(); // the owner is chosen a delta cycle later (choose)
    void choose();      // the best waiter gets the processor
    bool owned_ = false;
    bool choosing_ = false; // choose_ is notified
    std::uint64_t owner_ticket_ = 0; // ticket of the owner, or of the waiter just granted
    Priority owner_prio_ = Priority::control_cycle;
    std::uint64_t next_ticket_ = 1;
    std::vector<Waiter> waiters_;
    sc_core::sc_event granted_, choose_;
    sc_core::sc_time busy_since_;
    sc_core::sc_time busy_total_;
};

} // namespace rcsim
