// Bond list as struct-of-arrays. Bonded pairs never also act as contacts.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "dem/bonds/bond_law.h"

namespace dem {

// Where a bond's shear spring is driven from (bond_geometry_lanes, dem/kernels/step_bodies-inl.h).
// kRadius: the relative velocity at the full radii, as a contact's (Yade's avoidGranularRatcheting,
// the convention the paper's model was run with), while the torques act at the bond point,
// r - g/2 from each centre (g = r1 + r2 - L): the two agree for a bond of rest length r1 + r2 (the
// damper's lattice foil, 2 r_f) up to its strain, but on a remeshed membrane's bonds (0.45 to
// 1.27 diameters long) a rigid rotation loads the spring with energy no force did work for.
// kBondPoint: the relative velocity at the bond point, where the torques act: a rigid motion
// leaves the spring unloaded and it stores exactly the work of the torques (docs/energy.md, "Bonds").
enum class BondArm : uint8_t { kRadius = 0, kBondPoint = 1 };

// The arms' names in config files and Python: "radius", "bond_point"; nullopt for any other.
inline const char* bond_arm_name(BondArm a) { return a == BondArm::kBondPoint ? "bond_point" : "radius"; }
inline std::optional<BondArm> bond_arm_from_name(std::string_view name) {
    if (name == "radius") return BondArm::kRadius;
    if (name == "bond_point") return BondArm::kBondPoint;
    return std::nullopt;
}

struct BondList {
    std::vector<uint32_t> i, j;       // particle indices, i < j
    std::vector<BondPhys> phys;
    std::vector<Vec3> shear;          // [N] shear spring (history), global frame
    std::vector<Vec3> prev_normal;    // bond axis of the previous step (zero before the first)
    std::vector<Vec3> force;          // [N] on j (i gets the opposite), this step
    std::vector<Vec3> torque1, torque2;  // [N m]
    BondArm arm = BondArm::kRadius;      // every bond of the list (one membrane law per World)

    std::size_t size() const { return i.size(); }
};

}  // namespace dem
