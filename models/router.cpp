#include "models/router.h"

#include "models/bus.h"

#include <sstream>
#include <stdexcept>

namespace rcsim {

Router::Router(sc_core::sc_module_name name, bool io_space)
    : sc_module(name), in("in"), out("out"), io_space_(io_space) {
    in.register_b_transport(this, &Router::b_transport);
    in.register_transport_dbg(this, &Router::transport_dbg);
}

void Router::map(std::uint64_t base, std::uint64_t size, unsigned port, const std::string& what,
                 unsigned wait_states) {
    for (const auto& r : ranges_) {
        if (base < r.base + r.size && r.base < base + size) {
            std::ostringstream os;
            os << name() << ": range of '" << what << "' at 0x" << std::hex << base << " overlaps '"
               << r.what << "' at 0x" << r.base;
            throw std::invalid_argument(os.str());
        }
    }
    ranges_.push_back({base, size, port, what, wait_states});
}

void Router::declare_stable(std::uint64_t base, const StableReads* target) {
    for (auto& r : ranges_)
        if (r.base == base) {
            r.stable = target;
            return;
        }
    throw std::invalid_argument(std::string(name()) +
                                ": no range is mapped at the address a stable-read declaration names");
}

bool Router::read_is_stable(std::uint64_t address, unsigned len) const {
    const Range* r = decode(address);
    return r && r->stable && address - r->base + len <= r->size && r->stable->read_is_stable(address - r->base, len);
}

const Router::Range* Router::decode(std::uint64_t addr) const {
    for (const auto& r : ranges_)
        if (addr - r.base < r.size) return &r;
    return nullptr;
}

void Router::b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time& delay) {
    const std::uint64_t addr = gp.get_address();
    const Range* r = decode(addr);
    if (!r) {
        ++unmapped_;
        gp.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
        return;
    }
    gp.set_address(addr - r->base);
    out[r->port]->b_transport(gp, delay);
    gp.set_address(addr);
    if (r->wait_states)
        if (auto* ext = gp.get_extension<BusExtension>()) ext->wait_states += r->wait_states;
}

unsigned Router::transport_dbg(tlm::tlm_generic_payload& gp) {
    const std::uint64_t addr = gp.get_address();
    const Range* r = decode(addr);
    if (!r) return 0;
    gp.set_address(addr - r->base);
    const unsigned n = out[r->port]->transport_dbg(gp);
    gp.set_address(addr);
    return n;
}

} // namespace rcsim
