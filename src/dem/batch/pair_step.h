// The batch engine's per-contact kernel bodies (docs/gpu.md) for the host backend and the CUDA
// kernels: one pair at a time on doubles, through the bodies World's kernels run on SIMD lanes
// (dem/kernels/step_bodies.h: frictional_pair_lanes, smooth_pair_lanes, spheres_touch_lanes) and
// World's wall body (wall_pair), so that a batch gives World's bits (tests/unit/test_batch.cpp).
// With kEnergy the bodies also give the energy ledger's terms of the contact (PairEnergy), as the
// kernels do.
#pragma once

#include "dem/contact/linear_law.h"
#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/kernels/step_bodies.h"
#include "dem/core/vec3.h"

namespace dem::batch {

using dem::PairEnd;
using dem::PairEnergy;
using dem::PairOut;
using dem::wall_geometry;
using dem::wall_pair;
using dem::WallNow;

// The touch test of a candidate particle pair (as ContactSet::find_new on the packed records).
VPPDEM_HD inline bool spheres_touch(const Vec3& xi, double ri, const Vec3& xj, double rj) {
    return spheres_touch_lanes(lanes(xi), ri, lanes(xj), rj);
}

VPPDEM_HD inline PairLanes<double> pair_lanes(const PairEnd& a, const PairEnd& b) {
    return {lanes(a.x), lanes(a.v), lanes(a.w), lanes(b.x), lanes(b.v), lanes(b.w), a.r, b.r};
}

// A frictional particle pair (frictional_pair_lanes on one pair): the shear history fs, prev
// updated (zeroed when apart).
template <bool kEnergy = false>
VPPDEM_HD inline PairOut frictional_pair(const PairEnd& a, const PairEnd& b, const ContactPhys& ph, double dt, Vec3& fs,
                                         Vec3& prev, PairEnergy* en = nullptr) {
    V3<double> s = lanes(fs), p = lanes(prev);
    PairLanesOut<double> q;
    PairOut o;
    o.touch = frictional_pair_lanes<kEnergy>(pair_lanes(a, b), true, ph.kn, ph.ks, ph.mu, ph.cn, dt, s, p, q);
    o.force = vec3(q.force);
    o.torque1 = vec3(q.torque1);
    o.torque2 = vec3(q.torque2);
    fs = vec3(s);
    prev = vec3(p);
    if constexpr (kEnergy) *en = PairEnergy{q.elastic, q.slip, q.release, q.viscous, vec3(q.fv)};
    return o;
}

// A frictionless particle pair (smooth_pair_lanes on one pair): the normal force only.
template <bool kEnergy = false>
VPPDEM_HD inline PairOut smooth_pair(const PairEnd& a, const PairEnd& b, const ContactPhys& ph, double dt,
                                     PairEnergy* en = nullptr) {
    PairLanesOut<double> q;
    PairOut o;
    o.touch = smooth_pair_lanes<kEnergy>(pair_lanes(a, b), true, ph.kn, ph.cn, dt, q);
    o.force = vec3(q.force);
    if constexpr (kEnergy) *en = PairEnergy{q.elastic, q.slip, q.release, q.viscous, vec3(q.fv)};
    return o;
}

}  // namespace dem::batch
