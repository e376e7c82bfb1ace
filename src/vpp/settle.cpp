#include "vpp/settle.h"

#include <cmath>
#include <stdexcept>

namespace vpp {

Settling settle_cycles(const std::vector<CycleResult>& c, double tolerance) {
    if (!(tolerance > 0 && tolerance < 1)) throw std::invalid_argument("settle_cycles: tolerance must be in (0, 1)");
    Settling s;
    s.tolerance = tolerance;
    s.settled.assign(c.size(), false);
    // within[k]: cycle k follows cycle k-1 and its W is within the tolerance of it.
    std::vector<bool> within(c.size(), false);
    for (std::size_t k = 1; k < c.size(); ++k) {
        if (c[k].cycle != c[k - 1].cycle + 1 || !c[k].complete || !c[k - 1].complete) continue;
        const double prev = c[k - 1].W, now = c[k].W;
        within[k] = std::isfinite(prev) && std::isfinite(now) && std::abs(now - prev) <= tolerance * std::abs(prev);
    }
    double sum = 0;
    for (std::size_t k = 2; k < c.size(); ++k) {
        if (!(within[k] && within[k - 1])) continue;
        s.settled[k] = true;
        if (s.first == 0) s.first = c[k].cycle;
        ++s.count;
        sum += c[k].W;
    }
    if (s.count > 0) s.W_mean = sum / double(s.count);
    return s;
}

Settling mark_settled(std::vector<CycleResult>& cycles, double tolerance) {
    const Settling s = settle_cycles(cycles, tolerance);
    for (std::size_t k = 0; k < cycles.size(); ++k) {
        cycles[k].has_settled = true;
        cycles[k].settled = s.settled[k];
    }
    return s;
}

}  // namespace vpp
