// The walls as the step sees them: where each is at time t and how fast it moved over the last
// step (from its Motion), and the reactions the particles exert on it (summed from the wall
// contacts after the force kernels).
#pragma once

#include <array>
#include <vector>

#include "dem/contact/active_contacts.h"
#include "dem/core/hd.h"
#include "dem/core/vec3.h"
#include "dem/walls/wall.h"
#include "dem/walls/wall_now.h"

namespace dem {

struct WallState {
    std::vector<Vec3> plane_point;                 // [m] a point of each plane now
    std::vector<std::array<Vec3, 3>> facet_now;    // [m] each facet's vertices now
    std::vector<Vec3> velocity;                    // [m/s] each wall's mean velocity over the last step
    std::vector<WallNow> now;                      // each wall as the wall bodies read it (wall_now)
    std::vector<Vec3> force, torque;               // [N], [N m] (about the origin) particles on each wall

    // The walls at `time` (planes first, then facets); the velocity over [time - dt, time]
    // matches the particles' half-step velocity v(t - dt/2). Also `now`, from these.
    void move(const std::vector<Plane>& planes, const std::vector<Facet>& facets, double time, double dt);
    // Reactions from the live wall contacts of `walls` for nw walls, in slot order.
    void sum_reactions(const ActiveContacts& walls, std::size_t nw);
};

// One live wall contact's reaction added to its wall's force [N] and torque about the origin
// [N m]: the contact's force f on the particle [N] at the contact point [m] (sum_reactions' body,
// also the batch engine's device's, which adds a wall's contacts in slot order as sum_reactions).
VPPDEM_HD inline void add_wall_reaction(Vec3& force, Vec3& torque, const Vec3& f, const Vec3& point) {
    force -= f;
    torque += cross(point, -f);
}

// Wall k (planes first, then facets) as the wall bodies read it (dem/kernels/step_bodies.h):
// WallState::now, which World's wall kernel and touch test and the batch engine's kernels read.
inline WallNow wall_now(const std::vector<Plane>& planes, const std::vector<Facet>& facets,
                        const std::vector<Vec3>& plane_point, const std::vector<std::array<Vec3, 3>>& facet_now,
                        const Vec3& velocity, uint32_t k) {
    WallNow wl;
    const uint32_t np = uint32_t(planes.size());
    wl.plane = k < np;
    if (wl.plane) {
        wl.point = plane_point[k];
        wl.normal = planes[k].normal;
        wl.one_sided = planes[k].one_sided;
    } else {
        const std::array<Vec3, 3>& v = facet_now[k - np];
        wl.v0 = v[0];
        wl.v1 = v[1];
        wl.v2 = v[2];
        wl.one_sided = facets[k - np].one_sided;
    }
    wl.velocity = velocity;
    return wl;
}

}  // namespace dem
