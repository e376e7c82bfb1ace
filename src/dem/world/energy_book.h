// The energy ledger's bookkeeping (docs/energy.md): the kernels and the integrator leave their
// terms summed per fixed block; account() adds the blocks in order and books them, back halves
// and the contacts' terms on [t_n - dt, t_n], forward halves pending until the next step.
// Everything is summed in a fixed order: the same numbers for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/world/contact_set.h"
#include "dem/core/energy.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/core/vec3.h"
#include "dem/walls/wall.h"
#include "dem/world/wall_state.h"

namespace dem {

struct EnergyBook {
    EnergyLedger ledger;
    bool ready = false;  // compute_forces() filled the block sums below (integrate() books them)
    // Block sums of the step's kernels: kernels::kPairSums per block of each contact store,
    // one per block of bonds, kernels::kParticleSums per block of particles and per block of
    // clumps (integrate()).
    std::vector<double> fric, smooth, walls, bonds, particles, clumps;
    double prescribed[2] = {};        // [J] boundary work of prescribed particles: back, forward half
    // The dashpots' forward halves per block of the frictional, frictionless and wall stores, in
    // that order (dashpot_forward_work, lane_block_sum), when an engine formed them (then
    // `dashpot_blocks_given`; account() forms them from the stores otherwise).
    std::vector<double> dashpot_blocks;
    bool dashpot_blocks_given = false;
    std::vector<Vec3> wall_vel_next;  // scratch of account()

    // Room for the block sums of the contact stores and bonds (every block is written).
    void size_blocks(const ContactSet& c, std::size_t bond_count);

    struct Step {
        const Particles* p = nullptr;
        const std::vector<Material>* materials = nullptr;
        const std::vector<Plane>* planes = nullptr;
        const std::vector<Facet>* facets = nullptr;
        const WallState* walls = nullptr;  // reactions and velocities of the step
        ContactSet* contacts = nullptr;    // stores (dashpot forces); its dropped shear energy is booked and reset
        double time = 0;                   // [s] t_n + dt (after integration)
        double dt = 0;                     // [s]
        double t_n = 0;                    // [s] the time the forces were computed at
    };
    // Adds step n (forces at t_n, velocities v(t_n -/+ dt/2)) to the ledger.
    void account(const Step& s);
    // Each wall's velocity over the next step [m/s] (the forward half of its work), for the
    // clock's time after integration (Step::time).
    static void next_wall_velocities(const std::vector<Plane>& planes, const std::vector<Facet>& facets, double time,
                                     double dt, std::vector<Vec3>& v_next);
};

}  // namespace dem
