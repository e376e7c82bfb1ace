// Leapfrog (velocity Verlet in half-step form) with Yade's non-viscous local damping.
#pragma once

#include "dem/core/vec3.h"
#include "dem/core/hd.h"

namespace dem {

VPPDEM_HD inline double sign(double v) { return double((v > 0.0) - (v < 0.0)); }

// Translational acceleration after Yade's NewtonIntegrator::cundallDamp2nd: each component
// is scaled by (1 - lambda sign(a_k v_k(t))), with v(t) estimated as v(t-dt/2) + dt/2 a.
// Equivalent to F_k - lambda sign(v_k) |F_k| with gravity included in F.
VPPDEM_HD inline Vec3 damped_acceleration(const Vec3& f, double inv_mass, const Vec3& v_half, double dt,
                                double lambda) {
    Vec3 a = f * inv_mass;
    if (lambda != 0.0)
        for (int k = 0; k < 3; ++k) a[k] *= 1.0 - lambda * sign(a[k] * (v_half[k] + 0.5 * dt * a[k]));
    return a;
}

// Angular acceleration after Yade's cundallDamp1st (sign of torque times angular velocity).
VPPDEM_HD inline Vec3 damped_angular_acceleration(const Vec3& t, double inv_inertia, const Vec3& w_half,
                                        double lambda) {
    Vec3 a = t * inv_inertia;
    if (lambda != 0.0)
        for (int k = 0; k < 3; ++k) a[k] *= 1.0 - lambda * sign(a[k] * w_half[k]);
    return a;
}

}  // namespace dem
