// The Verlet lists' rules, written once for World (BroadPhase, ContactSet) and the batch
// engine's device, which runs them between its layouts: when the candidates must be found again,
// how far the touch test must look, and when the contact stores are laid out again without a
// rebuild. Every rule is a comparison of the same doubles in the same order on both, so both take
// the same decisions at the same steps (a rebuild one step apart would change the slot order,
// hence the trajectory).
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>

#include "dem/core/hd.h"

namespace dem {

// The particles alone moved so far that two of them may have closed the skin [m]: max_disp is the
// largest move of a particle since the rebuild (its rounding included).
VPPDEM_HD inline bool particles_past_skin(double max_disp, double skin) { return 2.0 * max_disp > skin; }

// A particle and a wall may have closed the skin: wall_move is the largest move of a wall since
// the rebuild [m].
VPPDEM_HD inline bool walls_past_skin(double max_disp, double wall_move, double skin) { return max_disp + wall_move > skin; }

// max_disp after a step whose largest squared move from the rebuild positions was max_d2 [m^2];
// ref_round bounds the rounding of those positions (kept in float) [m].
VPPDEM_HD inline double max_disp_after(double max_d2, double ref_round) { return std::sqrt(max_d2) + ref_round; }

// How far [m] the touch test looks at the candidates' gaps at the rebuild: two particles that
// each moved max_disp (pairs), or a particle and a wall (walls), plus a margin for the rounding of
// the gaps and of the moves (World::engine_reach).
struct Reaches {
    float pair = 0, wall = 0;
};
VPPDEM_HD inline Reaches touch_reaches(double max_disp, double wall_move, double skin) {
    const double margin = 1e-9 * skin;
    return {float(2.0 * max_disp + margin), float(max_disp + wall_move + margin)};
}

// Where contacts come and go much faster than rebuilds happen (a collapsing column), the holes of
// opened contacts are dropped once they are a quarter of the slots (plus a floor), so that the
// kernels do not sweep mostly empty stores (ContactSet's stores; World::update_candidates).
VPPDEM_HD inline bool stores_need_compaction(uint64_t holes, uint64_t store_slots) { return holes > store_slots / 4 + 256; }

}  // namespace dem
