// The walls as the step sees them: where each is at time t and how fast it moved over the last
// step (from its Motion), and the reactions the particles exert on it (summed from the wall
// contacts after the force kernels).
#pragma once

#include <array>
#include <vector>

#include "dem/contact/active_contacts.h"
#include "dem/core/vec3.h"
#include "dem/walls/wall.h"

namespace dem {

struct WallState {
    std::vector<Vec3> plane_point;                 // [m] a point of each plane now
    std::vector<std::array<Vec3, 3>> facet_now;    // [m] each facet's vertices now
    std::vector<Vec3> velocity;                    // [m/s] each wall's mean velocity over the last step
    std::vector<Vec3> force, torque;               // [N], [N m] (about the origin) particles on each wall

    // The walls at `time` (planes first, then facets); the velocity over [time - dt, time]
    // matches the particles' half-step velocity v(t - dt/2).
    void move(const std::vector<Plane>& planes, const std::vector<Facet>& facets, double time, double dt);
    // Reactions from the live wall contacts of `walls` for nw walls, in slot order.
    void sum_reactions(const ActiveContacts& walls, std::size_t nw);
};

}  // namespace dem
