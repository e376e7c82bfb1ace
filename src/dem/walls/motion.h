// Prescribed rigid translation of a boundary (or of a group of particles).
// A motion is either a constant velocity or a piecewise-linear displacement history
// d(t) given as samples (t_k, d_k); outside the samples the end values are held.
#pragma once

#include <algorithm>
#include <vector>

#include "dem/core/vec3.h"

namespace dem {

struct DisplacementSample {
    double time = 0.0;   // [s]
    Vec3 displacement;   // [m] from the reference position
};

struct Motion {
    Vec3 velocity;                          // [m/s] constant part, used when history is empty
    std::vector<DisplacementSample> history;  // [s, m] sorted by time; overrides velocity

    bool is_static() const { return history.empty() && velocity == Vec3{}; }

    // Displacement from the reference position at time t [s].
    Vec3 displacement(double t) const {
        if (history.empty()) return velocity * t;
        if (t <= history.front().time) return history.front().displacement;
        if (t >= history.back().time) return history.back().displacement;
        auto it = std::upper_bound(history.begin(), history.end(), t,
                                   [](double v, const DisplacementSample& s) { return v < s.time; });
        const auto& b = *it;
        const auto& a = *(it - 1);
        const double s = (t - a.time) / (b.time - a.time);
        return a.displacement + (b.displacement - a.displacement) * s;
    }

    // Mean velocity over [t0, t1] [m/s]: exact for piecewise-linear histories when the
    // interval lies inside one segment, and what a leapfrog step needs in any case.
    Vec3 mean_velocity(double t0, double t1) const {
        if (history.empty()) return velocity;
        return (displacement(t1) - displacement(t0)) / (t1 - t0);
    }
};

}  // namespace dem
