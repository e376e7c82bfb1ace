// The batch engine's per-bond and per-node kernel bodies (docs/gpu.md), written once for the
// host backend and the CUDA kernels: the arithmetic of World's SIMD bond kernel
// (dem/core/kernels.cpp, bond_body) and of the follower pressure (dem/core/pressure.cpp) in the
// same order, so that a batch gives World's bits (tests/unit/test_batch.cpp).
#pragma once

#include "dem/bonds/bond_law.h"
#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/core/pressure.h"
#include "dem/core/vec3.h"

namespace dem::batch {

struct BondEnd {
    Vec3 x, v, w;  // [m], [m/s], [rad/s] (half step)
    double r;      // [m]
};

struct BondOut {
    Vec3 force;             // [N] on body 2 (body 1: the opposite)
    Vec3 torque1, torque2;  // [N m]
};

// One bond's step: geometry, relative velocity at the bond point (lever arms at the full radii,
// Yade's convention), the bond law with its shear history (fs, prev: updated), torques.
// With kEnergy the bond's stored energy [J] goes to *elastic.
template <bool kEnergy = false>
VPPDEM_HD inline BondOut bond_step(const BondEnd& a, const BondEnd& b, double kn, double ks, double rest, double dt,
                                   Vec3& fs, Vec3& prev, double* elastic = nullptr) {
    const Vec3 dx = b.x - a.x;
    const double dist = lane_sqrt(norm2(dx));
    const Vec3 n = dx * (1.0 / dist);
    const double half_gap = 0.5 * (a.r + b.r - dist);
    const Vec3 vrel = (b.v + cross(b.w, n * neg(b.r))) - (a.v + cross(a.w, n * a.r));
    const double spin_n = 0.5 * dot(n, a.w + b.w);
    V3<double> s = lanes(fs), p = lanes(prev);
    const V3<double> f = bond_force_lanes<kEnergy, double>(kn, ks, rest, lanes(n), dist, lanes(vrel), spin_n, dt, s, p, elastic);
    fs = vec3(s);
    prev = vec3(p);
    const Vec3 force = vec3(f);
    const Vec3 nxf = cross(n, -force);
    return {force, nxf * (a.r - half_gap), nxf * (b.r - half_gap)};
}

// The follower pressure's force on a node [N]: -(A dp), A its ring's tributary area.
VPPDEM_HD inline Vec3 pressure_force(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double dp) {
    return -(tributary_area(p1, p2, p3, p4) * dp);
}

}  // namespace dem::batch
