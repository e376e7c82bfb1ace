// The shear spring that contacts and bonds share: an incremental tangential force carried in the
// global frame and turned with the pair's axis each step (Yade's ScGeom::rotate, with |Fs| kept).
// Below both the contact law (dem/contact/linear_law.h) and the bond law (dem/bonds/bond_law.h),
// so that neither includes the other.
#pragma once

#include "dem/core/hd.h"
#include "dem/core/lanes.h"
#include "dem/core/vec3.h"

namespace dem {

// Tangential state carried while a contact or bond lives.
struct ShearHistory {
    Vec3 shear;        // [N] elastic shear force in the global frame (acts on body 1 as -shear)
    Vec3 prev_normal;  // unit normal of the previous step; zero before the first step
};

#include "dem/core/shear_spring-inl.h"  // IWYU pragma: export

// Scalar form (tests).
inline void rotate_shear(ShearHistory& h, const Vec3& n, double spin_n, double dt) {
    V3<double> fs = lanes(h.shear), prev = lanes(h.prev_normal);
    rotate_shear_lanes(fs, prev, lanes(n), spin_n, dt);
    h.shear = vec3(fs);
    h.prev_normal = vec3(prev);
}

}  // namespace dem
