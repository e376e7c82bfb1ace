// The batch engine's per-particle kernel body (docs/gpu.md): one free particle's leapfrog step
// with Yade's local damping, written once for the host backend and the CUDA kernels. It is the
// arithmetic of World's SIMD kernel (dem/core/kernels.cpp, advance_body) in the same order:
// total force (contact + external) + gravity, cundallDamp2nd on the translation, cundallDamp1st
// on the rotation, then v and x, so that a batch gives World's bits (tests/unit/test_batch.cpp).
#pragma once

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem::batch {

// 1 - lambda sign(x), sign(0) = 0: the kernels' damping_factor.
VPPDEM_HD inline double damping_factor(double x, double lambda) {
    const double sgn = x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0);
    return 1.0 - lambda * sgn;
}

struct ParticleState {
    Vec3 x, v, w;  // [m], [m/s] and [rad/s] at t - dt/2 (v, w)
};

// One step of a free particle (inv_m > 0): f the gathered contact force [N], fx the external
// force [N] (zero when there is none: it is added all the same, as the SIMD kernel adds its zero
// vector), t the torque [N m]; m [kg], inv_m [1/kg], inv_i [1/(kg m^2)]; g [m/s^2], dt [s],
// lambda [-]. A particle with inv_m = 0 is left as it is.
VPPDEM_HD inline void advance_particle(ParticleState& s, const Vec3& f, const Vec3& fx, const Vec3& t, double m,
                                       double inv_m, double inv_i, const Vec3& g, double dt, double lambda) {
    if (!(inv_m > 0.0)) return;
    const double half_dt = 0.5 * dt;
    const Vec3 fg{g.x * m, g.y * m, g.z * m};
    const Vec3 ftot = (f + fx) + fg;
    Vec3 acc = ftot * inv_m;
    acc.x = acc.x * damping_factor(acc.x * (s.v.x + half_dt * acc.x), lambda);
    acc.y = acc.y * damping_factor(acc.y * (s.v.y + half_dt * acc.y), lambda);
    acc.z = acc.z * damping_factor(acc.z * (s.v.z + half_dt * acc.z), lambda);
    const Vec3 v1 = s.v + acc * dt;
    s.x = s.x + v1 * dt;
    s.v = v1;
    Vec3 al = t * inv_i;
    al.x = al.x * damping_factor(al.x * s.w.x, lambda);
    al.y = al.y * damping_factor(al.y * s.w.y, lambda);
    al.z = al.z * damping_factor(al.z * s.w.z, lambda);
    s.w = s.w + al * dt;
}

}  // namespace dem::batch
