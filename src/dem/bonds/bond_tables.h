// Each particle's bonds, derived from the BondList: the gather reads a particle's bonds from
// here, and the broad phase skips bonded pairs (a bonded pair never also acts as a contact).
// Rebuilt whenever bonds are added (World marks them dirty); never saved, since it follows
// from the list.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/bonds/bond_list.h"

namespace dem {

struct BondTables {
    static constexpr uint32_t kSideBit = 1u << 31;  // in `entries`: this particle is body 2
    // Particle i's bonds are entries[start[i] .. start[i+1]) (bond index | kSideBit when i is
    // its body 2), in bond order; partner[k] is the other particle of entries[k].
    std::vector<uint32_t> start, entries, partner;

    bool built_for(std::size_t n) const { return start.size() == n + 1; }

    void build(std::size_t n, const BondList& b) {
        const std::size_t nb = b.size();
        start.assign(n + 1, 0);
        for (std::size_t k = 0; k < nb; ++k) {
            ++start[b.i[k] + 1];
            ++start[b.j[k] + 1];
        }
        for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
        entries.resize(start.back());
        partner.resize(start.back());
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t k = 0; k < nb; ++k) {
            const uint32_t i = b.i[k], j = b.j[k];
            partner[fill[i]] = j;
            entries[fill[i]++] = uint32_t(k);
            partner[fill[j]] = i;
            entries[fill[j]++] = uint32_t(k) | kSideBit;
        }
    }
};

}  // namespace dem
