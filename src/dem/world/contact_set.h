// The contacts of a World and their lifecycle: the candidate lists the broad phase found, the
// stores of the live (touching) contacts, and each particle's interaction list. Between two
// rebuilds a contact opens when a candidate starts touching (find_new, then activate_new, in
// candidate order) and closes when the force kernels find its pair apart (release_opened);
// compact() lays the stores out again in candidate order. Every step does the same for any
// thread count: the threads only find, the serial parts decide the slots.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "dem/bonds/bond_tables.h"
#include "dem/contact/active_contacts.h"
#include "dem/detect/candidates.h"
#include "dem/contact/contact_physics.h"
#include "dem/contact/interaction_lists.h"
#include "dem/kernels/kernels.h"
#include "dem/core/particles.h"
#include "dem/core/vec3.h"
#include "dem/walls/wall.h"

namespace dem {

// A touching pair as the World reports it (World::for_each_touching).
struct TouchingContact {
    uint32_t i = 0, j = 0;  // particle i; particle j, or wall j when `wall`
    bool wall = false;
    ContactPhys phys;
    Vec3 force;             // [N] on body 2 (the wall's contact: on the particle)
    Vec3 shear;             // [N] shear spring (zero for frictionless pairs)
};

struct ContactSet {
    CandidateList pp, pw;               // particle pairs, particle-wall pairs
    ActiveContacts fric, smooth, walls; // live contacts: frictional, frictionless, wall
    InteractionLists links;             // per particle: bonds and live contacts (the gather's input)
    std::size_t holes = 0;              // slots freed since the last compaction
    double dropped_shear_energy = 0;    // [J] shear springs dropped by a physics change (for the ledger)

    // Per thread: candidates found touching without a slot (particle, candidate), scratch of
    // the search, and the slots whose pair the kernels found open (per store).
    std::vector<std::vector<uint32_t>> new_pp, new_pw, scratch, pair_i, pair_j, pair_hits;
    std::vector<std::vector<uint32_t>> opened_fric, opened_smooth, opened_walls;

    // Per-thread lists for nt threads.
    void prepare_threads(int nt);

    struct FindArgs {
        const Particles* p = nullptr;
        kernels::PackedParticle* packed = nullptr;  // the pair kernels' records (nullptr: none yet)
        bool repack = false;                        // write `packed` first (the particles changed by hand)
        const std::vector<Plane>* planes = nullptr;
        const std::vector<Facet>* facets = nullptr;
        const std::vector<WallNow>* wall_now = nullptr;               // the walls now (WallState::now)
        float pair_reach = 0, wall_reach = 0;  // [m] largest gap a candidate may have closed since the rebuild
        const std::vector<std::pair<int64_t, int64_t>>* blocks = nullptr;  // this thread's particle blocks
    };
    // Inside the step's parallel region, over the calling thread's particle blocks: the
    // candidates without a slot that touch now (into new_pp, new_pw of this thread).
    void find_new(const FindArgs& a);
    // Serial: the found contacts get slots in candidate order (so the slots do not depend on
    // which thread found them), filling the lowest holes first.
    void activate_new(const ContactPhysics& phys);
    // Serial: the slots whose pair opened this step are freed.
    void release_opened();
    // Every live contact into fresh stores in candidate order (holes dropped); with `refresh`
    // their coefficients are recomputed first (and a pair whose friction became zero or
    // nonzero changes store, a dropped shear spring booked in dropped_shear_energy).
    void compact(bool refresh, const ContactPhysics& phys, const BondTables& bonds, std::size_t n);
    // The per-particle interaction lists from the bonds and the live contacts.
    void build_interaction_lists(const BondTables& bonds, std::size_t n);
    // After the broad phase wrote new candidate lists: each live contact is attached to its
    // pair's new candidate, or dropped with its history when the pair is no longer a candidate
    // (its masks, bonds or fixity changed).
    void reattach();
    // Drops the contacts with walls w >= first_wall (removed facets), their history and their
    // candidates: until the next broad phase the lists must name only walls that exist (a
    // checkpoint may be taken in between, and its reader checks them).
    void drop_wall_contacts_from(uint32_t first_wall);
    // Particles added since the last broad phase (up to n in all) get empty candidate ranges,
    // so that the lists keep their shape, one range per particle, until the next step rebuilds
    // them (a checkpoint taken right after a re-fill's grains were added must load).
    void cover_particles(std::size_t n);
    // Walls w >= first move up by one (a plane inserted before the facets): the live contacts and
    // the candidates with them follow, the lists stay ascending.
    void shift_walls_from(uint32_t first);

    std::size_t particle_live_count() const { return fric.live_count() + smooth.live_count(); }
    std::size_t live_count() const { return particle_live_count() + walls.live_count(); }
    std::size_t store_slots() const { return fric.size() + smooth.size() + walls.size(); }

    // Calls f(const TouchingContact&) for every touching pair, particle pairs first, each list
    // in candidate order (particle i, then partner).
    template <class F> void for_each_touching(F&& f) const;

    // Consistency of lists and stores for n particles and nw walls: nullptr, or what is wrong.
    const char* broken_rule(std::size_t n, std::size_t nw) const;
};

template <class F> void ContactSet::for_each_touching(F&& f) const {
    const auto visit = [&](const CandidateList& cl, bool wall) {
        for (std::size_t i = 0; i + 1 < cl.start.size(); ++i)
            for (uint32_t k = cl.start[i]; k < cl.start[i + 1]; ++k) {
                const uint32_t s = cl.slot[k];
                if (s == kNoSlot) continue;
                const bool is_smooth = !wall && (s & kSmoothBit);
                const ActiveContacts& a = wall ? walls : is_smooth ? smooth : fric;
                const uint32_t c = s & ~kSmoothBit;
                f(TouchingContact{uint32_t(i), cl.other[k], wall, a.phys[c], a.force[c], a.shear[c]});
            }
    };
    visit(pp, false);
    visit(pw, true);
}

}  // namespace dem
