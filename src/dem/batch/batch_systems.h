// The batch engine's state (docs/gpu.md): B independent systems advanced by one call, each with
// its own particles, contacts, walls, parameters and prescribed motions. The hot state (the
// particles, the bonds with their shear history, the follower pressure's nodes) is stored
// concatenated over the batch with per-system offsets, and the per-index kernel bodies
// (dem/batch/*_step.h, VPPDEM_HD) work on it. Each system is a World that the caller keeps: the
// engine runs World's own serial phases on it (the walls' motion, the broad phase and the contact
// lifecycle, the prescribed motions, the clock; World::engine_*), so that a system's contacts get
// the slots World would give them and the gather sums in World's order: a batch gives every
// World's bits. A World in a batch is stepped by the batch only, until store() hands it back.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/world/world.h"

namespace dem::batch {

struct BatchSystems {
    // Per system: its World, its particles first[s] .. first[s + 1] (first has B + 1 entries).
    std::vector<World*> world;
    std::vector<int64_t> first{0};
    std::vector<Vec3> gravity;          // [m/s^2]
    std::vector<double> dt, lambda;     // [s], [-]
    // Per particle, concatenated.
    std::vector<Vec3> x, v, w;          // [m], [m/s] and [rad/s] at t - dt/2
    std::vector<Vec3> f, fx, t;         // [N] contact force, external force, [N m] torque
    std::vector<double> m, inv_m, inv_i;  // [kg], [1/kg], [1/(kg m^2)]
    std::vector<double> r;              // [m]
    std::vector<Vec3> pressure_slot;    // [N] the pressure's force (zero but on the nodes)
    // Per system: bonds bond_first[s] .. bond_first[s + 1], pressure nodes node_first[s] ..,
    // prescribed particles presc_first[s] ..
    std::vector<int64_t> bond_first{0}, node_first{0}, presc_first{0};
    std::vector<double> dp;             // [Pa] (World's, read at each step)
    std::vector<uint8_t> bond_point;    // 1: the system's bonds drive their shear springs at the bond point (BondArm)
    // Per bond (global particle indices).
    std::vector<int64_t> bi, bj;
    std::vector<double> kn, ks, rest;   // [N/m], [N/m], [m]
    std::vector<Vec3> shear, prev_normal, bond_force, torque1, torque2;
    // Per pressure node (global particle indices): the node and its ring P1..P4.
    std::vector<int64_t> node;
    std::vector<std::array<int64_t, 4>> ring;
    // The prescribed particles (indices within their system), copied from World after it moved them.
    std::vector<uint32_t> prescribed;

    std::size_t systems() const { return gravity.size(); }
    // System s's foil carries its underpressure dp[s] (its pressure nodes' forces join the gather).
    bool with_pressure(std::size_t s) const { return dp[s] != 0.0 && node_first[s + 1] > node_first[s]; }
    std::size_t particles() const { return x.size(); }
    // Appends `world` as system B and returns B. The World must outlive the batch's use of it (its
    // own threads, params.threads, serve its broad phase). Refused: clumps.
    std::size_t add(World& world);
    // Hands system s back to its World: particles (state, forces), bonds' state and history.
    void store(std::size_t s) const;
};

// The underpressure a system's foil carries [Pa]: World's, and none without pressure nodes (read
// at each step: a driver may change it between steps, the air inside).
inline double world_underpressure(const World& wd) { return wd.pressure.nodes.empty() ? 0.0 : wd.pressure.dp; }

// The two halves of system s's step on the host (World::compute_forces(), World::integrate()):
// between them World's wall reactions, its prescribed particles' forces, its energy ledger and
// its parameters are current and may be read or changed (reset_energy(), pressure.dp).
void step_forces(BatchSystems& b, std::size_t s);
void step_motion(BatchSystems& b, std::size_t s);

// Host backend: `steps` steps of every system, the systems shared among `threads` threads (each
// system in one thread: the same bits for any thread count).
void step_host(BatchSystems& b, int threads, uint64_t steps = 1);

}  // namespace dem::batch
