// The foil's membrane tensions: what the bonds of a cylinder lattice carry around and along the
// cylinder, per unit length of the cut, as a thin shell's stress resultants N_theta and N_z.
// A measure (summary.json start_of_cycling: foil_hoop_tension, foil_axial_tension), not a force
// law: it reads the bonds' forces of the last compute_forces().
#pragma once

#include "dem/world/world.h"
#include "vpp/membrane/foil.h"

namespace vpp {

struct FoilTension {
    double hoop = 0.0;   // [N/m] N_theta: force across a cut through the axis per unit height, tension > 0
    double axial = 0.0;  // [N/m] N_z: force across a cut normal to the axis per unit circumference, tension > 0
};

// The mean tensions over the free band of a cylinder lattice (between its rows 1 and rows - 2,
// the rows off the fixed end rings), by the virial of its bonds:
//   N_theta = sum (T_b . t)(l_b . t) / A,   N_z = sum (T_b . z)(l_b . z) / A,
// T_b the bond's tension force (along l_b for a stretched bond), l_b its vector, t the azimuth at
// its midpoint, A = 2 pi R h the band's lateral area: R the mean distance of the band's particles
// from the axis, h the mean heights of rows 1 and rows - 2 apart. The band holds the row bonds of
// the even rows 2 .. rows - 3 and the column bonds from rows 1 .. rows - 3, each chain's share of
// the band once, so a uniform tension T per chain gives T / (4 r_f) around and T / (2 column
// pitch) along (docs/foil.md, "Tension"). Needs at least 5 rows.
FoilTension cylinder_tension(const FoilLattice& L, const dem::World& w);

}  // namespace vpp
