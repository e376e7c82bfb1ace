// The batch engine's per-particle kernel body (docs/gpu.md) for the host backend and the CUDA
// kernels: one free particle's leapfrog step with Yade's local damping, on doubles, through the
// body World's SIMD kernel runs on lanes (dem/kernels/step_bodies.h, advance_lanes), so that a batch
// gives World's bits (tests/unit/test_batch.cpp).
#pragma once

#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/kernels/step_bodies.h"
#include "dem/core/vec3.h"

namespace dem::batch {

struct ParticleState {
    Vec3 x, v, w;  // [m], [m/s] and [rad/s] at t - dt/2 (v, w)
};

// The energy ledger's terms of one particle's step (dem/kernels/kernels.h, ParticleTerm): the work of
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
    AdvanceLanes<double> st;
    st.x = lanes(s.x);
    st.v = lanes(s.v);
    st.w = lanes(s.w);
    st.f = lanes(f);
    st.fx = lanes(fx);
    st.t = lanes(t);
    st.m = m;
    st.inv_m = inv_m;
    st.inv_i = inv_i;
    const bool free = inv_m > 0.0;
    const AdvanceStepLanes<double> q = advance_lanes(free, st, lanes(g), dt, lambda);
    if constexpr (kEnergy) {
        double terms[11];
        advance_terms_lanes(free, st, q, dt, lambda != 0.0, lanes(fp), r, terms);
        for (int k = 0; k < 5; ++k) {
            en->back[k] = terms[k];
            en->fwd[k] = terms[5 + k];
        }
        en->kinetic = terms[10];
    }
    s.x = vec3(st.x);
    s.v = vec3(st.v);
    s.w = vec3(st.w);
}

}  // namespace dem::batch
