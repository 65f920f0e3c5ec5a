// rcsim — the register set-ups WorstClocks tries an instruction with. See worst_clocks_setups.h.
#include "comm_cpu/i8086/worst_clocks_setups.h"

namespace rcsim::i8086::worst_setups {

std::vector<Registers> alignments(std::uint16_t cx) {
    static const std::uint8_t odd[6][4] = {
        // BX BP SI DI (AX, DX follow BX): each ModR/M sum both ways, the string pointers mixed
        {0, 0, 0, 0}, {1, 1, 1, 1}, {1, 1, 0, 0}, {0, 0, 1, 1}, {1, 0, 1, 0}, {0, 1, 0, 1},
    };
    std::vector<Registers> out;
    for (unsigned sp = 0; sp < 2; ++sp) // (SP's parity apart: a displacement flips the others')
        for (const auto& o : odd) {
            Registers r;
            r.r[BX] = std::uint16_t(0x0200 + o[0]);
            r.r[AX] = std::uint16_t(0x0400 + o[0]);
            r.r[DX] = std::uint16_t(0x0600 + o[0]);
            r.r[BP] = std::uint16_t(0x0800 + o[1]);
            r.r[SI] = std::uint16_t(0x0A00 + o[2]);
            r.r[DI] = std::uint16_t(0x0C00 + o[3]);
            r.r[SP] = std::uint16_t(0x8000 + sp);
            r.r[CX] = cx;
            r.flags = 0xF002;
            out.push_back(r);
        }
    return out;
}

std::vector<Values> muldiv_values(bool word) {
    std::vector<Values> v;
    const std::uint16_t many[] = {0x0000, 0x0001, 0x007F, 0x0080, 0x00FF, 0x7FFF, 0x8000, 0x8001, 0xFFFF,
                                  0xFF80, 0xFF81, 0x5555, 0xAAAA, 0x7F7F, 0x8080, 0xFFFE, 0x0002};
    for (std::uint16_t a : many)
        for (std::uint16_t m : many) v.push_back({a, a, m});
    // Division: dividend = quotient * divisor + remainder with the quotient's magnitude all ones
    // (unsigned) or 2^(n-1) - 1 (signed), positive and negative.
    const unsigned n = word ? 16 : 8;
    const std::uint32_t mask = (1u << n) - 1;
    for (std::uint32_t d : {1u, 2u, 3u, 5u, 0x7Fu, mask >> 1, mask - 1})
        for (std::uint32_t q : {mask, mask >> 1, mask >> 2, (mask >> 1) - 1})
            for (std::uint32_t rem : {0u, d - 1})
                for (int sd = 0; sd < 2; ++sd)
                    for (int sq = 0; sq < 2; ++sq) {
                        const std::uint64_t mag = std::uint64_t(q) * d + rem;
                        const std::uint64_t dividend = (sd ^ sq) ? (~mag + 1) : mag; // sign of the quotient * divisor
                        const std::uint32_t dv = sd ? ((~d + 1) & mask) : d;
                        if (word) v.push_back({std::uint16_t(dividend), std::uint16_t(dividend >> 16), std::uint16_t(dv)});
                        else v.push_back({std::uint16_t(dividend), 0, std::uint16_t(dv * 0x101)});
                    }
    std::uint32_t s = 0x2545F491;
    auto next = [&]() { return s = s * 1664525u + 1013904223u, std::uint16_t(s >> 16); };
    for (int i = 0; i < 64; ++i) {
        const std::uint16_t a = next(), d = next(), m = next();
        v.push_back({a, word ? std::uint16_t(d >> (i & 15)) : d, m});
    }
    return v;
}


} // namespace rcsim::i8086::worst_setups
