// A board run in a child process (models/plumbing/child_process.h), for a test that compares two runs of a
// board (a switch on and off): what the run counted comes back as counters and a byte log.
#pragma once

#include "models/plumbing/child_process.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace rcsim::test {

/// What a child run sends back: fixed counters, then a byte log.
struct ChildResult {
    std::vector<std::uint64_t> counts;
    std::vector<std::uint8_t> log;
};

/// Runs `body` in a child process (models/plumbing/child_process.h) and returns what it returned. The
/// child's own failure (an exception, a short write, a crash) fails the calling test and gives an
/// empty result.
inline ChildResult run_in_child(const std::function<ChildResult()>& body) {
    const std::optional<std::string> bytes = run_in_child_process(
        [&] {
            const ChildResult r = body();
            const std::uint64_t sizes[2] = {r.counts.size(), r.log.size()};
            std::string out(reinterpret_cast<const char*>(sizes), sizeof sizes);
            out.append(reinterpret_cast<const char*>(r.counts.data()), r.counts.size() * sizeof(std::uint64_t));
            out.append(reinterpret_cast<const char*>(r.log.data()), r.log.size());
            return out;
        },
        "child run");
    EXPECT_TRUE(bytes.has_value()) << "the child run failed";
    ChildResult r;
    std::uint64_t head[2] = {}; // the sizes the child announced: counts, log bytes
    if (!bytes || bytes->size() < sizeof head) return r;
    std::memcpy(head, bytes->data(), sizeof head);
    const std::size_t counts_bytes = head[0] * sizeof(std::uint64_t);
    if (bytes->size() != sizeof head + counts_bytes + head[1]) {
        ADD_FAILURE() << "the child run sent " << bytes->size() << " bytes, not the ones it announced";
        return r;
    }
    r.counts.resize(head[0]);
    std::memcpy(r.counts.data(), bytes->data() + sizeof head, counts_bytes);
    r.log.assign(bytes->begin() + std::ptrdiff_t(sizeof head + counts_bytes), bytes->end());
    return r;
}

} // namespace rcsim::test
