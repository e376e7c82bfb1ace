// Linear Cundall-Strack contact law with Yade's conventions (FrictPhys +
// Law2_ScGeom_FrictPhys_CundallStrack), plus an optional normal dashpot set by a
// coefficient of restitution. A value type with a pure force function: coefficients are
// precomputed once per contact (ContactPhys), the history lives in ShearHistory.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dem/core/energy.h"
#include "dem/core/material.h"
#include "dem/core/vec3.h"
#include "dem/detect/geometry.h"

namespace dem {

struct ContactPhys {
    double kn = 0;  // [N/m] normal stiffness
    double ks = 0;  // [N/m] shear stiffness
    double mu = 0;  // [-] Coulomb coefficient
    double cn = 0;  // [N s/m] normal dashpot; 0 when restitution = 1
};

// Damping ratio of a linear spring-dashpot whose free normal impact has restitution e:
// e = exp(-zeta pi / sqrt(1 - zeta^2)). The dashpot force is not clipped at the end of the
// impact (the contact ends when the overlap, not the force, returns to zero), which is what
// makes this relation exact whatever kn and mass are.
inline double damping_ratio_from_restitution(double e) {
    if (e >= 1.0) return 0.0;
    if (e <= 0.0) return 1.0;
    const double l = std::log(e);
    return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

// Coefficients for a pair. r1, r2: radii [m] (a wall passes the sphere's radius for both);
// m_eff: reduced mass [kg] (the particle's mass against a wall or a fixed particle).
inline ContactPhys make_contact_phys(const Material& a, double r1, const Material& b, double r2,
                                     double m_eff) {
    ContactPhys p;
    const double ea = a.young * r1, eb = b.young * r2;
    p.kn = harmonic_stiffness(ea, eb);
    p.ks = harmonic_stiffness(ea * a.stiffness_ratio, eb * b.stiffness_ratio);
    p.mu = std::min(a.friction, b.friction);  // min of the angles, as Yade: tan is monotonic
    // Two materials with different restitution: the pair takes the smaller (more dissipative).
    const double zeta = damping_ratio_from_restitution(std::min(a.restitution, b.restitution));
    p.cn = 2.0 * zeta * std::sqrt(m_eff * p.kn);
    return p;
}

// Tangential state carried while a contact lives.
struct ShearHistory {
    Vec3 shear;        // [N] elastic shear force in the global frame (acts on body 1 as -shear)
    Vec3 prev_normal;  // unit normal of the previous step; zero before the first step
};

// Carries the shear force with the contact plane: rotates it by the change of normal and by
// the twist (Yade's ScGeom::rotate), projects it back onto the plane and keeps its length.
// Yade rotates to first order only; keeping |Fs| avoids creating energy by the rotation itself.
inline void rotate_shear(ShearHistory& h, const Vec3& n, double spin_n, double dt) {
    Vec3& fs = h.shear;
    if (h.prev_normal == Vec3{}) h.prev_normal = n;
    const double len0_2 = norm2(fs);
    if (len0_2 > 0.0) {
        fs -= cross(fs, cross(h.prev_normal, n));
        fs -= cross(fs, n * (dt * spin_n));
        fs -= n * dot(fs, n);
        const double len1_2 = norm2(fs);
        if (len1_2 > 0.0) fs *= std::sqrt(len0_2 / len1_2);  // one root instead of two
    }
    h.prev_normal = n;
}

// One step of the law. `vrel` is the velocity of body 2 relative to body 1 at the contact
// [m/s]; `spin_n` = 0.5 * normal . (w1 + w2) [rad/s] is the twist rate of the contact plane.
// Returns the force on body 2 [N] (body 1 gets the opposite). With `e` (energy tracking, see
// docs/energy.md) the step's energy terms are written there; the force does not depend on it.
[[gnu::always_inline]] inline Vec3 linear_contact_force(const ContactPhys& p, const ContactGeom& g, const Vec3& vrel,
                                 double spin_n, double dt, ShearHistory& h,
                                 ContactEnergyStep* e = nullptr) {
    const Vec3& n = g.normal;
    rotate_shear(h, n, spin_n, dt);
    Vec3& fs = h.shear;
    Vec3 fs_prev;
    if (e) fs_prev = fs;  // the spring carried into this step's contact plane

    const double vn = dot(vrel, n);        // > 0 separating
    const Vec3 vt = vrel - n * vn;
    fs -= vt * (p.ks * dt);                // incremental elastic shear spring

    const double fn = p.kn * g.overlap - p.cn * vn;  // elastic part never pulls (overlap > 0)
    const double fs_max = p.mu * std::max(fn, 0.0);
    const double fs2 = norm2(fs);
    if (e) e->slip = 0.0;
    if (fs2 > fs_max * fs_max) {
        Vec3 trial;
        if (e) trial = fs;
        fs *= fs_max / std::sqrt(fs2);  // Coulomb slip
        // Work done on the spring over the step (trapezoid with the relative displacement
        // u = vt dt = (fs_prev - trial) / ks) minus its energy change:
        //   (trial - fs) . (fs_prev + fs) / (2 ks)   (= mu fn |slip| when sliding steadily).
        if (e && p.ks > 0.0) e->slip = dot(trial - fs, fs_prev + fs) / (2.0 * p.ks);
    }
    if (e) {
        e->elastic = 0.5 * p.kn * g.overlap * g.overlap + (p.ks > 0.0 ? norm2(fs) / (2.0 * p.ks) : 0.0);
        e->viscous = 0.5 * p.cn * vn * vn * dt;
        e->fv = n * (-p.cn * vn);
        e->release = 0.0;
    }

    // Force on body 1 is -(fn n) - fs (Yade); body 2 gets the opposite.
    return n * fn + fs;
}

// Energy lost when a contact opens with a loaded shear spring (the contact forgets it): the
// spring's energy |Fs|^2 / (2 ks) minus the work it did on the bodies over the first half of
// the opening step (trapezoid: Fs . vrel dt / 2). `vrel` as for linear_contact_force, with the
// last contact normal as lever-arm direction. Call before the history is cleared.
inline double shear_release_energy(const ContactPhys& p, const ShearHistory& h, const Vec3& vrel, double dt) {
    if (!(p.ks > 0.0)) return 0.0;
    return norm2(h.shear) / (2.0 * p.ks) - 0.5 * dot(h.shear, vrel) * dt;
}

}  // namespace dem
