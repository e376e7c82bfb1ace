#include "dem/core/pressure.h"

#include <cstring>

#include "dem/core/parallel.h"

namespace dem {

void PressureForces::prepare(const MembranePressure& mp, std::size_t n, bool on, bool needed) {
    if (!needed) return;
    if (force.size() != n || on != was_on_ || mp.nodes.size() != seen_.size() ||
        (on && std::memcmp(mp.nodes.data(), seen_.data(), mp.nodes.size() * sizeof(PressureNode)) != 0) ||
        mp.fans.node != seen_fans_) {
        force.assign(n, Vec3{});
        seen_ = mp.nodes;
        seen_fans_ = mp.fans.node;
        was_on_ = on;
    }
}

void PressureForces::apply(const MembranePressure& mp, const std::vector<Vec3>& pos) {
    const auto [k0, k1] = thread_range(int64_t(mp.nodes.size()), thread_id(), thread_count());
    // Each node appears once in the list, so every iteration writes its own slot.
    for (int64_t k = k0; k < k1; ++k) {
        const PressureNode& q = mp.nodes[k];
        force[q.node] = pressure_force(pos[q.ring[0]], pos[q.ring[1]], pos[q.ring[2]], pos[q.ring[3]], mp.dp);
    }
    const auto [f0, f1] = thread_range(int64_t(mp.fans.node.size()), thread_id(), thread_count());
    for (int64_t k = f0; k < f1; ++k) force[mp.fans.node[k]] = -(fan_area(pos, mp.fans, std::size_t(k)) * mp.dp);
}

}  // namespace dem
