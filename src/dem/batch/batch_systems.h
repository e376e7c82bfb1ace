// The batch engine's state (docs/gpu.md): B independent systems stored concatenated, each with
// its own particles and parameters, advanced by one call. This first part holds what the
// integration needs (the particles' state, masses, forces; each system's gravity, dt and local
// damping) and its host backend; the contact, bond, wall and pressure kernels come next.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/world/world.h"

namespace dem::batch {

struct BatchSystems {
    // Per system: its particles are first[s] .. first[s + 1] (first has B + 1 entries).
    std::vector<int64_t> first{0};
    std::vector<Vec3> gravity;          // [m/s^2]
    std::vector<double> dt, lambda;     // [s], [-]
    // Per particle, concatenated.
    std::vector<Vec3> x, v, w;          // [m], [m/s] and [rad/s] at t - dt/2
    std::vector<Vec3> f, fx, t;         // [N] contact force, external force, [N m] torque
    std::vector<double> m, inv_m, inv_i;  // [kg], [1/kg], [1/(kg m^2)]

    std::size_t systems() const { return gravity.size(); }
    std::size_t particles() const { return x.size(); }
    // Appends world's particles and parameters as system B; returns B.
    std::size_t add(const World& world);
    // Writes system s's positions and velocities back into `world` (the one it was made from).
    void store(std::size_t s, World& world) const;
};

// Host backend: advance_particle (dem/batch/particle_step.h) for every particle of every system,
// the systems shared among `threads` threads (each system's particles in one thread: the same
// bits for any thread count).
void advance_host(BatchSystems& b, int threads);

}  // namespace dem::batch
