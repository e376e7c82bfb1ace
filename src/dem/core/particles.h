// Spheres as struct-of-arrays. The integrator and contact loops touch only the hot arrays
// (pos, vel, angvel, force, torque, radius, inverse mass/inertia); names and tracking
// flags stay in the cold part.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dem/core/vec3.h"

namespace dem {

// Per-particle flag bits.
enum ParticleFlag : uint32_t {
    kFixed = 1u << 0,       // never moves (all six degrees of freedom blocked)
    kPrescribed = 1u << 1,  // translation follows a Motion (see World::prescribed); no rotation
    kTracked = 1u << 2,     // written to tracked output
    kClumpMember = 1u << 3, // a member sphere of a clump (dem/clumps/clumps.h): moved with it
};

struct SphereDef {
    Vec3 position;          // [m]
    Vec3 velocity;          // [m/s]
    Vec3 angular_velocity;  // [rad/s]
    double radius = 0.01;   // [m]
    uint32_t material = 0;  // index into World::materials
    uint32_t mask = 1;      // collision mask: two bodies interact when their masks share a bit
    uint32_t flags = 0;     // ParticleFlag bits
};

struct Particles {
    // hot
    std::vector<Vec3> pos;          // [m]
    std::vector<Vec3> vel;          // [m/s] at the half step t - dt/2 (leapfrog)
    std::vector<Vec3> angvel;       // [rad/s] at the half step
    std::vector<Vec3> force;        // [N] gathered from contacts this step (without gravity)
    std::vector<Vec3> torque;       // [N m]
    // [N] extra external force per particle, set by the application; empty: none (most scenes:
    // the integrator then reads nothing). Resize to size() to use it.
    std::vector<Vec3> ext_force;
    std::vector<double> radius;     // [m]
    std::vector<double> mass;       // [kg]
    std::vector<double> inv_mass;   // [1/kg], 0 for fixed and prescribed particles
    std::vector<double> inv_inertia;  // [1/(kg m^2)], solid sphere I = 2/5 m r^2; 0 if not free
    std::vector<uint32_t> material;
    std::vector<uint32_t> mask;
    std::vector<uint32_t> flags;
    // cold
    std::vector<int32_t> motion;    // index into World::motions for kPrescribed, else -1
    // [m] reference position of prescribed particles (position = ref_pos + motion displacement);
    // empty until a particle is made prescribed (World::set_prescribed sizes it).
    std::vector<Vec3> ref_pos;

    std::size_t size() const { return pos.size(); }
};

// Whether particle i moves under forces: free spheres and clump members (whose inverse mass is
// 0 because their clump, not the particle integrator, moves them).
inline bool moves(const Particles& p, std::size_t i) { return p.inv_mass[i] != 0.0 || (p.flags[i] & kClumpMember); }

// The kinetic energy of some particles from their stored half-step velocities (vel, angvel), as
// the applications read it to tell a sample at rest: translation over the free particles
// (inv_mass != 0; fixed and prescribed particles and clump members are left out: a clump's is
// World::clump_kinetic_energy), rotation over those free to rotate (inv_inertia != 0), each summed
// in index order. Not the energy ledger's K (dem/core/energy.h), which averages the two half
// steps around t.
struct KineticEnergy {
    double translation = 0;  // [J] sum 1/2 m v^2
    double rotation = 0;     // [J] sum 1/2 I w^2, I = 1 / inv_inertia
    double total() const { return translation + rotation; }
};
// The particles named by `ids` (a foil's nodes), in that order.
KineticEnergy kinetic_energy(const Particles& p, std::span<const uint32_t> ids);
// The particles first .. end - 1 (a scene's grains).
KineticEnergy kinetic_energy(const Particles& p, uint32_t first, uint32_t end);

}  // namespace dem
