// rcsim — statistics for reports: sample sets summarised as {count, min, mean, p50, p99, max}.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <vector>

namespace rcsim {

struct Summary {
    std::size_t count = 0;
    double min = 0, mean = 0, p50 = 0, p99 = 0, max = 0;
};

/// Keeps every sample (reports need exact percentiles; a 2 s run has at most a few 10^4 samples).
class Samples {
public:
    void add(double v) { values_.push_back(v); }
    std::size_t count() const { return values_.size(); }
    bool empty() const { return values_.empty(); }
    /// Percentiles by the nearest-rank method on the sorted samples.
    Summary summary() const;
    void clear() { values_.clear(); }

private:
    std::vector<double> values_;
};

nlohmann::json to_json(const Summary& s);

} // namespace rcsim
