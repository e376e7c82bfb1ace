// Linear Cundall-Strack contact law with Yade's conventions (FrictPhys +
// Law2_ScGeom_FrictPhys_CundallStrack), plus an optional normal dashpot set by a
// coefficient of restitution. A value type with a pure force function: coefficients are
// precomputed once per contact (ContactPhys), the history lives in ShearHistory.
//
// The law is written once over "lanes" (dem/core/lanes.h): the *_lanes functions run on
// doubles and, in the SIMD kernels, on vectors of doubles, with the same bits. The functions
// on ContactPhys/ShearHistory are the scalar form used by tests and rare paths.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dem/core/energy.h"
#include "dem/core/lanes.h"
#include "dem/core/material.h"
#include "dem/core/shear_spring.h"
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
// makes this relation exact whatever kn and mass are. The price is a short pull at the end of
// an impact: the dashpot part of the normal force, -cn vn with vn > 0 separating, can exceed
// the elastic push as the overlap closes (docs/model.md, "Normal dashpot"). The elastic part
// never pulls.
inline double damping_ratio_from_restitution(double e) {
    if (e >= 1.0) return 0.0;
    if (e <= 0.0) return 1.0;
    const double l = std::log(e);
    return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

// Coefficients for a pair from the two sides' moduli [Pa], ks/kn ratios [-], friction
// coefficients [-] and radii r1, r2 [m] (a wall passes the sphere's radius for both), the reduced
// mass m_eff [kg] (the particle's mass against a wall or a fixed particle) and the damping ratio
// zeta [-] (damping_ratio_from_restitution of the smaller restitution). One source for World and
// the batch engine's device, which places contacts itself; zeta comes from the host because a
// device's log need not round as the host's does.
VPPDEM_HD inline ContactPhys contact_phys_of(double young_a, double ratio_a, double friction_a, double r1,
                                             double young_b, double ratio_b, double friction_b, double r2,
                                             double m_eff, double zeta) {
    ContactPhys p;
    const double ea = young_a * r1, eb = young_b * r2;
    p.kn = harmonic_stiffness(ea, eb);
    p.ks = harmonic_stiffness(ea * ratio_a, eb * ratio_b);
    p.mu = friction_b < friction_a ? friction_b : friction_a;  // min of the angles, as Yade: tan is monotonic
    p.cn = 2.0 * zeta * std::sqrt(m_eff * p.kn);
    return p;
}

// Two materials with different restitution: the pair takes the smaller (more dissipative).
inline double pair_damping_ratio(const Material& a, const Material& b) {
    return damping_ratio_from_restitution(std::min(a.restitution, b.restitution));
}

// Coefficients for a pair (contact_phys_of) of two materials.
inline ContactPhys make_contact_phys(const Material& a, double r1, const Material& b, double r2,
                                     double m_eff) {
    return contact_phys_of(a.young, a.stiffness_ratio, a.friction, r1, b.young, b.stiffness_ratio, b.friction, r2,
                           m_eff, pair_damping_ratio(a, b));
}

#include "dem/contact/linear_law-inl.h"  // IWYU pragma: export

// ---- scalar forms

// One step of the law for one contact (see linear_contact_force_lanes). With `e` the step's
// energy terms are written there (release = 0).
inline Vec3 linear_contact_force(const ContactPhys& p, const ContactGeom& g, const Vec3& vrel, double spin_n,
                                 double dt, ShearHistory& h, ContactEnergyStep* e = nullptr) {
    V3<double> fs = lanes(h.shear), prev = lanes(h.prev_normal), f;
    if (e) {
        ContactEnergyLanes<double> el;
        f = linear_contact_force_lanes<true>(p.kn, p.ks, p.mu, p.cn, lanes(g.normal), g.overlap, lanes(vrel),
                                             spin_n, dt, fs, prev, &el);
        *e = ContactEnergyStep{el.elastic, el.slip, 0.0, el.viscous, vec3(el.fv)};
    } else {
        f = linear_contact_force_lanes<false>(p.kn, p.ks, p.mu, p.cn, lanes(g.normal), g.overlap, lanes(vrel),
                                              spin_n, dt, fs, prev);
    }
    h.shear = vec3(fs);
    h.prev_normal = vec3(prev);
    return vec3(f);
}

// Energy lost when a contact opens with a loaded shear spring (the contact forgets it): the
// spring's energy |Fs|^2 / (2 ks) minus the work it did on the bodies over the first half of
// the opening step (trapezoid: Fs . vrel dt / 2). `vrel` as for linear_contact_force, with the
// last contact normal as lever-arm direction. Call before the history is cleared.
VPPDEM_HD inline double shear_release_energy(double ks, const Vec3& shear, const Vec3& vrel, double dt) {
    if (!(ks > 0.0)) return 0.0;
    return norm2(shear) / (2.0 * ks) - 0.5 * dot(shear, vrel) * dt;
}

}  // namespace dem
