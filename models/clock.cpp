#include "models/clock.h"

#include <stdexcept>
#include <string>

namespace rcsim {

Clock::Clock(std::uint64_t hz) : hz_(hz) {
    if (hz == 0 || hz > 1'000'000'000'000ULL)
        throw std::invalid_argument("clock frequency out of range: " + std::to_string(hz) + " Hz");
    period_ps_ = (1'000'000'000'000ULL + hz / 2) / hz;
    for (std::size_t i = 0; i < table_.size(); ++i)
        table_[i] = ps(i * period_ps_);
}

} // namespace rcsim
