// The broad phase: new candidate lists from a cell grid whenever something moved more than half
// the skin (Verlet lists). It keeps what the rebuild test needs: the positions at the last
// rebuild (in float: half the memory of a large scene, the rounding bounded by ref_round), the
// walls' displacements then, and the largest moves since.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dem/bonds/bond_tables.h"
#include "dem/core/particles.h"
#include "dem/core/thread_team.h"
#include "dem/core/vec3.h"
#include "dem/detect/candidates.h"
#include "dem/detect/cell_grid.h"
#include "dem/walls/wall.h"

namespace dem {

struct BroadPhase {
    std::vector<FloatVec3> ref_pos;    // [m] particle positions at the last rebuild
    double ref_round = 0.0;            // [m] bound of the rounding of ref_pos
    std::vector<Vec3> wall_ref_disp;   // [m] wall displacements at the last rebuild
    double max_disp = 0.0;             // [m] largest particle move since the last rebuild (rounding included)
    double wall_move = 0.0;            // [m] largest wall move since the last rebuild
    double skin = 0.0;                 // [m] the skin of the last rebuild
    bool dirty = true;                 // rebuild at the next step (particles or walls changed by hand)
    uint64_t rebuilds = 0;
    CellGrid grid;                     // scratch of rebuild()

    // Whether the candidates must be found again before the step at `time`; measures the
    // walls' move since the rebuild (wall_move).
    bool needs_rebuild(std::size_t n, const std::vector<Plane>& planes, const std::vector<Facet>& facets, double time);

    struct Scene {
        const Particles* p = nullptr;
        const std::vector<Plane>* planes = nullptr;
        const std::vector<Facet>* facets = nullptr;
        const std::vector<Vec3>* plane_point = nullptr;               // [m] planes now
        const std::vector<std::array<Vec3, 3>>* facet_now = nullptr;  // [m] facets now
        const BondTables* bonds = nullptr;                            // bonded pairs are no candidates
        const int32_t* owner = nullptr;  // per particle its clump or -1; nullptr: no clumps (members of one clump are no candidates)
        double skin = 0.0;                                            // [m]
        double time = 0.0;                                            // [s]
        int threads = 1;
        ThreadTeam* team = nullptr;
    };
    // New candidate lists `pp` (particle pairs) and `pw` (particle-wall pairs), every slot
    // kNoSlot, and the reference state. The caller re-attaches its live contacts to them
    // (ContactSet::reattach): detection sits below the contacts and knows nothing of them.
    void rebuild(const Scene& s, CandidateList& pp, CandidateList& pw);
    // After an integration step: the largest squared move of a particle from ref_pos [m^2].
    void record_moves(double max_d2);
};

}  // namespace dem
