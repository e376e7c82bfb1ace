// The batch engine's per-bond and per-node kernel bodies (docs/gpu.md) for the host backend and
// the CUDA kernels: one bond at a time on doubles, through the body World's bond kernel runs on
// SIMD lanes (dem/kernels/step_bodies.h, bond_lanes), and the follower pressure's node force
// (dem/core/pressure.h, pressure_force, World's too), so that a batch gives World's bits
// (tests/unit/test_batch.cpp).
#pragma once

#include "dem/bonds/bond_law.h"
#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/core/pressure.h"
#include "dem/kernels/step_bodies.h"
#include "dem/core/vec3.h"

namespace dem::batch {

using dem::pressure_force;

struct BondEnd {
    Vec3 x, v, w;  // [m], [m/s], [rad/s] (half step)
    double r;      // [m]
};

struct BondOut {
    Vec3 force;             // [N] on body 2 (body 1: the opposite)
    Vec3 torque1, torque2;  // [N m]
};

// One bond's step (bond_lanes on one bond): the shear history fs, prev updated. With kEnergy the
// bond's stored energy [J] goes to *elastic. bond_point: the shear spring driven at the bond
// point (dem::BondArm::kBondPoint).
template <bool kEnergy = false>
VPPDEM_HD inline BondOut bond_step(const BondEnd& a, const BondEnd& b, double kn, double ks, double rest, double dt,
                                   Vec3& fs, Vec3& prev, double* elastic = nullptr, bool bond_point = false) {
    const PairLanes<double> q{lanes(a.x), lanes(a.v), lanes(a.w), lanes(b.x), lanes(b.v), lanes(b.w), a.r, b.r};
    V3<double> s = lanes(fs), p = lanes(prev), f, t1, t2;
    bond_lanes<kEnergy>(q, kn, ks, rest, dt, s, p, f, t1, t2, elastic, bond_point);
    fs = vec3(s);
    prev = vec3(p);
    return {vec3(f), vec3(t1), vec3(t2)};
}

}  // namespace dem::batch
