// Bond list as struct-of-arrays. Bonded pairs never also act as contacts.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/bonds/bond_law.h"

namespace dem {

struct BondList {
    std::vector<uint32_t> i, j;       // particle indices, i < j
    std::vector<BondPhys> phys;
    std::vector<Vec3> shear;          // [N] shear spring (history), global frame
    std::vector<Vec3> prev_normal;    // bond axis of the previous step (zero before the first)
    std::vector<Vec3> force;          // [N] on j (i gets the opposite), this step
    std::vector<Vec3> torque1, torque2;  // [N m]

    std::size_t size() const { return i.size(); }
};

}  // namespace dem
