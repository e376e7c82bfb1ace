#include "dem/integrate/critical_dt.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dem/core/material.h"

namespace dem {

double critical_dt(const Particles& p, const std::vector<Material>& materials, const std::vector<Plane>& planes,
                   const std::vector<Facet>& facets, const BondList& bonds) {
    // Stiffest partner per material: E * r_max of that material's particles.
    std::vector<double> er_max(materials.size(), 0.0);
    for (std::size_t i = 0; i < p.size(); ++i)
        er_max[p.material[i]] = std::max(er_max[p.material[i]], materials[p.material[i]].young * p.radius[i]);
    double wall_e = 0.0;
    for (const Plane& pl : planes) wall_e = std::max(wall_e, materials[pl.material].young);
    for (const Facet& f : facets) wall_e = std::max(wall_e, materials[f.material].young);
    std::vector<double> kbond(p.size(), 0.0);
    for (std::size_t b = 0; b < bonds.size(); ++b) {
        kbond[bonds.i[b]] = std::max(kbond[bonds.i[b]], bonds.phys[b].kn);
        kbond[bonds.j[b]] = std::max(kbond[bonds.j[b]], bonds.phys[b].kn);
    }
    double best = std::numeric_limits<double>::infinity();
    const double partner_er = *std::max_element(er_max.begin(), er_max.end());
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.inv_mass[i] == 0.0) continue;
        const double a = materials[p.material[i]].young * p.radius[i];
        const double b = std::max(partner_er, wall_e * p.radius[i]);
        const double kn = std::max(harmonic_stiffness(a, b), kbond[i]);
        best = std::min(best, std::sqrt(p.mass[i] / kn));
    }
    return best;
}

}  // namespace dem
