// The largest stable time step of the explicit integrator.
#pragma once

#include <vector>

#include "dem/bonds/bond_list.h"
#include "dem/clumps/clumps.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/walls/wall.h"

namespace dem {

// Largest stable step [s] for a lone contact pair: min over free particles of sqrt(m / kn_max),
// kn_max the stiffest pair the particle can form with any material present, with a wall, or
// through one of its bonds. Multiply by a safety factor (< 1) for dense packings. A clump
// member counts with the smaller of its clump's mass and the mass its clump's rotation puts
// at the member's far side, I_min / d^2 (d the member's reach from the centre of mass).
double critical_dt(const Particles& p, const std::vector<Material>& materials, const std::vector<Plane>& planes,
                   const std::vector<Facet>& facets, const BondList& bonds, const Clumps& clumps = Clumps{});

}  // namespace dem
