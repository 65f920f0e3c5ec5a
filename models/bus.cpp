#include "models/bus.h"

namespace rcsim {

const char* to_string(BusCycle kind) {
    switch (kind) {
    case BusCycle::int_ack: return "INTA";
    case BusCycle::io_read: return "IOR";
    case BusCycle::io_write: return "IOW";
    case BusCycle::halt: return "HALT";
    case BusCycle::code_fetch: return "CODE";
    case BusCycle::mem_read: return "MEMR";
    case BusCycle::mem_write: return "MEMW";
    case BusCycle::passive: return "PASV";
    }
    return "?";
}

BusView::BusView(tlm::tlm_generic_payload& gp, bool io_space) : ext_(gp.get_extension<BusExtension>()) {
    if (ext_) return;
    ext_ = &fallback_;
    BusExtension& e = fallback_;
    const bool write = gp.get_command() == tlm::TLM_WRITE_COMMAND;
    e.kind = io_space ? (write ? BusCycle::io_write : BusCycle::io_read)
                      : (write ? BusCycle::mem_write : BusCycle::mem_read);
    e.a0 = gp.get_address() & 1;
    e.bhe = gp.get_data_length() == 2 || (gp.get_address() & 1);
    e.start = sc_core::sc_time_stamp();
}

} // namespace rcsim
