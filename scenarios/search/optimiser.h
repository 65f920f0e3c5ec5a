// rcsim — the optimiser of a search (docs/search.md "How it searches"): a Latin-hypercube sample of
// the unit cube, then up to `starts` streams of an NLopt algorithm, each from one of the best sample
// points (or, for DIRECT-L, over its own slice of the first axis); as many streams as the budget
// gives each 8 (d + 1) runs, at least one. A stream whose points have all run before has
// converged: it goes on from the next best sample point it was dealt, until its runs are spent.
//
// NLopt calls its objective one point at a time, so each stream runs in a thread of its own whose
// objective waits for its answer; the streams advance in lockstep rounds, each round one batch of
// runs for the process pool. A stream's points depend only on its own answers, and the sample only
// on the seed: the same seed asks the same points in the same order whatever `--jobs` is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace rcsim::search {

enum class Direction { maximize, minimize };

struct Plan {
    std::string algorithm = "subplex"; // one of search_algorithms()
    std::size_t dims = 1;
    std::size_t runs = 1; // points to ask in all
    unsigned starts = 4;  // streams after the sample
    std::uint64_t seed = 1;
    Direction direction = Direction::maximize;
    /// Axes with no neighbourhood (the seed: seeds 7 and 8 are unrelated runs): the sample varies
    /// them, a stream keeps its start point's value, since a local step in them is a fresh draw.
    std::vector<bool> noise;
};

/// A point the optimiser asks for: coordinates in [0, 1] per axis; `stage` is "sample" or the
/// stream ("s1", "s2", ...).
struct Ask {
    std::vector<double> u;
    std::string stage;
};

/// The answer to one ask: the run's figure (none: it gave none), and whether it took a run (false:
/// the point had run before, its answer is that run's).
struct Answer {
    std::optional<double> figure;
    bool ran = true;
};

/// Evaluates one batch: one answer per ask. False: stop searching.
using Evaluate = std::function<bool(const std::vector<Ask>&, std::vector<Answer>&)>;

/// How many of `runs` points the sample takes: an eighth, at least one per start. A figure that is
/// the maximum of a run (a latency) is rugged: most of what a search finds it finds near a good
/// point (docs/search.md "How it searches" has the measurements behind the eighth).
std::size_t sample_size(std::size_t runs, unsigned starts);

/// An n-point Latin hypercube of [0, 1]^dims from `seed` (its own generator: the same points on
/// every platform): each axis cut into n equal cells, one point in each.
std::vector<std::vector<double>> latin_hypercube(std::size_t n, std::size_t dims, std::uint64_t seed);

/// Runs the plan, asking `evaluate` for every point. Returns false when it stopped the search.
bool optimise(const Plan& plan, const Evaluate& evaluate);

} // namespace rcsim::search
