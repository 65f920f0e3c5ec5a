#include "models/memory.h"

#include <sstream>
#include <stdexcept>

namespace rcsim {

void MemoryMap::add(const MemRegion& region) {
    if (region.size == 0 || region.data == nullptr)
        throw std::invalid_argument("memory region '" + region.name + "' has no storage");
    for (const auto& r : regions_) {
        const bool overlap = region.base < r.base + r.size && r.base < region.base + region.size;
        if (overlap) {
            std::ostringstream os;
            os << "memory region '" << region.name << "' at 0x" << std::hex << region.base
               << " overlaps '" << r.name << "' at 0x" << r.base;
            throw std::invalid_argument(os.str());
        }
    }
    regions_.push_back(region);
    last_ = nullptr;
}

} // namespace rcsim
