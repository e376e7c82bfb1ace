// What acts on each particle: its bonds and its live contacts, as 32-bit references kept per
// particle, so the gather reads a particle's interactions in one short list instead of
// scanning every candidate (most of which do not touch).
//
// Each list is kept sorted by reference value: its order, and hence the order in which the
// gather adds the forces, depends only on which interactions are live, not on when they
// started. So the lists need not be saved in a checkpoint: rebuilding them gives the same.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem {

struct InteractionLists {
    // Reference layout: bits 31-30 the source, bit 29 set when the particle is body 2 of the
    // pair, bits 28-0 the index in the source (a store slot or a bond).
    enum Source : uint32_t { kFrictional = 0, kFrictionless = 1, kWall = 2, kBond = 3 };
    static constexpr uint32_t kSecond = 1u << 29;
    static constexpr uint32_t kIndexMask = kSecond - 1;
    VPPDEM_HD static uint32_t make(Source s, bool second, uint32_t index) {
        return (uint32_t(s) << 30) | (second ? kSecond : 0u) | index;
    }

    // Particle i's region is ref[start[i] .. start[i] + cap[i]), its first count[i] entries in
    // use. A full region moves to the end of `ref` with twice the room (the next rebuild lays
    // the lists out afresh, in particle order).
    std::vector<uint32_t> start, count, cap, ref;

    void insert(uint32_t i, uint32_t r) {
        if (count[i] == cap[i]) {
            const uint32_t from = start[i], n = count[i];
            start[i] = uint32_t(ref.size());
            cap[i] = 2 * n + 2;
            ref.resize(ref.size() + cap[i]);
            std::copy(ref.begin() + from, ref.begin() + from + n, ref.begin() + start[i]);
        }
        uint32_t* b = &ref[start[i]];
        uint32_t* e = b + count[i]++;
        uint32_t* at = std::upper_bound(b, e, r);
        std::move_backward(at, e, e + 1);
        *at = r;
    }
    void erase(uint32_t i, uint32_t r) {
        uint32_t* b = &ref[start[i]];
        uint32_t* e = b + count[i];
        uint32_t* at = std::lower_bound(b, e, r);
        if (at == e || *at != r) return;
        std::move(at + 1, e, at);
        --count[i];
    }
};

// The gather's fixed order (World's and the batch engine's): a particle's references in list
// order, alternating between two partial sums so that the chains of dependent additions are half
// as long (the gather is bound by them). add(ref, f, t) adds one interaction's force and torque;
// the sums come out in f and t.
template <class Add>
VPPDEM_HD inline void gather_in_order(const uint32_t* refs, uint32_t m, Add&& add, Vec3& f, Vec3& t) {
    Vec3 fa, ta, fb, tb;
    uint32_t e = 0;
    for (; e + 1 < m; e += 2) {
        add(refs[e], fa, ta);
        add(refs[e + 1], fb, tb);
    }
    if (e < m) add(refs[e], fa, ta);
    f = fa + fb;
    t = ta + tb;
}

// The force and torque tables the gather reads, by source (InteractionLists::Source) and side
// (body 1, body 2). The frictionless store's torques are never written and stay zero; a wall
// contact's particle is always its body 2.
struct GatherTables {
    const Vec3* force[4];
    const Vec3* torque[4][2];
};

// One particle's force and torque from its interactions `refs` (m of them) in list order
// (gather_in_order): World's gather and the batch engine's.
VPPDEM_HD inline void gather_particle(const GatherTables& tb, const uint32_t* refs, uint32_t m, Vec3& f, Vec3& t) {
    using L = InteractionLists;
    const auto add = [&](uint32_t ref, Vec3& fo, Vec3& to) {
        const uint32_t src = ref >> 30, second = (ref & L::kSecond) ? 1 : 0, k = ref & L::kIndexMask;
        // Body 1 gets the opposite of the force on body 2: x - y and x + (-y) round alike.
        fo += tb.force[src][k] * (second ? 1.0 : -1.0);
        to += tb.torque[src][second][k];
    };
    gather_in_order(refs, m, add, f, t);
}

}  // namespace dem
