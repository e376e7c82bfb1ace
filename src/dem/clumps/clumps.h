// Clumps: rigid grains made of overlapping spheres (dem/clumps/clump_shape.h), as struct-of-
// arrays. The members are ordinary particles (flag kClumpMember) that carry the contacts; the
// integrator leaves them alone (inverse mass 0) and World::advance_clumps() moves each clump as
// one rigid body and places its members. A member's `mass` is its clump's mass, so that a
// contact's reduced mass is the two bodies' (dem/contact/contact_physics.h).
#pragma once

#include <cstdint>
#include <vector>

#include "dem/clumps/quaternion.h"
#include "dem/core/vec3.h"

namespace dem {

struct ClumpDef {
    Vec3 position;            // [m] centre of mass
    Quat orientation;         // principal frame -> world frame
    Vec3 velocity;            // [m/s]
    Vec3 angular_velocity;    // [rad/s] world frame
    uint32_t material = 0;    // index into World::materials (its density sets the mass)
    uint32_t mask = 1;        // collision mask of the members
};

struct Clumps {
    // per clump (hot)
    std::vector<Vec3> pos;       // [m] centre of mass at t
    std::vector<Vec3> vel;       // [m/s] at t - dt/2 (leapfrog)
    std::vector<Quat> q;         // orientation at t (principal frame -> world)
    std::vector<Vec3> mom;       // [kg m^2/s] angular momentum, world frame, at t - dt/2
    std::vector<Vec3> angvel;    // [rad/s] world frame at t - dt/2 (from mom; the damping's sign)
    std::vector<Vec3> inertia;   // [kg m^2] principal moments
    std::vector<double> mass;    // [kg]
    std::vector<double> inv_mass;  // [1/kg]
    // members: particles member[start[c] .. start[c + 1]), at rel[k] in the principal frame
    std::vector<uint32_t> start{0};
    std::vector<uint32_t> member;
    std::vector<Vec3> rel;       // [m]
    // per particle: its clump, or -1 (empty while there are no clumps)
    std::vector<int32_t> owner;

    std::size_t size() const { return pos.size(); }
    bool empty() const { return pos.empty(); }
};

}  // namespace dem
