// A probe of forces over steps, for a caller that reads forces every step of a window (a damper's
// sample window) while the batch engine's device runs the steps by itself (DeviceBatch::run): over
// the steps whose time exceeds `from`, the sum of one wall's reaction and the sum of a set of
// particles' forces, added in step order, each step's particles summed in their order from +0:
// the bits of a caller that adds World::wall_force(wall) and the particles' forces after each
// compute_forces() (the sum's components are independent, so its z is a sum of the z's).
#pragma once

#include <cstdint>

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem::batch {

struct ForceProbe {
    double from = 1e300;            // [s] steps at a time above this are summed (1e300: none)
    uint32_t wall = 0xffffffffu;    // the wall whose reaction is summed (planes first, then facets; none)
    Vec3 wall_sum;                  // [N s/dt] the wall's reaction summed over the steps
    Vec3 particle_sum;              // [N s/dt] the particles' summed force summed over the steps
    uint64_t count = 0;             // steps summed
};

// One step at `time` [s] into p: the wall's reaction (null: none), the forces of the n particles
// idx[0..n) of `force` (indices from `base`).
VPPDEM_HD inline void probe_step(ForceProbe& p, double time, const Vec3* wall_reaction, const Vec3* force,
                                 const uint32_t* idx, uint32_t n, int64_t base) {
    if (!(time > p.from)) return;
    if (wall_reaction) p.wall_sum += *wall_reaction;
    Vec3 f;
    for (uint32_t k = 0; k < n; ++k) f += force[base + idx[k]];
    p.particle_sum += f;
    ++p.count;
}

}  // namespace dem::batch
