// The batch engine's state (docs/gpu.md): B independent systems stored concatenated, each with
// its own particles and parameters, advanced by one call. This part holds the particles, the
// bonds with their shear history, the follower pressure and each system's gravity, dt and local
// damping, and the host backend of their kernels; the contact and wall kernels come next (a
// system's particles must not touch yet: add() refuses what the engine cannot step).
#pragma once

#include <array>
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
    std::vector<double> r;              // [m]
    // What acts on each particle, in World's gather order (dem/contact/interaction_lists.h: by
    // reference value): bond k as body 1 (2 k) or body 2 (2 k + 1), global bond indices.
    std::vector<int64_t> link_start{0};
    std::vector<int64_t> links;
    std::vector<Vec3> pressure_slot;    // [N] the pressure's force (zero but on the nodes)
    // Per system: bonds bond_first[s] .. bond_first[s + 1], pressure nodes node_first[s] ..
    std::vector<int64_t> bond_first{0}, node_first{0};
    std::vector<double> dp;             // [Pa]
    // Per bond (global particle indices).
    std::vector<int64_t> bi, bj;
    std::vector<double> kn, ks, rest;   // [N/m], [N/m], [m]
    std::vector<Vec3> shear, prev_normal, bond_force, torque1, torque2;
    // Per pressure node (global particle indices): the node and its ring P1..P4.
    std::vector<int64_t> node;
    std::vector<std::array<int64_t, 4>> ring;

    std::size_t systems() const { return gravity.size(); }
    std::size_t particles() const { return x.size(); }
    // Appends world's particles and parameters as system B; returns B.
    std::size_t add(const World& world);
    // Writes system s's positions and velocities back into `world` (the one it was made from).
    void store(std::size_t s, World& world) const;
};

// Host backend of one step of every system: the pressure on its nodes, the bonds, the gather per
// particle in World's order, then advance_particle; systems shared among `threads` threads.
void step_host(BatchSystems& b, int threads);

// Host backend: advance_particle (dem/batch/particle_step.h) for every particle of every system,
// the systems shared among `threads` threads (each system's particles in one thread: the same
// bits for any thread count).
void advance_host(BatchSystems& b, int threads);

}  // namespace dem::batch
