// rcsim — RAM/ROM regions reachable by direct pointer (the SystemC DMI idea without the protocol).
//
// A CPU model looks up the region of an address once per access and reads or writes the host
// buffer directly, adding the region's wait states to the bus cycle. Regions that need the kernel
// (DP-RAM with BUSY, memory-mapped peripherals) are not in this map: the CPU sends those through
// its TLM memory socket after syncing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rcsim {

struct MemRegion {
    std::string name;
    std::uint32_t base = 0;
    std::uint32_t size = 0;
    std::uint8_t* data = nullptr; // host buffer of `size` bytes, owned elsewhere
    unsigned wait_states = 0;     // Tw per bus cycle into this region
    bool writable = true;         // ROM: writes are ignored (and counted)

    bool contains(std::uint32_t addr) const { return addr - base < size; }
};

/// An ordered set of non-overlapping direct-access regions in a 20-bit (or wider) address space.
class MemoryMap {
public:
    /// Adds a region; throws std::invalid_argument naming both regions on overlap.
    void add(const MemRegion& region);
    /// The region holding addr, or nullptr.
    const MemRegion* find(std::uint32_t addr) const {
        if (last_ && last_->contains(addr)) return last_;
        for (const auto& r : regions_)
            if (r.contains(addr)) return last_ = &r;
        return nullptr;
    }
    const std::vector<MemRegion>& regions() const { return regions_; }

private:
    std::vector<MemRegion> regions_;
    mutable const MemRegion* last_ = nullptr;
};

} // namespace rcsim
