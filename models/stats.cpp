#include "models/stats.h"

#include <algorithm>
#include <cmath>

namespace rcsim {

namespace {
// Pending samples are merged once there are this many, or as many as kept values: each merge
// costs O(kept + pending), so an add costs O(log n) amortised.
constexpr std::size_t kMinBatch = 1024;
} // namespace

Samples::Samples(double resolution, std::size_t capacity)
    : resolution_(resolution > 0 ? resolution : kDefaultResolution), capacity_(std::max<std::size_t>(capacity, 1)) {}

double Samples::rounded(double v) const { return std::nearbyint(v / resolution_) * resolution_; }

void Samples::add(double v) {
    if (count_ == 0 || v < min_) min_ = v;
    if (count_ == 0 || v > max_) max_ = v;
    ++count_;
    // Neumaier: the rounding error of each addition is carried apart, whichever term is larger.
    const double t = sum_ + v;
    sum_error_ += std::fabs(sum_) >= std::fabs(v) ? (sum_ - t) + v : (v - t) + sum_;
    sum_ = t;
    pending_.push_back(exact_ ? v : rounded(v));
    if (pending_.size() >= std::max(kMinBatch, values_.size())) merge();
}

void Samples::merge() const {
    if (pending_.empty()) return;
    std::sort(pending_.begin(), pending_.end());
    std::vector<std::pair<double, std::uint64_t>> merged;
    merged.reserve(values_.size() + pending_.size());
    auto put = [&merged](double v, std::uint64_t n) {
        if (!merged.empty() && merged.back().first == v) merged.back().second += n;
        else merged.emplace_back(v, n);
    };
    std::size_t i = 0;
    for (const auto& [v, n] : values_) {
        for (; i < pending_.size() && pending_[i] < v; ++i) put(pending_[i], 1);
        put(v, n);
    }
    for (; i < pending_.size(); ++i) put(pending_[i], 1);
    pending_.clear();
    values_.swap(merged);
    if (exact_ && values_.size() > capacity_) {
        // Too many distinct values: round every one to the grid. Rounding is monotone, so the
        // list stays sorted; equal neighbours fold into one.
        exact_ = false;
        std::vector<std::pair<double, std::uint64_t>> coarse;
        for (const auto& [v, n] : values_) {
            const double r = rounded(v);
            if (!coarse.empty() && coarse.back().first == r) coarse.back().second += n;
            else coarse.emplace_back(r, n);
        }
        values_.swap(coarse);
    }
    // Keep the capacity of the batch for the next one, but give back a list that shrank a lot.
    if (values_.capacity() > 2 * values_.size() + kMinBatch) values_.shrink_to_fit();
}

const std::vector<std::pair<double, std::uint64_t>>& Samples::values() const {
    merge();
    return values_;
}

std::uint64_t Samples::count_above(double limit) const {
    const auto& v = values();
    const auto first = std::upper_bound(v.begin(), v.end(), limit,
                                        [](double l, const std::pair<double, std::uint64_t>& e) { return l < e.first; });
    std::uint64_t n = 0;
    for (auto it = first; it != v.end(); ++it) n += it->second;
    return n;
}

Summary Samples::summary() const {
    Summary s;
    s.count = count_;
    if (count_ == 0) return s;
    merge();
    s.min = min_;
    s.max = max_;
    // Nearest rank: the ceil(pct/100 * n)-th smallest sample (1-based).
    auto rank_of = [this](double pct) {
        auto rank = static_cast<std::size_t>(std::ceil(pct / 100.0 * static_cast<double>(count_)));
        return std::clamp<std::size_t>(rank, 1, count_);
    };
    const std::size_t r50 = rank_of(50), r99 = rank_of(99);
    double sorted_sum = 0;
    std::size_t seen = 0;
    for (const auto& [v, n] : values_) {
        if (seen < r50 && r50 <= seen + n) s.p50 = v;
        if (seen < r99 && r99 <= seen + n) s.p99 = v;
        seen += n;
        // The sum of the sorted samples, term by term (the mean of an exact list, to the bit).
        if (exact_)
            for (std::uint64_t k = 0; k < n; ++k) sorted_sum += v;
    }
    s.mean = (exact_ ? sorted_sum : sum_ + sum_error_) / static_cast<double>(count_);
    if (!exact_) {
        s.p50 = std::clamp(s.p50, min_, max_);
        s.p99 = std::clamp(s.p99, min_, max_);
    }
    return s;
}

void Samples::clear() {
    *this = Samples(resolution_, capacity_);
}

nlohmann::json to_json(const Summary& s) {
    return {{"count", s.count}, {"min", s.min}, {"mean", s.mean},
            {"p50", s.p50},     {"p99", s.p99}, {"max", s.max}};
}

} // namespace rcsim
