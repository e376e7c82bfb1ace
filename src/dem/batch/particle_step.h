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

// The energy ledger's terms of one particle's step (dem/core/kernels.h, ParticleTerm): the work of
// each force over the back and forward half steps [J], then the kinetic energy [J].
struct ParticleEnergy {
    double back[5] = {}, fwd[5] = {}, kinetic = 0;
};

// One step of a free particle (inv_m > 0): f the gathered contact force [N], fx the external
// force [N] (zero when there is none: it is added all the same, as the SIMD kernel adds its zero
// vector), t the torque [N m]; m [kg], inv_m [1/kg], inv_i [1/(kg m^2)]; g [m/s^2], dt [s],
// lambda [-]. A particle with inv_m = 0 is left as it is. With kEnergy its terms go to *en (fp the
// pressure's force [N], r the radius [m]; all zero for a particle that is not free).
template <bool kEnergy = false>
VPPDEM_HD inline void advance_particle(ParticleState& s, const Vec3& f, const Vec3& fx, const Vec3& t, double m,
                                       double inv_m, double inv_i, const Vec3& g, double dt, double lambda,
                                       ParticleEnergy* en = nullptr, const Vec3& fp = Vec3{}, double r = 0.0) {
    if (!(inv_m > 0.0)) {
        if constexpr (kEnergy) *en = ParticleEnergy{};
        return;
    }
    const double half_dt = 0.5 * dt;
    const Vec3 fg{g.x * m, g.y * m, g.z * m};
    const Vec3 ftot = (f + fx) + fg;
    Vec3 acc = ftot * inv_m;
    acc.x = acc.x * damping_factor(acc.x * (s.v.x + half_dt * acc.x), lambda);
    acc.y = acc.y * damping_factor(acc.y * (s.v.y + half_dt * acc.y), lambda);
    acc.z = acc.z * damping_factor(acc.z * (s.v.z + half_dt * acc.z), lambda);
    const Vec3 v0 = s.v, w0 = s.w;
    const Vec3 v1 = v0 + acc * dt;
    s.x = s.x + v1 * dt;
    s.v = v1;
    Vec3 al = t * inv_i;
    al.x = al.x * damping_factor(al.x * w0.x, lambda);
    al.y = al.y * damping_factor(al.y * w0.y, lambda);
    al.z = al.z * damping_factor(al.z * w0.z, lambda);
    s.w = w0 + al * dt;
    if constexpr (kEnergy) {
        // As the SIMD kernel (advance_body): trapezoid halves of each force's work.
        const double h = half_dt;
        const Vec3 w1 = s.w;
        const double inertia = inv_i > 0.0 ? 0.4 * m * r * r : 0.0;
        *en = ParticleEnergy{};
        en->back[2] = dot(fg, v0) * h;  // gravity
        en->fwd[2] = dot(fg, v1) * h;
        en->back[1] = dot(fp, v0) * h;  // pressure
        en->fwd[1] = dot(fp, v1) * h;
        en->back[3] = dot(fx, v0) * h;  // external
        en->fwd[3] = dot(fx, v1) * h;
        en->kinetic = 0.5 * m * dot(v0, v1) + 0.5 * inertia * dot(w0, w1);
        if (lambda != 0.0) {  // the damping force and torque the integrator removed: F - m a, T - I alpha
            const Vec3 df = ftot - acc * m;
            const Vec3 dq = inertia > 0.0 ? t - al * inertia : Vec3{};
            en->back[4] = (dot(df, v0) + dot(dq, w0)) * h;
            en->fwd[4] = (dot(df, v1) + dot(dq, w1)) * h;
        }
    }
}

}  // namespace dem::batch
