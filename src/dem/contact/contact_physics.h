// The coefficients of a new contact (ContactPhys) from the materials and radii of its two
// bodies: what the contact lifecycle asks when a pair starts touching or the materials change.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/contact/linear_law.h"
#include "dem/core/hd.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/walls/wall.h"

namespace dem {

// The reduced mass [kg] of a pair of particles of masses mi, mj [kg]: against a particle that does
// not move (fixed or prescribed) the moving one meets an infinite mass. ContactPhysics' and the
// batch engine's device's.
VPPDEM_HD inline double pair_mass(bool moves_i, double mi, bool moves_j, double mj) {
    if (!moves_i) return mj;
    if (!moves_j) return mi;
    return mi * mj / (mi + mj);
}

struct ContactPhysics {
    const Particles* p = nullptr;
    const std::vector<Material>* materials = nullptr;
    const std::vector<Plane>* planes = nullptr;
    const std::vector<Facet>* facets = nullptr;

    // Particle pair (i, j). Against a fixed or prescribed particle the moving one meets an
    // infinite mass; a clump member's mass is its clump's.
    ContactPhys pair(uint32_t i, uint32_t j) const {
        const Particles& q = *p;
        const double m_eff = pair_mass(moves(q, i), q.mass[i], moves(q, j), q.mass[j]);
        const auto& m = *materials;
        return make_contact_phys(m[q.material[i]], q.radius[i], m[q.material[j]], q.radius[j], m_eff);
    }
    // Particle i against wall w (planes first, then facets).
    ContactPhys wall(uint32_t i, uint32_t w) const {
        const Particles& q = *p;
        const uint32_t wm = w < planes->size() ? (*planes)[w].material : (*facets)[w - planes->size()].material;
        const auto& m = *materials;
        return make_contact_phys(m[wm], q.radius[i], m[q.material[i]], q.radius[i], q.mass[i]);
    }
};

}  // namespace dem
