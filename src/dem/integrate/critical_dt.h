// The largest stable time step of the explicit integrator.
#pragma once

#include <vector>

#include "dem/bonds/bond_list.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/walls/wall.h"

namespace dem {

// Largest stable step [s] for a lone contact pair: min over free particles of sqrt(m / kn_max),
// kn_max the stiffest pair the particle can form with any material present, with a wall, or
// through one of its bonds. Multiply by a safety factor (< 1) for dense packings.
double critical_dt(const Particles& p, const std::vector<Material>& materials, const std::vector<Plane>& planes,
                   const std::vector<Facet>& facets, const BondList& bonds);

}  // namespace dem
