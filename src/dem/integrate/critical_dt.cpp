#include "dem/integrate/critical_dt.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dem/core/material.h"

namespace dem {

double critical_dt(const Particles& p, const std::vector<Material>& materials, const std::vector<Plane>& planes,
                   const std::vector<Facet>& facets, const BondList& bonds, const Clumps& clumps) {
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
    // Clump members: the mass their clump's rotation puts at their far side.
    std::vector<double> rot_mass;
    if (!clumps.empty()) {
        rot_mass.assign(p.size(), std::numeric_limits<double>::infinity());
        for (std::size_t c = 0; c < clumps.size(); ++c) {
            const Vec3 I = clumps.inertia[c];
            const double i_min = std::min({I.x, I.y, I.z});
            for (uint32_t k = clumps.start[c]; k < clumps.start[c + 1]; ++k) {
                const uint32_t i = clumps.member[k];
                const double d = norm(clumps.rel[k]) + p.radius[i];
                rot_mass[i] = i_min / (d * d);
            }
        }
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (!moves(p, i)) continue;
        const double a = materials[p.material[i]].young * p.radius[i];
        const double b = std::max(partner_er, wall_e * p.radius[i]);
        const double kn = std::max(harmonic_stiffness(a, b), kbond[i]);
        const double m = rot_mass.empty() ? p.mass[i] : std::min(p.mass[i], rot_mass[i]);
        best = std::min(best, std::sqrt(m / kn));
    }
    return best;
}

}  // namespace dem
