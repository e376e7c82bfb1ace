#include "vpp/analysis/settle.h"

#include <cmath>
#include <stdexcept>

namespace vpp {

namespace {

struct Line {
    double mean = 0, slope = 0, sxx = 0;
};

// Mean of W and least-squares slope of W against the cycle number over c[a..b] (inclusive).
Line fit(const std::vector<CycleResult>& c, std::size_t a, std::size_t b) {
    const double n = double(b - a + 1);
    double kbar = 0, wbar = 0;
    for (std::size_t i = a; i <= b; ++i) kbar += c[i].cycle, wbar += c[i].W;
    kbar /= n, wbar /= n;
    Line l;
    l.mean = wbar;
    double sxy = 0;
    for (std::size_t i = a; i <= b; ++i) {
        const double dk = c[i].cycle - kbar;
        l.sxx += dk * dk;
        sxy += dk * (c[i].W - wbar);
    }
    l.slope = l.sxx > 0 ? sxy / l.sxx : 0.0;
    return l;
}

}  // namespace

Settling settle_cycles(const std::vector<CycleResult>& c, double tolerance) {
    if (!(tolerance > 0 && tolerance < 1)) throw std::invalid_argument("settle_cycles: tolerance must be in (0, 1)");
    Settling s;
    s.tolerance = tolerance;
    s.settled.assign(c.size(), false);
    // The tail ends at the last complete cycle with a finite W.
    std::size_t last = c.size();
    for (std::size_t k = c.size(); k-- > 0;)
        if (c[k].complete && std::isfinite(c[k].W)) {
            last = k;
            break;
        }
    if (last == c.size()) return s;
    std::size_t first = last;
    double sum = c[last].W;  // of c[first..last]
    while (first > 0) {
        const std::size_t a = first - 1;
        const CycleResult& ca = c[a];
        if (!ca.complete || !std::isfinite(ca.W) || ca.cycle + 1 != c[first].cycle) break;
        const double n_after = double(last - first + 1);
        const double m_after = sum / n_after;
        const bool level = std::abs(ca.W - m_after) <=
                           kSettleZ * tolerance * std::abs(m_after) * std::sqrt(1.0 + 1.0 / n_after);
        if (!level) break;
        if (last - a + 1 >= kSettleMinCycles) {
            const Line l = fit(c, a, last);
            if (std::abs(l.slope) > kSettleZ * tolerance * std::abs(l.mean) / std::sqrt(l.sxx)) break;
        }
        first = a;
        sum += ca.W;
    }
    s.tail_first = c[first].cycle;
    s.tail_last = c[last].cycle;
    if (last - first + 1 < kSettleMinCycles) return s;
    const Line l = fit(c, first, last);
    s.first = c[first].cycle;
    s.count = last - first + 1;
    s.W_mean = l.mean;
    s.slope = l.slope;
    s.slope_limit = kSettleZ * tolerance * std::abs(l.mean) / std::sqrt(l.sxx);
    for (std::size_t k = first; k <= last; ++k) s.settled[k] = true;
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
