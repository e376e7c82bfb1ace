// The light candidate list: pairs closer than the sum of radii plus the skin, found by the
// broad phase at each rebuild, stored per particle in CSR form. Most candidates never touch
// (in a loose packing or a free fall, none do), so a candidate costs 12 bytes (its partner,
// its contact slot, its gap at the rebuild); the shear history and the forces live only with
// the pairs that touch (ActiveContacts). Why CSR per particle rather than a list of 64-bit
// pair keys: less memory, and a particle's candidates are read contiguously.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/core/hd.h"

namespace dem {

inline constexpr uint32_t kNoSlot = 0xffffffffu;  // candidate without a live contact

// A candidate the touch test looks at (ContactSet::find_new, World's filter and the batch
// engine's kernels): no live contact, and a gap at the rebuild [m] below `reach` [m].
VPPDEM_HD inline bool open_candidate(uint32_t slot, float gap, float reach) { return slot == kNoSlot && gap < reach; }

struct CandidateList {
    // Particle i's partners are other[start[i] .. start[i+1]), ascending: particles j > i for
    // particle pairs, wall indices (planes first, then facets) for wall pairs.
    std::vector<uint32_t> start;   // size n + 1
    std::vector<uint32_t> other;
    std::vector<uint32_t> slot;    // the pair's live contact (kSmoothBit marks the frictionless store) or kNoSlot
    // [m] surface gap at the rebuild, rounded down. Between rebuilds no particle moves more
    // than World's max_disp_, so a pair whose gap exceeds twice that cannot touch yet and is
    // not tested (walls: max_disp_ plus the wall's own move).
    std::vector<float> gap;

    std::size_t size() const { return other.size(); }
    void clear() { *this = CandidateList{}; }
};

}  // namespace dem
