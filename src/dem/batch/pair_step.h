// The batch engine's per-contact kernel bodies (docs/gpu.md), written once for the host backend
// and the CUDA kernels: the arithmetic of World's pair kernels (dem/core/kernels.cpp,
// frictional_body and smooth_body, one SIMD lane at a time) and of its wall kernel
// (dem/core/wall_kernel.cpp) in the same order, and the touch test that opens a contact
// (ContactSet::find_new), so that a batch gives World's bits (tests/unit/test_batch.cpp).
// With kEnergy the bodies also give the energy ledger's terms of the contact (PairEnergy), as the
// kernels do.
#pragma once

#include "dem/contact/linear_law.h"
#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/core/vec3.h"
#include "dem/detect/geometry.h"

namespace dem::batch {

// One body of a particle pair as the pair kernels read it (position, half-step velocities, radius).
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

// A contact's terms for the energy ledger (dem/core/kernels.h, PairSum): zero but for a touching
// pair (elastic, slip, viscous and the dashpot force) or one found apart with a loaded shear
// spring (release).
struct PairEnergy {
    double elastic = 0, slip = 0, release = 0, viscous = 0;  // [J]
    Vec3 fv;                                                  // [N] dashpot force on body 2
};

// The touch test of a candidate particle pair (as ContactSet::find_new on the packed records).
VPPDEM_HD inline bool spheres_touch(const Vec3& xi, double ri, const Vec3& xj, double rj) {
    const V3<double> dx = lanes(xj) - lanes(xi);
    const double rs = ri + rj;
    return norm2(dx) < rs * rs;
}

// Sphere-sphere geometry as the SIMD pair kernels compute it (dem/detect/geometry.h,
// sphere_sphere, evaluated whether or not the spheres touch).
struct SphereGeometry {
    V3<double> n;    // unit normal from body 1 to body 2 ((0, 0, 1) for coincident centres)
    double overlap;  // [m] rs - distance (negative when apart)
    bool touch;
};
VPPDEM_HD inline SphereGeometry sphere_geometry(const PairEnd& a, const PairEnd& b) {
    const V3<double> dx = lanes(b.x) - lanes(a.x);
    const double d2 = norm2(dx), rs = a.r + b.r;
    const double dist = lane_sqrt(d2);
    const double inv = 1.0 / dist;
    return {dist > 0.0 ? dx * inv : V3<double>{0.0, 0.0, 1.0}, rs - dist, d2 < rs * rs};
}

// A frictional particle pair: sphere-sphere geometry, relative velocity at the contact with
// lever arms at the full radii (Yade's avoidGranularRatcheting), the linear law with its shear
// history (fs, prev: updated; zeroed when apart), torques at the contact point.
template <bool kEnergy = false>
VPPDEM_HD inline PairOut frictional_pair(const PairEnd& a, const PairEnd& b, const ContactPhys& ph, double dt, Vec3& fs,
                                         Vec3& prev, PairEnergy* en = nullptr) {
    const SphereGeometry q = sphere_geometry(a, b);
    const V3<double>& n = q.n;
    const double overlap = q.overlap;
    PairOut o;
    o.touch = q.touch;
    const double arm1 = a.r - 0.5 * overlap, arm2 = b.r - 0.5 * overlap;
    const auto relative_velocity = [&](const V3<double>& m) {
        return (lanes(b.v) + cross(lanes(b.w), m * neg(b.r))) - (lanes(a.v) + cross(lanes(a.w), m * a.r));
    };
    const V3<double> vrel = relative_velocity(n);
    const double spin_n = 0.5 * dot(n, lanes(a.w) + lanes(b.w));
    const V3<double> fs0 = lanes(fs), prev0 = lanes(prev);
    V3<double> s = fs0, p = prev0;
    ContactEnergyLanes<double> e;
    const V3<double> f = linear_contact_force_lanes<kEnergy, double>(ph.kn, ph.ks, ph.mu, ph.cn, n, overlap, vrel, spin_n,
                                                                     dt, s, p, &e);
    if (!o.touch) {
        if constexpr (kEnergy) {
            // Opened this step: the loaded spring is lost, with the last normal as lever-arm direction.
            *en = PairEnergy{};
            if (ph.ks > 0.0) en->release = norm2(fs0) / (2.0 * ph.ks) - 0.5 * dot(fs0, relative_velocity(prev0)) * dt;
        }
        fs = prev = Vec3{};
        return o;
    }
    const V3<double> nxf = cross(n, neg(f));
    o.force = vec3(f);
    o.torque1 = vec3(nxf * arm1);
    o.torque2 = vec3(nxf * arm2);
    fs = vec3(s);
    prev = vec3(p);
    if constexpr (kEnergy) *en = PairEnergy{e.elastic, e.slip, 0.0, e.viscous, vec3(e.fv)};
    return o;
}

// A frictionless particle pair: the normal force only (no shear spring, no torques).
template <bool kEnergy = false>
VPPDEM_HD inline PairOut smooth_pair(const PairEnd& a, const PairEnd& b, const ContactPhys& ph, double dt,
                                     PairEnergy* en = nullptr) {
    const SphereGeometry q = sphere_geometry(a, b);
    const V3<double>& n = q.n;
    const double overlap = q.overlap;
    PairOut o;
    o.touch = q.touch;
    // Only the normal relative velocity matters here: without shear there is no lever arm.
    const V3<double> vrel = lanes(b.v) - lanes(a.v);
    ContactEnergyLanes<double> e;
    const V3<double> f = normal_contact_force_lanes<kEnergy, double>(ph.kn, ph.cn, n, overlap, vrel, dt, &e);
    if (o.touch) o.force = vec3(f);
    if constexpr (kEnergy) *en = o.touch ? PairEnergy{e.elastic, 0.0, 0.0, e.viscous, vec3(e.fv)} : PairEnergy{};
    return o;
}

// Where a wall is now: a plane (point, normal) or a facet (vertices), and its velocity over the
// last step.
struct WallNow {
    bool plane = true;
    bool one_sided = false;
    Vec3 point, normal;  // [m], [-] (planes)
    Vec3 v0, v1, v2;     // [m] (facets)
    Vec3 velocity;       // [m/s]
};

// The narrow phase of a particle against a wall.
VPPDEM_HD inline bool wall_geometry(const PairEnd& a, const WallNow& wl, ContactGeom& g) {
    if (wl.plane) return sphere_plane(a.x, a.r, wl.point, wl.normal, wl.one_sided, g);
    return sphere_facet(a.x, a.r, {wl.v0, wl.v1, wl.v2}, wl.one_sided, g);
}

// A particle-wall contact (the particle is body 2): geometry, the linear law (frictionless:
// normal force only), the torque on the particle and the contact point.
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

}  // namespace dem::batch
