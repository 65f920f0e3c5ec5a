// rcsim — the check on the static bound. See bound_check.h.
#include "scenarios/verdict/bound_check.h"

#include <iomanip>
#include <sstream>

namespace rcsim {

namespace {
std::string us1(double v) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << v << " us";
    return os.str();
}
} // namespace

Check bound_service_check(const std::vector<BoundFigure>& sources, const Figure& budget) {
    const BoundFigure* worst = nullptr;
    for (const BoundFigure& b : sources)
        if (!worst || b.blocking_us > worst->blocking_us) worst = &b;
    const Figure figure = !budget.value ? budget
                          : worst       ? Figure::of(worst->blocking_us)
                                        : Figure::none("the firmware installs no interrupt source");
    Check c = Check::at_most("bound_service_us", figure, budget.value.value_or(0));
    nlohmann::json detail = nlohmann::json::object();
    for (const BoundFigure& b : sources)
        detail[b.source] = {{"bound_blocking_us", b.blocking_us}, {"handler", b.handler}};
    if (!detail.empty()) c.detail = detail;
    if (c.status != Check::Status::failed) return c;
    // Sources in the order given (IR0 first): the first over the budget is the one named.
    for (const BoundFigure& b : sources)
        if (b.blocking_us > *budget.value) {
            c.why = b.source + ": the bound of its blocking time, " + us1(b.blocking_us) + ", is over the " +
                    us1(*budget.value) + " budget on a path of " + b.handler + (b.path.empty() ? "" : ": " + b.path);
            break;
        }
    return c;
}

} // namespace rcsim
