// The light candidate list: pairs closer than the sum of radii plus the skin, found by the
// broad phase at each rebuild, stored per particle in CSR form. Most candidates never touch
// (in a loose packing or a free fall, none do), so a candidate costs 8 bytes (its partner and
// its contact slot) plus 4 for the reverse table; the shear history and the forces live only
// with the pairs that touch (ActiveContacts). Why CSR per particle rather than a list of
// 64-bit pair keys: half the memory, and the gather reads a particle's contacts contiguously.
#pragma once

#include <cstdint>
#include <vector>

namespace dem {

inline constexpr uint32_t kNoSlot = 0xffffffffu;  // candidate without a live contact

struct CandidateList {
    // Particle i's partners are other[start[i] .. start[i+1]), ascending: particles j > i for
    // particle pairs, wall indices (planes first, then facets) for wall pairs.
    std::vector<uint32_t> start;   // size n + 1
    std::vector<uint32_t> other;
    std::vector<uint32_t> slot;    // the pair's live contact (ContactStores::slot encoding) or kNoSlot
    // Particle pairs only: candidates in which j is the partner, for the gather:
    // rentry[rstart[j] .. rstart[j+1]) are candidate indices, ascending.
    std::vector<uint32_t> rstart, rentry;

    std::size_t size() const { return other.size(); }
    void clear() { *this = CandidateList{}; }
};

}  // namespace dem
