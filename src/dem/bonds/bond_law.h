// Permanent elastic bond between two spheres (a foil link): a normal spring that carries
// tension and compression about the rest length, and an incremental shear spring rotated with
// the bond axis like a contact's, never capped and never broken. No bending or twisting
// moment (as Yade's CohFrictPhys with momentRotationLaw = False).
// Written over lanes (dem/core/lanes.h) like the contact law: bond_force_lanes runs on doubles
// and in the SIMD bond kernel with the same bits.
#pragma once

#include "dem/core/shear_spring.h"

namespace dem {

struct BondPhys {
    double kn = 0;           // [N/m] axial stiffness
    double ks = 0;           // [N/m] shear stiffness
    double rest_length = 0;  // [m] centre distance at which the axial force is zero
};

#include "dem/bonds/bond_law-inl.h"  // IWYU pragma: export

// Scalar form (tests).
inline Vec3 bond_force(const BondPhys& b, const Vec3& n, double dist, const Vec3& vrel, double spin_n, double dt,
                       ShearHistory& h, double* elastic = nullptr) {
    V3<double> fs = lanes(h.shear), prev = lanes(h.prev_normal), f;
    if (elastic)
        f = bond_force_lanes<true>(b.kn, b.ks, b.rest_length, lanes(n), dist, lanes(vrel), spin_n, dt, fs, prev,
                                   elastic);
    else
        f = bond_force_lanes<false>(b.kn, b.ks, b.rest_length, lanes(n), dist, lanes(vrel), spin_n, dt, fs, prev);
    h.shear = vec3(fs);
    h.prev_normal = vec3(prev);
    return vec3(f);
}

}  // namespace dem
