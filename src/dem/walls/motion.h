// Prescribed rigid translation of a boundary (or of a group of particles).
// A motion is either a constant velocity or a piecewise-linear displacement history
// d(t) given as samples (t_k, d_k); outside the samples the end values are held.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem {

struct DisplacementSample {
    double time = 0.0;   // [s]
    Vec3 displacement;   // [m] from the reference position
};

// A motion as plain data (the batch engine's device keeps its walls' and prescribed particles'
// motions so): the constant velocity [m/s], or n samples (t_k, d_k) at `history`. The functions
// below are Motion's arithmetic, written once for World and the device.
struct MotionView {
    Vec3 velocity;                                 // [m/s]
    const DisplacementSample* history = nullptr;  // sorted by time; n == 0: the constant velocity
    uint32_t n = 0;
};

// Displacement from the reference position at time t [s] [m]: the samples linearly
// interpolated (the end values held outside them), or velocity * t.
VPPDEM_HD inline Vec3 motion_displacement(const MotionView& m, double t) {
    if (m.n == 0) return m.velocity * t;
    const DisplacementSample* h = m.history;
    if (t <= h[0].time) return h[0].displacement;
    if (t >= h[m.n - 1].time) return h[m.n - 1].displacement;
    // The first sample later than t (std::upper_bound): lo <= t < hi holds throughout.
    uint32_t lo = 0, hi = m.n - 1;
    while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (t < h[mid].time) hi = mid;
        else lo = mid;
    }
    const DisplacementSample& a = h[hi - 1];
    const DisplacementSample& b = h[hi];
    const double s = (t - a.time) / (b.time - a.time);
    return a.displacement + (b.displacement - a.displacement) * s;
}

// Mean velocity over [t0, t1] [m/s]: exact for piecewise-linear histories when the interval lies
// inside one segment, and what a leapfrog step needs in any case.
VPPDEM_HD inline Vec3 motion_mean_velocity(const MotionView& m, double t0, double t1) {
    if (m.n == 0) return m.velocity;
    return (motion_displacement(m, t1) - motion_displacement(m, t0)) / (t1 - t0);
}

// A prescribed particle after a step of dt [s] from `time` [s] (World's prescribed motions, the
// batch engine's device's): at its reference position ref [m] plus the displacement at time + dt,
// moving at the mean velocity over the step [m/s].
struct Placement {
    Vec3 pos, vel;  // [m], [m/s]
};
VPPDEM_HD inline Placement placement_after_step(const MotionView& m, const Vec3& ref, double time, double dt) {
    const double t1 = time + dt;
    return {ref + motion_displacement(m, t1), motion_mean_velocity(m, time, t1)};
}

struct Motion {
    Vec3 velocity;                          // [m/s] constant part, used when history is empty
    std::vector<DisplacementSample> history;  // [s, m] sorted by time; overrides velocity

    bool is_static() const { return history.empty() && velocity == Vec3{}; }

    MotionView view() const { return {velocity, history.data(), uint32_t(history.size())}; }
    // Displacement from the reference position at time t [s] (motion_displacement).
    Vec3 displacement(double t) const { return motion_displacement(view(), t); }
    // Mean velocity over [t0, t1] [m/s] (motion_mean_velocity).
    Vec3 mean_velocity(double t0, double t1) const { return motion_mean_velocity(view(), t0, t1); }
};

}  // namespace dem
