#include "scenarios/search/optimiser.h"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

namespace rcsim::search {

namespace {

/// Evaluations a stream wants per vertex of its simplex (see optimise()).
constexpr std::size_t kEvalsPerVertex = 8;

/// Stands for "no figure" to NLopt: worse than any figure a run reports.
constexpr double kNoFigure = 1e300;

nlopt_algorithm nlopt_of(const std::string& name) {
    if (name == "subplex") return NLOPT_LN_SBPLX;
    if (name == "neldermead") return NLOPT_LN_NELDERMEAD;
    if (name == "cobyla") return NLOPT_LN_COBYLA;
    if (name == "direct-l") return NLOPT_GN_DIRECT_L;
    if (name == "crs2") return NLOPT_GN_CRS2_LM;
    throw std::invalid_argument("unknown search algorithm '" + name + "'");
}

/// Uniform in [0, 1) from the generator's top 53 bits (std::uniform_real_distribution's output
/// is the library's choice; this is the same everywhere).
double unit(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }

/// One NLopt stream: its thread, its budget and its side of the handshake with the rounds.
struct Stream {
    std::string name;
    std::vector<std::vector<double>> starts; // whole points, best first: a converged start gives way to the next
    std::vector<double> point;               // the current start: the noise axes keep its values
    std::vector<std::size_t> free;           // the axes the stream moves
    std::vector<double> lo, hi;              // over the free axes
    std::size_t budget = 0, spent = 0;       // runs (answers from an earlier run are free)
    std::size_t repeats = 0;                 // answers in a row from earlier runs: converged
    std::uint64_t seed = 0;
    // The handshake (under Rounds::m).
    bool waiting = false, done = false, answered = false, ran = false;
    std::vector<double> ask;
    double answer = 0;
};

/// The lockstep rounds: every live stream posts one point, the batch is evaluated, each gets its answer.
struct Rounds {
    std::mutex m;
    std::condition_variable cv;
    bool stop = false;
    Direction direction = Direction::maximize;
    nlopt_algorithm algorithm = NLOPT_LN_SBPLX;
    double step = 0.1;
};

struct Context {
    Rounds* rounds;
    Stream* stream;
    nlopt_opt opt;
};

double objective(unsigned n, const double* x, double*, void* data) {
    auto* c = static_cast<Context*>(data);
    std::unique_lock<std::mutex> lock(c->rounds->m);
    Stream& s = *c->stream;
    // The budget is in runs, ours to keep whatever NLopt counts; a start whose points all ran
    // before has converged and gives way to the next.
    if (c->rounds->stop || s.spent >= s.budget || s.repeats >= 2 * (n + 1)) {
        nlopt_force_stop(c->opt);
        return c->rounds->direction == Direction::maximize ? -kNoFigure : kNoFigure;
    }
    s.ask = s.point;
    for (unsigned i = 0; i < n; ++i) s.ask[s.free[i]] = x[i];
    s.waiting = true;
    s.answered = false;
    c->rounds->cv.notify_all();
    c->rounds->cv.wait(lock, [&] { return s.answered || c->rounds->stop; });
    if (!s.answered) nlopt_force_stop(c->opt);
    s.spent += s.ran ? 1 : 0;
    s.repeats = s.ran ? 0 : s.repeats + 1;
    return s.answer;
}

/// One NLopt run of stream `s` from its current start `x`, until it converges, its budget is
/// spent or the search stops.
void optimise_from(Rounds& r, Stream& s, std::vector<double> x) {
    const std::size_t dims = s.free.size();
    nlopt_opt opt = nlopt_create(r.algorithm, static_cast<unsigned>(dims));
    Context c{&r, &s, opt};
    nlopt_set_lower_bounds(opt, s.lo.data());
    nlopt_set_upper_bounds(opt, s.hi.data());
    if (r.direction == Direction::maximize) nlopt_set_max_objective(opt, objective, &c);
    else nlopt_set_min_objective(opt, objective, &c);
    nlopt_set_xtol_abs1(opt, 1e-9); // run on: a figure's edge may be narrow (objective() ends it)
    nlopt_set_initial_step1(opt, r.step);
    if (r.algorithm == NLOPT_GN_CRS2_LM) {
        nlopt_srand(s.seed); // NLopt's generator is per thread
        const std::size_t population = std::min<std::size_t>(s.budget / 2, 10 * (dims + 1));
        nlopt_set_population(opt, static_cast<unsigned>(std::max<std::size_t>(dims + 2, population)));
    }
    double f = 0;
    nlopt_optimize(opt, x.data(), &f);
    nlopt_destroy(opt);
}

void run_stream(Rounds& r, Stream& s) {
    for (const std::vector<double>& start : s.starts) {
        std::vector<double> x;
        {
            std::lock_guard<std::mutex> lock(r.m);
            if (r.stop || s.spent >= s.budget) break;
            s.point = start;
            s.repeats = 0;
        }
        for (std::size_t i = 0; i < s.free.size(); ++i) x.push_back(std::clamp(start[s.free[i]], s.lo[i], s.hi[i]));
        optimise_from(r, s, x);
    }
    std::lock_guard<std::mutex> lock(r.m);
    s.done = true;
    s.waiting = false;
    r.cv.notify_all();
}

/// Asks the streams' points round by round until every stream is done; false when stopped.
bool drive(Rounds& r, std::vector<Stream>& streams, const Evaluate& evaluate) {
    for (;;) {
        std::vector<Stream*> batch;
        std::vector<Ask> asks;
        {
            std::unique_lock<std::mutex> lock(r.m);
            r.cv.wait(lock, [&] {
                return std::all_of(streams.begin(), streams.end(), [](const Stream& s) { return s.done || s.waiting; });
            });
            for (Stream& s : streams)
                if (s.waiting) {
                    batch.push_back(&s);
                    asks.push_back({s.ask, s.name});
                }
        }
        if (batch.empty()) return true;
        std::vector<Answer> answers(asks.size());
        const bool go_on = evaluate(asks, answers);
        std::lock_guard<std::mutex> lock(r.m);
        for (std::size_t i = 0; i < batch.size(); ++i) {
            const double none = r.direction == Direction::maximize ? -kNoFigure : kNoFigure;
            batch[i]->answer = answers[i].figure ? *answers[i].figure : none;
            batch[i]->ran = answers[i].ran;
            batch[i]->answered = go_on;
            batch[i]->waiting = false;
        }
        if (!go_on) r.stop = true;
        r.cv.notify_all();
        if (!go_on) return false;
    }
}

/// The streams after the sample (`asks`, `order`: best first) with their budgets and starts.
std::vector<Stream> deal_streams(const Plan& plan, const std::vector<Ask>& asks, const std::vector<std::size_t>& order,
                                 const Rounds& r) {
    const std::size_t n0 = asks.size();
    const unsigned starts = std::max(1u, plan.starts);
    // A stream needs room to refine: about eight evaluations per simplex vertex (d + 1) for a
    // local method to halve its step several times. Fewer, longer streams when the budget is short.
    std::vector<std::size_t> free;
    for (std::size_t d = 0; d < plan.dims; ++d)
        if (d >= plan.noise.size() || !plan.noise[d]) free.push_back(d);
    const std::size_t left = plan.runs - n0;
    const std::size_t room = left / (kEvalsPerVertex * (free.size() + 1));
    const std::size_t count = free.empty() ? 0 : std::min<std::size_t>(left, std::clamp<std::size_t>(room, 1, starts));
    if (count == 0) return {};
    std::vector<Stream> streams(count);
    const bool slices = r.algorithm == NLOPT_GN_DIRECT_L;
    for (std::size_t k = 0; k < count; ++k) {
        Stream& s = streams[k];
        s.name = "s" + std::to_string(k + 1);
        s.budget = left / count + (k < left % count ? 1 : 0);
        s.seed = plan.seed * 1000 + k + 1;
        s.free = free;
        s.lo.assign(free.size(), 0.0);
        s.hi.assign(free.size(), 1.0);
        if (slices) { // DIRECT-L starts from its box's centre: each stream gets a slice of the first axis
            s.lo[0] = static_cast<double>(k) / static_cast<double>(count);
            s.hi[0] = static_cast<double>(k + 1) / static_cast<double>(count);
            std::vector<double> centre = asks[order[0]].u;
            centre[free[0]] = (s.lo[0] + s.hi[0]) / 2;
            s.starts.push_back(centre); // DIRECT-L is global in its slice: one start
        } else {
            for (std::size_t j = k; j < n0; j += count) s.starts.push_back(asks[order[j]].u);
        }
    }
    return streams;
}

} // namespace

std::size_t sample_size(std::size_t runs, unsigned starts) {
    const std::size_t eighth = (runs + 7) / 8;
    return std::min(runs, std::max<std::size_t>(eighth, starts));
}

std::vector<std::vector<double>> latin_hypercube(std::size_t n, std::size_t dims, std::uint64_t seed) {
    std::mt19937_64 g(seed);
    std::vector<std::vector<double>> points(n, std::vector<double>(dims));
    for (std::size_t d = 0; d < dims; ++d) {
        std::vector<std::size_t> cell(n);
        for (std::size_t i = 0; i < n; ++i) cell[i] = i;
        for (std::size_t i = n; i > 1; --i) std::swap(cell[i - 1], cell[g() % i]); // Fisher-Yates
        for (std::size_t i = 0; i < n; ++i) points[i][d] = (static_cast<double>(cell[i]) + unit(g)) / static_cast<double>(n);
    }
    return points;
}

bool optimise(const Plan& plan, const Evaluate& evaluate) {
    Rounds r;
    r.direction = plan.direction;
    r.algorithm = nlopt_of(plan.algorithm);
    const unsigned starts = std::max(1u, plan.starts);
    // With only noise axes (the seed alone) no stream can move: the sample is the whole search.
    const bool all_noise = plan.noise.size() >= plan.dims &&
                           std::all_of(plan.noise.begin(), plan.noise.begin() + static_cast<std::ptrdiff_t>(plan.dims),
                                       [](bool n) { return n; });
    const std::size_t n0 = all_noise ? plan.runs : sample_size(plan.runs, starts);
    // The sample: one batch.
    std::vector<Ask> asks;
    for (auto& u : latin_hypercube(n0, plan.dims, plan.seed)) asks.push_back({std::move(u), "sample"});
    std::vector<Answer> values(asks.size());
    if (!evaluate(asks, values)) return false;
    // The streams start from the best sample points, best first (ties: the earlier point).
    std::vector<std::size_t> order(n0);
    for (std::size_t i = 0; i < n0; ++i) order[i] = i;
    const bool up = plan.direction == Direction::maximize;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const auto& fa = values[a].figure;
        const auto& fb = values[b].figure;
        if (!fb) return static_cast<bool>(fa);
        if (!fa) return false;
        return up ? *fa > *fb : *fa < *fb;
    });
    r.step = 0.5 / static_cast<double>(n0); // about the sample's spacing: a stream refines its point
    std::vector<Stream> streams = deal_streams(plan, asks, order, r);
    if (streams.empty()) return true;
    std::vector<std::thread> threads;
    for (Stream& s : streams) threads.emplace_back(run_stream, std::ref(r), std::ref(s));
    auto join = [&] {
        {
            std::lock_guard<std::mutex> lock(r.m);
            r.stop = r.stop || std::any_of(streams.begin(), streams.end(), [](const Stream& s) { return !s.done; });
        }
        r.cv.notify_all();
        for (auto& t : threads) t.join();
    };
    try {
        const bool finished = drive(r, streams, evaluate);
        join();
        return finished;
    } catch (...) { // a run the loader refused, say: the streams must end before the error goes up
        join();
        throw;
    }
}

} // namespace rcsim::search
