// The wall contacts' kernel (dem/kernels/kernels.h, wall_pairs): few contacts (caps, a funnel), so
// scalar code over the calling thread's blocks of slots, with the same contact law as the pair
// kernels and the energy terms summed per block in slot order.
#include <algorithm>

#include "dem/kernels/kernels.h"
#include "dem/kernels/step_bodies.h"

namespace dem::kernels {

namespace {

template <bool kEnergy> void wall_pairs_impl(const WallPairArgs& a) {
    const Particles& p = *a.p;
    ActiveContacts& ws = *a.c;
    const std::vector<WallNow>& now = *a.now;
    const double dt = a.dt;
    const int64_t ns = int64_t(ws.size());
    std::vector<uint32_t>& opened = *a.opened;
    opened.clear();
    for (const auto& [b0, b1] : *a.blocks)
    for (int64_t b = b0; b < b1; ++b) {
        double sum[kPairSums] = {};
        for (int64_t s = b * kBlock; s < std::min(ns, (b + 1) * kBlock); ++s) {
            if (ws.cand[s] == kNoSlot) continue;
            const uint32_t i = ws.i[s], w = ws.j[s];
            // The wall body of dem/kernels/step_bodies.h (the batch engine's too).
            const WallNow& wl = now[w];
            PairEnergy en;
            const PairOut o = wall_pair<kEnergy>({p.pos[i], p.vel[i], p.angvel[i], p.radius[i]}, wl, ws.phys[s], dt,
                                                 ws.shear[s], ws.prev_normal[s], &en);
            ws.force[s] = o.force;
            ws.torque2[s] = o.torque2;
            if (!o.touch) {
                if constexpr (kEnergy) sum[kRelease] += en.release;
                ws.fv[s] = Vec3{};
                opened.push_back(uint32_t(s));
                continue;
            }
            ws.point[s] = o.point;
            if constexpr (kEnergy) {
                sum[kElastic] += en.elastic;
                sum[kSlip] += en.slip;
                sum[kViscous] += en.viscous;
                ws.fv[s] = en.fv;
            }
        }
        if constexpr (kEnergy) std::copy(sum, sum + kPairSums, a.energy + b * kPairSums);
    }
}

}  // namespace

void wall_pairs(const WallPairArgs& a) {
    if (a.energy) wall_pairs_impl<true>(a);
    else wall_pairs_impl<false>(a);
}

}  // namespace dem::kernels
