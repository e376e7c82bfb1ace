#include "dem/world/wall_state.h"

#include "dem/detect/candidates.h"

namespace dem {

void WallState::move(const std::vector<Plane>& planes, const std::vector<Facet>& facets, double time, double dt) {
    plane_point.resize(planes.size());
    facet_now.resize(facets.size());
    velocity.resize(planes.size() + facets.size());
    const double t0 = time - dt, t1 = time;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        plane_point[k] = planes[k].point + planes[k].motion.displacement(time);
        velocity[k] = planes[k].motion.mean_velocity(t0, t1);
    }
    for (std::size_t k = 0; k < facets.size(); ++k) {
        const Vec3 d = facets[k].motion.displacement(time);
        for (int v = 0; v < 3; ++v) facet_now[k][v] = facets[k].vertices[v] + d;
        velocity[planes.size() + k] = facets[k].motion.mean_velocity(t0, t1);
    }
    now.resize(velocity.size());
    for (std::size_t k = 0; k < now.size(); ++k) now[k] = wall_now(planes, facets, plane_point, facet_now, velocity[k], uint32_t(k));
}

void WallState::sum_reactions(const ActiveContacts& walls, std::size_t nw) {
    force.assign(nw, Vec3{});
    torque.assign(nw, Vec3{});
    for (std::size_t s = 0; s < walls.size(); ++s) {
        if (walls.cand[s] == kNoSlot) continue;
        const uint32_t w = walls.j[s];
        add_wall_reaction(force[w], torque[w], walls.force[s], walls.point[s]);
    }
}

}  // namespace dem
