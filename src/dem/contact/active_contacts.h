// Touching pairs and their state, in struct-of-arrays: one entry ("slot") per live contact.
// A pair gets a slot when it starts touching and gives it up when it opens; the freed slots are
// holes (cand = kNoSlot) until the next rebuild compacts the store into candidate order.
// Three stores: frictional particle pairs (shear history, torques), frictionless particle
// pairs (normal force only: with mu = 0 the shear spring is always zero, see
// normal_contact_force_lanes), and wall pairs.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/detect/candidates.h"
#include "dem/contact/linear_law.h"
#include "dem/core/vec3.h"

namespace dem {

struct ActiveContacts {
    std::vector<uint32_t> i, j;       // body 1 (particle) and body 2 (particle, or wall index)
    std::vector<uint32_t> cand;       // the pair's candidate index; kNoSlot marks a hole
    std::vector<ContactPhys> phys;
    std::vector<Vec3> shear, prev_normal;  // shear history (frictional stores)
    // Written every step by the force kernels:
    std::vector<Vec3> force;          // [N] on body 2 (body 1 gets the opposite)
    std::vector<Vec3> torque1;        // [N m] on body 1 (frictional particle pairs)
    std::vector<Vec3> torque2;        // [N m] on body 2 (frictional stores)
    std::vector<Vec3> point;          // [m] contact point (walls; for the wall torques)
    std::vector<Vec3> fv;             // [N] dashpot force on body 2 (energy ledger only)

    std::size_t size() const { return i.size(); }  // slots, holes included
    std::size_t live_count() const {
        std::size_t n = 0;
        for (uint32_t c : cand) n += c != kNoSlot;
        return n;
    }
    // Gives a new contact with zero history the first hole at or after *cursor (then moves the
    // cursor past it), or a new slot at the end; returns the slot. Filling the lowest holes
    // first keeps the slots a function of which contacts are live, not of who found them.
    uint32_t place(uint32_t a, uint32_t b, uint32_t candidate, const ContactPhys& p, std::size_t* cursor) {
        while (*cursor < cand.size() && cand[*cursor] != kNoSlot) ++*cursor;
        if (*cursor == cand.size()) {
            ++*cursor;
            return add(a, b, candidate, p);
        }
        const std::size_t s = (*cursor)++;
        i[s] = a;
        j[s] = b;
        cand[s] = candidate;
        phys[s] = p;
        shear[s] = prev_normal[s] = force[s] = torque1[s] = torque2[s] = point[s] = fv[s] = Vec3{};
        return uint32_t(s);
    }
    // Appends a slot for a new contact with zero history; returns its index.
    uint32_t add(uint32_t a, uint32_t b, uint32_t candidate, const ContactPhys& p) {
        i.push_back(a);
        j.push_back(b);
        cand.push_back(candidate);
        phys.push_back(p);
        shear.emplace_back();
        prev_normal.emplace_back();
        force.emplace_back();
        torque1.emplace_back();
        torque2.emplace_back();
        point.emplace_back();
        fv.emplace_back();
        return uint32_t(i.size() - 1);
    }
    void clear() { *this = ActiveContacts{}; }
};

// Slot encoding in CandidateList::slot for particle pairs: bit 31 set = frictionless store.
inline constexpr uint32_t kSmoothBit = 1u << 31;

}  // namespace dem
