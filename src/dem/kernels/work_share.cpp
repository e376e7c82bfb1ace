#include "dem/kernels/work_share.h"

#include <algorithm>

#include "dem/kernels/kernels.h"

namespace dem {

bool WorkShare::valid_for(int nt, std::size_t n) const {
    return owners_for_ == nt && block_owner_.size() == std::size_t(kernels::block_count(n));
}

void WorkShare::assign(int nt, const std::vector<Vec3>& pos, const std::vector<uint32_t>& links,
                       const std::vector<uint32_t>& cand_start, const std::vector<uint32_t>& bond_i) {
    nt = std::max(1, nt);
    const int64_t n = int64_t(pos.size()), nb = kernels::block_count(pos.size());
    owners_for_ = nt;
    block_owner_.assign(std::size_t(nb), 0);
    if (nt > 1 && n > 0) {
        // Slabs along the longest extent of the packing, each with about 1/nt of the work
        // (a block's work: its particles plus their bonds and candidates).
        Vec3 lo = pos[0], hi = lo;
        for (const Vec3& x : pos)
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], x[d]);
                hi[d] = std::max(hi[d], x[d]);
            }
        int axis = 0;
        for (int d = 1; d < 3; ++d)
            if (hi[d] - lo[d] > hi[axis] - lo[axis]) axis = d;
        std::vector<double> key(std::size_t(nb), 0.0), weight(std::size_t(nb), 0.0);
        for (int64_t i = 0; i < n; ++i) {
            key[i / kernels::kBlock] += pos[i][axis];
            // Integration, the gather (live interactions) and the candidate tests.
            weight[i / kernels::kBlock] +=
                4.0 + (links.size() == std::size_t(n) ? double(links[i]) : 0.0) +
                (cand_start.size() == std::size_t(n + 1) ? 0.5 * double(cand_start[i + 1] - cand_start[i]) : 0.0);
        }
        std::vector<int64_t> order(static_cast<std::size_t>(nb));
        for (int64_t b = 0; b < nb; ++b) {
            key[b] /= double(std::min(n, (b + 1) * kernels::kBlock) - b * kernels::kBlock);
            order[b] = b;
        }
        std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return key[a] < key[b]; });
        double total = 0.0;
        for (double w : weight) total += w;
        double before = 0.0;
        for (int64_t b : order) {
            block_owner_[b] = std::min(nt - 1, int((before + 0.5 * weight[b]) / total * nt));
            before += weight[b];
        }
    }
    particles = runs_of(nb, nt, [&](int64_t b) { return block_owner_[b]; });
    bonds = runs_of(kernels::block_count(bond_i.size()), nt,
                    [&](int64_t b) { return block_owner_[bond_i[b * kernels::kBlock] / kernels::kBlock]; });
}

BlockRuns WorkShare::store_runs(const std::vector<uint32_t>& body1) const {
    // A block of slots goes to the owner of its first slot's particle (slots are in particle
    // order after each rebuild; the few added since are wherever they fall).
    return runs_of(kernels::block_count(body1.size()), owners_for_,
                   [&](int64_t b) { return block_owner_[body1[b * kernels::kBlock] / kernels::kBlock]; });
}

}  // namespace dem
