// rcsim — loops and the longest path through a part of a FlowGraph (scenarios/bound/bound.h).
//
// The part (a handler's whole graph, or the main code's IF = 0 nodes) is entered from a set of
// sources. Its loops are its strongly connected parts, nested: the header of each is the node
// the depth-first search enters first, and a loop may be entered elsewhere too (hand-written
// assembly jumps into the middle of a loop: such an entry costs its way to the header, then the
// loop as usual). Each loop is bounded once; then, for
// a weight per node (a service's clocks, or only the blocking ones), the loops are collapsed
// innermost first into one step that costs (bound - 1) x its longest iteration plus its longest
// way out, and the longest path of what is left is the bound. The path is expanded back into
// instructions with how often the worst path runs each.
#pragma once

#include "scenarios/bound/flow.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rcsim::bound {

struct LoopFound {
    int header = 0;
    std::vector<int> body;    // nodes, the header included
    std::vector<int> latches; // nodes with an edge back to the header
    std::vector<int> entries; // other nodes entered from outside (a loop with two entries)
    std::uint64_t bound = 1;  // how often the header runs per entry into the loop
    std::string reason;
};

/// Gives a loop its bound and the reason, or throws ConfigError naming the line to add.
using LoopBounder = std::function<void(LoopFound&)>;

class Paths {
public:
    Paths(const FlowGraph& graph, std::vector<bool> member, std::vector<int> sources, const LoopBounder& bounder);
    struct Longest {
        std::uint64_t clocks = 0;
        /// (node, times, fell through) in path order: a conditional transfer the path runs both
        /// ways is listed once per way, as its weight differs.
        struct Ran {
            int node;
            std::uint64_t times;
            bool fell;
        };
        std::vector<Ran> nodes;
        std::vector<int> loops; // indexes into loops() on the path
    };
    /// The longest path: a path weighs the sum over the nodes it runs of `weight`, or of `fall`
    /// where a conditional transfer falls through to the next instruction (nullptr: `weight`
    /// there too). A path may end at any node (weights are never negative).
    Longest longest(const std::vector<std::uint64_t>& weight, const std::vector<std::uint64_t>* fall = nullptr) const;
    const std::vector<LoopFound>& loops() const { return loops_; }

private:
    void find_loops(const LoopBounder& bounder);
    const FlowGraph& g_;
    std::vector<bool> member_;
    std::vector<int> sources_;
    std::vector<LoopFound> loops_; // innermost first
};

} // namespace rcsim::bound
