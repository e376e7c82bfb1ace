// The per-index bodies of the step, written once for World's kernels and the batch engine's
// (host backend, device kernels: VPPDEM_HD, docs/gpu.md). The lane templates of
// dem/kernels/step_bodies-inl.h (pairs, bonds, the integrator, the touch test) run on SIMD vectors in
// World's kernels (dem/kernels/kernels.cpp) and on doubles here; the wall contact, which World runs
// in scalar code (dem/kernels/wall_kernel.cpp), is a scalar function here. Both engines call these
// same functions, so that they give the same bits (tests/unit/test_batch.cpp).
#pragma once

#include "dem/bonds/bond_law.h"
#include "dem/contact/linear_law.h"
#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/core/vec3.h"
#include "dem/detect/geometry.h"
#include "dem/walls/wall_now.h"

namespace dem {

#include "dem/kernels/step_bodies-inl.h"  // IWYU pragma: export

// One body of a particle pair as a scalar body reads it (position, half-step velocities, radius).
struct PairEnd {
    Vec3 x, v, w;  // [m], [m/s], [rad/s]
    double r;      // [m]
};

// What a contact's step wrote: zero everything (and touch = false) when the pair was found
// apart, which frees its slot (Yade deletes the interaction with its shear spring).
struct PairOut {
    Vec3 force;             // [N] on body 2 (body 1: the opposite)
    Vec3 torque1, torque2;  // [N m]
    Vec3 point;             // [m] contact point (walls only)
    bool touch = false;
};

// A contact's terms for the energy ledger (dem/kernels/kernels.h, PairSum): zero but for a touching
// pair (elastic, slip, viscous and the dashpot force) or one found apart with a loaded shear
// spring (release).
struct PairEnergy {
    double elastic = 0, slip = 0, release = 0, viscous = 0;  // [J]
    Vec3 fv;                                                  // [N] dashpot force on body 2
};

// The narrow phase of a sphere (x [m], r [m]) against a wall: the touch test of
// ContactSet::find_new and the geometry of the wall kernel.
VPPDEM_HD inline bool wall_geometry(const Vec3& x, double r, const WallNow& wl, ContactGeom& g) {
    if (wl.plane) return sphere_plane(x, r, wl.point, wl.normal, wl.one_sided, g);
    return sphere_facet(x, r, {wl.v0, wl.v1, wl.v2}, wl.one_sided, g);
}
VPPDEM_HD inline bool wall_geometry(const PairEnd& a, const WallNow& wl, ContactGeom& g) {
    return wall_geometry(a.x, a.r, wl, g);
}

// A particle-wall contact (the particle is body 2): geometry, the linear law (frictionless:
// normal force only), the torque on the particle and the contact point; zero everything when
// apart (with kEnergy: the lost shear spring's energy in en->release).
template <bool kEnergy = false>
VPPDEM_HD inline PairOut wall_pair(const PairEnd& a, const WallNow& wl, const ContactPhys& ph, double dt, Vec3& fs,
                                   Vec3& prev, PairEnergy* en = nullptr) {
    PairOut o;
    ContactGeom g;
    o.touch = wall_geometry(a, wl, g);
    if (!o.touch) {
        if constexpr (kEnergy) {  // opened this step: the shear spring's energy is lost
            *en = PairEnergy{};
            const Vec3 vrel = (a.v + cross(a.w, prev * -a.r)) - wl.velocity;
            en->release = shear_release_energy(ph.ks, fs, vrel, dt);
        }
        fs = prev = Vec3{};
        return o;
    }
    const Vec3& n = g.normal;  // from the wall to the sphere
    const Vec3 vrel = (a.v + cross(a.w, n * -a.r)) - wl.velocity;
    ContactEnergyLanes<double> e;
    V3<double> f;
    if (ph.mu == 0.0) {
        f = normal_contact_force_lanes<kEnergy, double>(ph.kn, ph.cn, lanes(n), g.overlap, lanes(vrel), dt, &e);
    } else {
        V3<double> s = lanes(fs), p = lanes(prev);
        const double spin_n = 0.5 * dot(n, a.w);
        f = linear_contact_force_lanes<kEnergy, double>(ph.kn, ph.ks, ph.mu, ph.cn, lanes(n), g.overlap, lanes(vrel),
                                                        spin_n, dt, s, p, &e);
        fs = vec3(s);
        prev = vec3(p);
        o.torque2 = cross(n, -vec3(f)) * g.arm2;
    }
    o.force = vec3(f);
    o.point = a.x - n * g.arm2;
    if constexpr (kEnergy) *en = PairEnergy{e.elastic, e.slip, 0.0, e.viscous, vec3(e.fv)};
    return o;
}

}  // namespace dem
