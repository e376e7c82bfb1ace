// Which thread does which work in the step. Each block of kernels::kBlock particles belongs to
// one thread, chosen by position (slabs along the longest axis, balanced by work), and every
// other list (bonds, contact stores) is split by the owner of its entries' first particle. So a
// thread integrates, packs, gathers and computes the contacts and bonds of one region: the data
// it reads was mostly written by itself (a cache line moved between cores costs ~200 ns on a
// 2-socket-like VM). Results never depend on it: every sum is formed per block.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/core/parallel.h"
#include "dem/core/vec3.h"

namespace dem {

class WorkShare {
public:
    // The runs of blocks of each thread (runs[t]), by list.
    BlockRuns particles, bonds, fric, smooth, walls;

    // Whether the owners were made for nt threads and n particles.
    bool valid_for(int nt, std::size_t n) const;
    // New slabs for nt threads from the particle positions and each particle's work: its
    // interaction count (links, empty when unknown) and candidate count (cand_start, the CSR
    // start of its candidates, size n + 1, or empty). bond_i: each bond's first particle.
    void assign(int nt, const std::vector<Vec3>& pos, const std::vector<uint32_t>& links,
                const std::vector<uint32_t>& cand_start, const std::vector<uint32_t>& bond_i);
    // The runs of a contact store from the first particle of each slot (body1).
    BlockRuns store_runs(const std::vector<uint32_t>& body1) const;
    // The next step assigns owners again (the particles moved: a rebuild).
    void invalidate() { owners_for_ = 0; }

private:
    std::vector<int> block_owner_;  // owner thread of each particle block
    int owners_for_ = 0;            // the thread count block_owner_ was made for
};

}  // namespace dem
