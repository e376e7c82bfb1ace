// Permanent elastic bond between two spheres (a foil link): a normal spring that carries
// tension and compression about the rest length, and an incremental shear spring rotated with
// the bond axis like a contact's, never capped and never broken. No bending or twisting
// moment (as Yade's CohFrictPhys with momentRotationLaw = False).
#pragma once

#include "dem/contact/linear_law.h"

namespace dem {

struct BondPhys {
    double kn = 0;           // [N/m] axial stiffness
    double ks = 0;           // [N/m] shear stiffness
    double rest_length = 0;  // [m] centre distance at which the axial force is zero
};

// `n` unit vector from 1 to 2, `dist` [m] centre distance, `vrel` velocity of 2 relative to 1
// at the bond point [m/s]. Returns the force on body 2 [N]; body 1 gets the opposite.
// With `elastic` (energy tracking) the stored energy 1/2 kn (L - L0)^2 + |Fs|^2 / (2 ks) [J]
// after the step is written there; the force does not depend on it.
[[gnu::always_inline]] inline Vec3 bond_force(const BondPhys& b, const Vec3& n, double dist, const Vec3& vrel,
                       double spin_n, double dt, ShearHistory& h, double* elastic = nullptr) {
    rotate_shear(h, n, spin_n, dt);
    const Vec3 vt = vrel - n * dot(vrel, n);
    h.shear -= vt * (b.ks * dt);
    if (elastic) {
        const double stretch = dist - b.rest_length;
        *elastic = 0.5 * b.kn * stretch * stretch + (b.ks > 0.0 ? norm2(h.shear) / (2.0 * b.ks) : 0.0);
    }
    return n * (b.kn * (b.rest_length - dist)) + h.shear;
}

}  // namespace dem
