#include "models/stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rcsim {

namespace {
double nearest_rank(const std::vector<double>& sorted, double pct) {
    const auto n = sorted.size();
    auto rank = static_cast<std::size_t>(std::ceil(pct / 100.0 * static_cast<double>(n)));
    rank = std::clamp<std::size_t>(rank, 1, n);
    return sorted[rank - 1];
}
} // namespace

Summary Samples::summary() const {
    Summary s;
    s.count = values_.size();
    if (values_.empty()) return s;
    std::vector<double> v = values_;
    std::sort(v.begin(), v.end());
    s.min = v.front();
    s.max = v.back();
    s.mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    s.p50 = nearest_rank(v, 50);
    s.p99 = nearest_rank(v, 99);
    return s;
}

nlohmann::json to_json(const Summary& s) {
    return {{"count", s.count}, {"min", s.min}, {"mean", s.mean},
            {"p50", s.p50},     {"p99", s.p99}, {"max", s.max}};
}

} // namespace rcsim
