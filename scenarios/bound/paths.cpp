// rcsim — loops and the longest path through a part of a FlowGraph. See paths.h.
#include "scenarios/bound/paths.h"

#include "models/plumbing/config_error.h"

#include <algorithm>
#include <map>
#include <set>

namespace rcsim::bound {
namespace {

constexpr int kRoot = -1, kSink = -2;

/// An edge of the graph as the collapse leaves it. An original edge leaves node `from` (it
/// costs from's weight); a loop's exit edge costs the loop and the way out: `iteration` and
/// `way_out` are chains of earlier edges (indexes), run bound - 1 times and once.
struct Edge {
    int from = 0, to = 0;
    std::uint64_t w = 0;
    int loop = -1;           // -1: an original edge; -2: a chain (a loop entered elsewhere)
    std::uint64_t times = 0; // bound - 1
    std::vector<int> iteration, way_out;
    int from_node = -1;      // the original edge's node
    bool fell = false;       // ... a conditional transfer's fall-through
};

Edge edge(int from, int to, std::uint64_t w, int from_node = -1) {
    Edge e;
    e.from = from;
    e.to = to;
    e.w = w;
    e.from_node = from_node;
    return e;
}

struct Arena {
    std::vector<Edge> edges;
    int add(Edge e) {
        edges.push_back(std::move(e));
        return int(edges.size() - 1);
    }
    using Key = std::pair<int, bool>; // node, fell through
    void expand(int e, std::uint64_t mult, std::map<Key, std::uint64_t>& times, std::vector<Key>& order,
                std::set<int>& loops) const {
        const Edge& x = edges[std::size_t(e)];
        if (x.loop == -1) {
            if (x.from_node < 0) return;
            const Key k{x.from_node, x.fell};
            if (times[k] == 0) order.push_back(k);
            times[k] += mult;
            return;
        }
        if (x.loop >= 0) loops.insert(x.loop);
        for (int i : x.iteration) expand(i, mult * x.times, times, order, loops);
        for (int i : x.way_out) expand(i, mult, times, order, loops);
    }
};

/// Longest paths from `start` over `edges` (a DAG once loops are collapsed): distance and the
/// edge that reached each node.
void dag_longest(int start, const std::vector<int>& edges, const Arena& a, std::map<int, std::uint64_t>& dist,
                 std::map<int, int>& via) {
    std::map<int, std::vector<int>> out;
    std::map<int, int> indeg;
    for (int e : edges) {
        const Edge& x = a.edges[std::size_t(e)];
        out[x.from].push_back(e);
        ++indeg[x.to];
    }
    // Kahn from the nodes reachable from start.
    std::set<int> seen{start};
    std::vector<int> stack{start};
    std::map<int, int> reach_indeg;
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        for (int e : out[n]) {
            const int t = a.edges[std::size_t(e)].to;
            ++reach_indeg[t];
            if (seen.insert(t).second) stack.push_back(t);
        }
    }
    dist[start] = 0;
    std::vector<int> ready{start};
    while (!ready.empty()) {
        const int n = ready.back();
        ready.pop_back();
        for (int e : out[n]) {
            const Edge& x = a.edges[std::size_t(e)];
            const std::uint64_t d = dist[n] + x.w;
            if (!dist.count(x.to) || d > dist[x.to] || (d == dist[x.to] && !via.count(x.to))) {
                dist[x.to] = d;
                via[x.to] = e;
            }
            if (--reach_indeg[x.to] == 0) ready.push_back(x.to);
        }
    }
}

std::vector<int> chain_to(int node, int start, const std::map<int, int>& via, const Arena& a) {
    std::vector<int> chain;
    for (int n = node; n != start;) {
        const int e = via.at(n);
        chain.push_back(e);
        n = a.edges[std::size_t(e)].from;
    }
    std::reverse(chain.begin(), chain.end());
    return chain;
}

/// A loop entered elsewhere than at its header h (hand-written assembly jumps into the middle of
/// a loop): each such entry becomes the way from it to the header (then the loop runs as usual)
/// and each way from it straight out, as edges of their own.
void enter_elsewhere(const std::vector<int>& entering, const std::vector<int>& inside, const std::vector<int>& backs,
                     const std::vector<int>& exits, int h, Arena& a, std::vector<int>& rest) {
for (int e : entering) {
    const Edge x = a.edges[std::size_t(e)];
    std::map<int, std::uint64_t> dm;
    std::map<int, int> vm;
    dag_longest(x.to, inside, a, dm, vm);
    for (int b : backs) {
        const Edge& y = a.edges[std::size_t(b)];
        if (!dm.count(y.from)) continue;
        Edge z = edge(x.from, h, x.w + dm[y.from] + y.w);
        z.loop = -2;
        z.way_out.push_back(e);
        for (int c : chain_to(y.from, x.to, vm, a)) z.way_out.push_back(c);
        z.way_out.push_back(b);
        rest.push_back(a.add(std::move(z)));
    }
    for (int o : exits) {
        const Edge& y = a.edges[std::size_t(o)];
        if (!dm.count(y.from)) continue;
        Edge z = edge(x.from, y.to, x.w + dm[y.from] + y.w);
        z.loop = -2;
        z.way_out.push_back(e);
        for (int c : chain_to(y.from, x.to, vm, a)) z.way_out.push_back(c);
        z.way_out.push_back(o);
        rest.push_back(a.add(std::move(z)));
    }
}
}

/// Collapses loop `li` (its nodes by their current representatives) into its header: the edges
/// out of it become one per target, each costing (bound - 1) x the longest round plus the longest
/// way from the header to that exit.
void collapse_loop(const LoopFound& l, int li, Arena& a, std::vector<int>& live, std::vector<int>& rep) {
    std::set<int> body;
    for (int v : l.body) body.insert(rep[std::size_t(v)]);
    const int h = rep[std::size_t(l.header)];
    std::set<int> entries;
    for (int v : l.entries) entries.insert(rep[std::size_t(v)]);
    entries.erase(h);
    std::vector<int> inside, backs, exits, rest, entering;
    for (int e : live) {
        const Edge& x = a.edges[std::size_t(e)];
        if (!body.count(x.from) && entries.count(x.to)) entering.push_back(e);
        else if (!body.count(x.from)) rest.push_back(e);
        else if (x.to == h) backs.push_back(e);
        else if (body.count(x.to)) inside.push_back(e);
        else exits.push_back(e);
    }
    std::map<int, std::uint64_t> dist;
    std::map<int, int> via;
    dag_longest(h, inside, a, dist, via);
    std::uint64_t iter = 0;
    std::vector<int> iter_chain;
    for (int e : backs) {
        const Edge& x = a.edges[std::size_t(e)];
        if (!dist.count(x.from)) continue;
        if (dist[x.from] + x.w >= iter) {
            iter = dist[x.from] + x.w;
            iter_chain = chain_to(x.from, h, via, a);
            iter_chain.push_back(e);
        }
    }
    std::map<int, int> best_exit; // target -> new edge
    for (int e : exits) {
        const Edge x = a.edges[std::size_t(e)];
        if (!dist.count(x.from)) continue;
        Edge y = edge(h, x.to, (l.bound - 1) * iter + dist[x.from] + x.w);
        y.loop = li;
        y.times = l.bound - 1;
        y.iteration = iter_chain;
        y.way_out = chain_to(x.from, h, via, a);
        y.way_out.push_back(e);
        auto it = best_exit.find(x.to);
        if (it == best_exit.end() || a.edges[std::size_t(it->second)].w < y.w) best_exit[x.to] = a.add(std::move(y));
    }
    enter_elsewhere(entering, inside, backs, exits, h, a, rest);
    live = rest;
    for (auto& [t, e] : best_exit) live.push_back(e);
    for (int v : l.body) rep[std::size_t(v)] = h;
    for (auto& r : rep)
        if (body.count(r)) r = h;
}

} // namespace

Paths::Paths(const FlowGraph& graph, std::vector<bool> member, std::vector<int> sources, const LoopBounder& bounder)
    : g_(graph), member_(std::move(member)), sources_(std::move(sources)) {
    find_loops(bounder);
}

void Paths::find_loops(const LoopBounder& bounder) {
    const auto& nodes = g_.nodes();
    const std::size_t n = nodes.size();
    // Depth-first preorder from the sources: a loop's header is the node of it entered first.
    std::vector<int> pre(n, -1);
    int counter = 0;
    for (int s : sources_) {
        if (pre[std::size_t(s)] >= 0) continue;
        std::vector<std::pair<int, std::size_t>> stack{{s, 0}};
        pre[std::size_t(s)] = counter++;
        while (!stack.empty()) {
            auto& [v, i] = stack.back();
            const auto& out = nodes[std::size_t(v)].out;
            if (i < out.size()) {
                const int t = out[i++].to;
                if (member_[std::size_t(t)] && pre[std::size_t(t)] < 0) {
                    pre[std::size_t(t)] = counter++;
                    stack.push_back({t, 0});
                }
            } else {
                stack.pop_back();
            }
        }
    }
    std::vector<std::vector<int>> preds(n);
    for (std::size_t v = 0; v < n; ++v)
        if (pre[v] >= 0)
            for (const auto& e : nodes[v].out)
                if (member_[std::size_t(e.to)] && pre[std::size_t(e.to)] >= 0) preds[std::size_t(e.to)].push_back(int(v));
    std::vector<int> all;
    for (std::size_t v = 0; v < n; ++v)
        if (pre[v] >= 0) all.push_back(int(v));
    // Nested strongly connected parts, innermost first: a part, then the parts of it without its header.
    std::vector<char> in_set(n, 0);
    std::vector<std::vector<int>> work{all};
    std::vector<LoopFound> found;
    while (!work.empty()) {
        std::vector<int> set = std::move(work.back());
        work.pop_back();
        for (int v : set) in_set[std::size_t(v)] = 1;
        // Tarjan's algorithm, without recursion.
        std::map<int, int> index, low;
        std::vector<int> stack;
        std::set<int> on_stack;
        int next = 0;
        for (int root : set) {
            if (index.count(root)) continue;
            std::vector<std::pair<int, std::size_t>> call{{root, 0}};
            index[root] = low[root] = next++;
            stack.push_back(root);
            on_stack.insert(root);
            while (!call.empty()) {
                auto& [v, i] = call.back();
                const auto& out = nodes[std::size_t(v)].out;
                if (i < out.size()) {
                    const int t = out[i++].to;
                    if (!in_set[std::size_t(t)]) continue;
                    if (!index.count(t)) {
                        index[t] = low[t] = next++;
                        stack.push_back(t);
                        on_stack.insert(t);
                        call.push_back({t, 0});
                    } else if (on_stack.count(t)) {
                        low[v] = std::min(low[v], index[t]);
                    }
                    continue;
                }
                const int done = v;
                call.pop_back();
                if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[done]);
                if (low[done] != index[done]) continue;
                std::vector<int> part;
                for (int w = -1; w != done;) {
                    w = stack.back();
                    stack.pop_back();
                    on_stack.erase(w);
                    part.push_back(w);
                }
                const bool self = std::any_of(nodes[std::size_t(done)].out.begin(), nodes[std::size_t(done)].out.end(),
                                              [&](const Node::Edge& e) { return e.to == done; });
                if (part.size() < 2 && !self) continue;
                std::set<int> body(part.begin(), part.end());
                LoopFound l;
                l.header = *std::min_element(part.begin(), part.end(),
                                             [&](int a, int b) { return pre[std::size_t(a)] < pre[std::size_t(b)]; });
                l.body.assign(body.begin(), body.end());
                for (int p : preds[std::size_t(l.header)])
                    if (body.count(p)) l.latches.push_back(p);
                for (int v2 : l.body)
                    if (v2 != l.header &&
                        std::any_of(preds[std::size_t(v2)].begin(), preds[std::size_t(v2)].end(),
                                    [&](int p) { return !body.count(p); }))
                        l.entries.push_back(v2);
                std::vector<int> inner;
                for (int v2 : l.body)
                    if (v2 != l.header) inner.push_back(v2);
                if (!inner.empty()) work.push_back(inner);
                found.push_back(std::move(l));
            }
        }
        for (int v : set) in_set[std::size_t(v)] = 0;
    }
    loops_ = std::move(found);
    std::stable_sort(loops_.begin(), loops_.end(),
                     [](const LoopFound& a, const LoopFound& b) { return a.body.size() < b.body.size(); });
    for (LoopFound& l : loops_) bounder(l);
}

Paths::Longest Paths::longest(const std::vector<std::uint64_t>& weight, const std::vector<std::uint64_t>* fall) const {
    const auto& nodes = g_.nodes();
    Arena a;
    std::vector<int> live; // edge indexes of the current graph
    for (int s : sources_) live.push_back(a.add(edge(kRoot, s, 0)));
    for (std::size_t v = 0; v < nodes.size(); ++v) {
        if (!member_[v]) continue;
        const Insn& i = *nodes[v].insn;
        const bool branch = i.flow == i8086::Flow::branch;
        const std::uint64_t w_fall = fall ? (*fall)[v] : weight[v];
        for (const auto& e : nodes[v].out) {
            if (!member_[std::size_t(e.to)]) continue;
            const bool fell = branch && nodes[std::size_t(e.to)].address == nodes[v].address + i.length &&
                              nodes[std::size_t(e.to)].context == nodes[v].context;
            Edge x = edge(int(v), e.to, fell ? w_fall : weight[v], int(v));
            x.fell = fell;
            live.push_back(a.add(std::move(x)));
        }
        // A path ends where the part ends: an IRET or HLT (no successor), or an edge out of the
        // part (the main code's IF = 0 stretch ends where IF = 1 again). Nowhere else: a loop
        // whose count is spent must leave by one of its exits.
        const bool ends = nodes[v].out.empty() ||
                          std::any_of(nodes[v].out.begin(), nodes[v].out.end(),
                                      [&](const Node::Edge& e) { return !member_[std::size_t(e.to)]; });
        if (ends) live.push_back(a.add(edge(int(v), kSink, std::max(weight[v], w_fall), int(v))));
    }
    std::vector<int> rep(nodes.size());
    for (std::size_t v = 0; v < nodes.size(); ++v) rep[v] = int(v);
    for (std::size_t li = 0; li < loops_.size(); ++li) collapse_loop(loops_[li], int(li), a, live, rep);
    std::map<int, std::uint64_t> dist;
    std::map<int, int> via;
    dag_longest(kRoot, live, a, dist, via);
    Longest out;
    if (!dist.count(kSink)) return out;
    out.clocks = dist[kSink];
    std::map<Arena::Key, std::uint64_t> times;
    std::vector<Arena::Key> order;
    std::set<int> loops;
    for (int e : chain_to(kSink, kRoot, via, a)) a.expand(e, 1, times, order, loops);
    for (const auto& k : order) out.nodes.push_back({k.first, times[k], k.second});
    out.loops.assign(loops.begin(), loops.end());
    return out;
}

} // namespace rcsim::bound
