// rcsim — statistics for reports: sample sets summarised as {count, min, mean, p50, p99, max}.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace rcsim {

struct Summary {
    std::size_t count = 0;
    double min = 0, mean = 0, p50 = 0, p99 = 0, max = 0;
};

/// A sample set in bounded memory: its distinct values with their counts, sorted.
///
/// Why the summary is exact. min, max and the nearest-rank percentiles depend only on the order
/// of the samples and on how often each value occurs, which the sorted (value, count) list holds;
/// the mean sums the values in ascending order, each as often as it occurs, which is the sum of
/// the sorted sample array term by term. So while the list holds the samples themselves, the
/// summary is the one of keeping every sample, to the last bit.
///
/// Why the memory is bounded. The samples of a run are differences of simulated times, and most
/// are whole numbers of CPU clocks (every service time is: both ends are bus-cycle edges), so they
/// repeat: a span S holds at most S / resolution + 1 of them (a 2 ms span at 125 ns is 16 001
/// values). Samples that are not on the clock grid (a latency from an IR line that rose between
/// two CPU clocks) are kept exactly too until the list holds `capacity` distinct values. Past
/// that the list is coarsened: every value, kept and to come, is rounded to the nearest multiple
/// of `resolution`. From then on a value on the grid is still exact, every other one is within
/// resolution / 2, and so are min/p50/p99/max (rounding keeps the order, so the k-th smallest of
/// the rounded values is the rounded k-th smallest; p50 and p99 are clamped into [min, max]);
/// min and max stay exact and the mean stays exact to rounding (both kept apart, the mean as a
/// compensated running sum), and the list holds at most (max - min) / resolution + 1 values.
/// `exact()` tells which case a summary is in.
class Samples {
public:
    /// One clock of the 8 MHz comm CPU in microseconds, the unit of every sample set in rcsim.
    static constexpr double kDefaultResolution = 0.125;
    static constexpr std::size_t kDefaultCapacity = std::size_t{1} << 13;

    explicit Samples(double resolution = kDefaultResolution, std::size_t capacity = kDefaultCapacity);

    void add(double v);
    std::size_t count() const { return count_; }
    bool empty() const { return count_ == 0; }
    /// Percentiles by the nearest-rank method on the sorted samples.
    Summary summary() const;
    void clear();

    /// False once the list was coarsened to `resolution` (see the class comment).
    bool exact() const { return exact_; }
    double resolution() const { return resolution_; }
    /// The distinct kept values with their counts, ascending.
    const std::vector<std::pair<double, std::uint64_t>>& values() const;
    /// How many samples exceed `limit` (of the kept values: once coarsened, each as rounded).
    std::uint64_t count_above(double limit) const;

private:
    double resolution_;
    std::size_t capacity_;
    std::size_t count_ = 0;
    double min_ = 0, max_ = 0;
    double sum_ = 0, sum_error_ = 0; // Neumaier's compensated sum: the mean once coarsened
    // Sorted distinct values; new samples wait in `pending_` and are merged in batches, so that an
    // add is amortised O(log n) and not a shift of the whole list. The list is coarsened exactly
    // when the samples so far have more than `capacity` distinct values, whenever that is noticed
    // (distinct values only grow, and coarsening rounds every value, kept or pending), so the
    // state is a function of the samples alone and a const summary() may merge: hence mutable.
    mutable std::vector<std::pair<double, std::uint64_t>> values_;
    mutable std::vector<double> pending_;
    mutable bool exact_ = true;

    double rounded(double v) const;
    void merge() const;
};

nlohmann::json to_json(const Summary& s);

} // namespace rcsim
