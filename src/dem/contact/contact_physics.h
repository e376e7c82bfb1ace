// The coefficients of a new contact (ContactPhys) from the materials and radii of its two
// bodies: what the contact lifecycle asks when a pair starts touching or the materials change.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/contact/linear_law.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/walls/wall.h"

namespace dem {

struct ContactPhysics {
    const Particles* p = nullptr;
    const std::vector<Material>* materials = nullptr;
    const std::vector<Plane>* planes = nullptr;
    const std::vector<Facet>* facets = nullptr;

    // Particle pair (i, j). Against a fixed or prescribed particle the moving one meets an
    // infinite mass; a clump member's mass is its clump's.
    ContactPhys pair(uint32_t i, uint32_t j) const {
        const Particles& q = *p;
        double m_eff;
        if (!moves(q, i)) m_eff = q.mass[j];
        else if (!moves(q, j)) m_eff = q.mass[i];
        else m_eff = q.mass[i] * q.mass[j] / (q.mass[i] + q.mass[j]);
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
