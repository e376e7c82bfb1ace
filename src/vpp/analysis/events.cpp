#include "vpp/analysis/events.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace vpp {

namespace {

// The median of the values (the mean of the two middle ones for an even count).
double median(std::vector<double> v) {
    const std::size_t n = v.size(), h = n / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(h), v.end());
    if (n % 2) return v[h];
    const double upper = v[h];
    return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(h)));
}

}  // namespace

EventSplit split_events(const EventSeries& s, double threshold) {
    if (!(threshold > 1.0))
        throw std::invalid_argument("split_events: threshold " + std::to_string(threshold) +
                                    " must exceed 1 (a burst is kinetic energy above threshold times the median)");
    const std::size_t n = s.kinetic.size();
    if (s.friction.size() != n || s.damping.size() != n || s.viscous.size() != n)
        throw std::invalid_argument("split_events: the columns have different lengths");
    EventSplit out;
    if (n < 2) return out;
    out.baseline = median(s.kinetic);
    const double limit = threshold * out.baseline;
    bool previous = false;  // the previous interval was in an event
    int in_events = 0;
    for (std::size_t k = 0; k + 1 < n; ++k) {
        const bool hot = s.kinetic[k] > limit || s.kinetic[k + 1] > limit;
        if (hot) {
            out.friction += s.friction[k + 1] - s.friction[k];
            out.damping += s.damping[k + 1] - s.damping[k];
            out.viscous += s.viscous[k + 1] - s.viscous[k];
            ++in_events;
            if (!previous) ++out.events;
        }
        previous = hot;
    }
    out.event_fraction = double(in_events) / double(n - 1);
    out.friction_total = s.friction[n - 1] - s.friction[0];
    out.damping_total = s.damping[n - 1] - s.damping[0];
    out.viscous_total = s.viscous[n - 1] - s.viscous[0];
    return out;
}

}  // namespace vpp
