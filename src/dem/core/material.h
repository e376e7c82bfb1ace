// Material parameters and the Yade-convention stiffness of a pair of them.
#pragma once

#include <string>

#include "dem/core/hd.h"

namespace dem {

struct Material {
    std::string name;
    double density = 2800.0;        // [kg/m^3]
    double young = 4.8e10;          // [Pa] particle modulus E; kn = E*r for two equal spheres
    double stiffness_ratio = 0.5;   // [-] ks/kn (Yade calls it 'poisson'; it is no Poisson ratio)
    double friction = 0.35;         // [-] Coulomb coefficient mu (not an angle)
    double restitution = 1.0;       // [-] normal coefficient of restitution; 1 = no viscous damping
};

// Yade's FrictPhys convention: each side is a spring of stiffness E*R in series,
//   kn = 2 E1 R1 E2 R2 / (E1 R1 + E2 R2),  ks = the same with E*R*alpha.
// With equal alphas, ks = alpha * kn. A wall counts as a sphere of the particle's radius.
VPPDEM_HD inline double harmonic_stiffness(double a, double b) { return 2.0 * a * b / (a + b); }

}  // namespace dem
