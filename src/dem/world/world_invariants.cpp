// World's consistency rules (World::broken_invariant): what every part of the state must agree
// on for a step to read only what exists. The checkpoint reader asks before it rebuilds the
// derived tables; tests ask after any step.
#include <stdexcept>
#include <string>

#include "dem/world/world.h"

namespace dem {

const char* World::broken_invariant() const {
    const Particles& p = particles;
    const std::size_t n = p.size(), nw = wall_count();
    if (!p.ext_force.empty() && p.ext_force.size() != n) return "particle arrays of different lengths";
    if (!p.ref_pos.empty() && p.ref_pos.size() != n) return "particle arrays of different lengths";
    for (std::size_t s : {p.vel.size(), p.angvel.size(), p.force.size(), p.torque.size(), p.radius.size(),
                          p.mass.size(), p.inv_mass.size(), p.inv_inertia.size(), p.material.size(), p.mask.size(),
                          p.flags.size(), p.motion.size()})
        if (s != n) return "particle arrays of different lengths";
    for (std::size_t i = 0; i < n; ++i) {
        if (p.material[i] >= materials.size()) return "particle material out of range";
        if (p.motion[i] >= int64_t(motions.size()) || p.motion[i] < -1) return "particle motion out of range";
        if ((p.flags[i] & kPrescribed) && (p.motion[i] < 0 || p.ref_pos.empty())) return "prescribed particle without motion";
    }
    for (const Plane& pl : planes)
        if (pl.material >= materials.size()) return "wall material out of range";
    for (const Facet& f : facets)
        if (f.material >= materials.size()) return "wall material out of range";
    for (const PressureNode& q : pressure.nodes) {
        if (q.node >= n) return "pressure node out of range";
        for (uint32_t r : q.ring)
            if (r >= n) return "pressure ring out of range";
    }
    {
        const PressureFans& f = pressure.fans;
        if (!f.empty() && (f.start.size() != f.node.size() + 1 || f.start.front() != 0 || f.start.back() != f.ring.size()))
            return "pressure fan ranges do not match the rings";
        for (uint32_t q : f.node)
            if (q >= n) return "pressure node out of range";
        for (uint32_t r : f.ring)
            if (r >= n) return "pressure ring out of range";
    }
    if (const char* why = clump_rule()) return why;
    if (const char* why = contacts_.broken_rule(n, nw)) return why;
    const BondList& b = bonds_;
    const std::size_t nb = b.size();
    if (b.j.size() != nb || b.phys.size() != nb || b.shear.size() != nb || b.prev_normal.size() != nb ||
        b.force.size() != nb || b.torque1.size() != nb || b.torque2.size() != nb)
        return "bond arrays of different lengths";
    for (std::size_t k = 0; k < nb; ++k)
        if (b.i[k] >= n || b.j[k] >= n) return "bond index out of range";
    if (!broad_.dirty && (broad_.ref_pos.size() != n || broad_.wall_ref_disp.size() != nw))
        return "rebuild state does not match the particles and walls";
    using kernels::block_count, kernels::kPairSums;
    const ContactSet& c = contacts_;
    if (book_.ready &&
        (book_.fric.size() != std::size_t(block_count(c.fric.size()) * kPairSums) ||
         book_.smooth.size() != std::size_t(block_count(c.smooth.size()) * kPairSums) ||
         book_.walls.size() != std::size_t(block_count(c.walls.size()) * kPairSums) ||
         book_.bonds.size() != std::size_t(block_count(nb)) || pressure_forces_.force.size() != n ||
         walls_now_.force.size() != nw || walls_now_.velocity.size() != nw))
        return "energy terms do not match the contacts, bonds and particles";
    return nullptr;
}

const char* World::clump_rule() const {
    const Clumps& c = clumps_;
    const Particles& p = particles;
    const std::size_t n = p.size(), nc = c.size();
    for (std::size_t s : {c.vel.size(), c.q.size(), c.mom.size(), c.angvel.size(), c.inertia.size(), c.mass.size(),
                          c.inv_mass.size()})
        if (s != nc) return "clump arrays of different lengths";
    if (c.start.size() != nc + 1 || c.start[0] != 0 || c.start[nc] != c.member.size() || c.rel.size() != c.member.size())
        return "clump member lists do not match the clumps";
    if (nc == 0) {
        if (!c.owner.empty()) return "clump owners without clumps";
        for (std::size_t i = 0; i < n; ++i)
            if (p.flags[i] & kClumpMember) return "clump member without a clump";
        return nullptr;
    }
    if (c.owner.size() != n) return "clump owners do not match the particles";
    std::size_t members = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const bool flagged = p.flags[i] & kClumpMember;
        if (c.owner[i] < -1 || c.owner[i] >= int64_t(nc) || flagged != (c.owner[i] >= 0))
            return "clump owner out of range or not matching the member flag";
        members += flagged;
    }
    if (members != c.member.size()) return "clump member lists do not match the member flags";
    for (std::size_t k = 0; k < nc; ++k) {
        if (c.start[k] > c.start[k + 1]) return "clump member lists do not match the clumps";
        if (!(c.mass[k] > 0.0) || !(c.inertia[k].x > 0.0) || !(c.inertia[k].y > 0.0) || !(c.inertia[k].z > 0.0))
            return "clump mass or moment of inertia not positive";
        for (uint32_t e = c.start[k]; e < c.start[k + 1]; ++e)
            if (c.member[e] >= n || c.owner[c.member[e]] != int32_t(k)) return "clump member out of range or of another clump";
    }
    return nullptr;
}

void World::check_invariants() const {
    if (const char* why = broken_invariant()) throw std::logic_error(std::string("World invariant broken: ") + why);
}

}  // namespace dem
