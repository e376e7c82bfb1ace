// Suction under a membrane that lies on an object (issue 61): the third holding mechanism of a
// jamming gripper (Brown et al., PNAS 2010), beside friction and geometric interlocking. Where
// the membrane lies on the object it seals; when the object is pulled off, the gap between them
// opens and its air, cut off from the surroundings, expands and drops below the ambient pressure,
// so the surroundings press the object against the bag.
//
// The model, per membrane particle of the footprint (the particles within `capture` of the
// object's surface when the seal forms: SuctionSeal):
//   gap      g_i = g0_i + (x_i - x0_i - u) . n_i: the surface gap at the capture (distance to the
//            object less r_f, < 0 an overlap) plus the particle's move from the object along the
//            object's outward normal n_i there (u: the object's translation since the capture).
//            First order in the opening: suction acts over openings far smaller than the bag.
//   open     g_i > h0 / 100: the particle has left the object's surface; closed ones touch it and seal.
//   volume   V_i = a_i (h0 + max(g_i, 0)): a_i the particle's tributary area, h0 the air film
//            trapped between membrane and object where they lie together (`gap`).
//   pockets  the open particles connected through the membrane's one-rings, each with one
//            pressure p: its air p V (the sum of its elements' p_i V_i) spread over its volume
//            (isothermal: slow next to sound). Closed particles seal; a pocket with open
//            particles on the footprint's rim (a neighbour off the footprint) leaks through each
//            of them as through a slit of height g_i, as wide as long, by plane Poiseuille flow
//            of an isothermal gas: d(pV)/dt = g_i^3 (p_amb^2 - p^2) / (24 mu). A pocket of 10 mm^2
//            opened 20 um refills through one rim slit 10 um high in about a millisecond, 1 um
//            high in about a second: the seal holds while the rim hugs the object and fails
//            once it lifts.
//   force    each open particle of a pocket is pulled toward the object by
//            (p_amb - p) a_i n_i, and the object toward it by the opposite (Newton's third law:
//            the pair sums to zero). A closed particle keeps its element's air for when it opens.
// The pull is bounded by p_amb a_i per particle; the membrane follows the object off the grains
// once p_amb - p exceeds the vacuum's dp, which bounds the holding force from suction by about
// dp times the sealed area, Brown et al.'s estimate.
// Where the model stops: no leak through the membrane or along a closed contact (the rim's
// open particles are the only way in), no wrinkles finer than the membrane's particles (a real
// membrane's wrinkles open channels at the rim), one pressure over a pocket (no flow resistance
// inside it), isothermal air; the footprint is fixed at the capture (a membrane that rolls
// onto the object later does not join the seal).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dem/core/pressure.h"
#include "dem/core/vec3.h"
#include "dem/walls/wall.h"

namespace vpp {

struct SuctionDef {
    bool enabled = false;     // [-] the seal between the membrane and result.object
    double gap = 1e-5;        // [m] h0: the air film between membrane and object where they lie together
    double ambient = 101325;  // [Pa] the surroundings' absolute pressure
    double capture = 0.0;     // [m] footprint: particles whose surface is within this of the object's (0: touching)
    double viscosity = 1.8e-5;  // [Pa s] of the air (20 C): the leak through the rim
};

// The footprint and its air, captured once (capture_seal) and stepped (step_seal); the run's
// checkpoint carries it.
struct SuctionSeal {
    std::vector<uint32_t> particle;  // World indices of the footprint's membrane particles
    std::vector<dem::Vec3> normal;   // [-] the object's outward unit normal at each, at the capture
    std::vector<dem::Vec3> x0;       // [m] positions at the capture
    std::vector<double> area;        // [m^2] tributary areas a_i at the capture
    std::vector<double> gap0;        // [m] surface gaps g0_i at the capture
    std::vector<double> air;         // [Pa m^3] p_i V_i of each element's air
    std::vector<uint8_t> rim;        // 1: a neighbour is off the footprint
    std::vector<uint32_t> start, next;  // CSR: footprint neighbours of i are next[start[i] .. start[i+1]) (local indices)
    dem::Vec3 u0;                    // [m] the object's translation at the capture
    template <class A, class S> static void fields(A& a, S& s) {
        a.vec(s.particle);
        a.vec(s.normal);
        a.vec(s.x0);
        a.vec(s.area);
        a.vec(s.gap0);
        a.vec(s.air);
        a.vec(s.rim);
        a.vec(s.start);
        a.vec(s.next);
        a.pod(s.u0);
    }
};

// What one step of the seal gave: for the records and the tests.
struct SuctionStep {
    dem::Vec3 object_force;       // [N] the surroundings' push on the object through the sealed pockets
    double pressure_min = 0;      // [Pa] absolute, the lowest pocket pressure (ambient when none is sealed)
    double sealed_volume = 0;     // [m^3] the sealed pockets' air
    double sealed_area = 0;       // [m^2] the open particles' area in sealed pockets
    std::size_t open = 0, sealed = 0, leaked = 0;  // particles: open; of them in pockets below / at the ambient pressure
};

// The footprint on `object` (its facets at translation `u`: vertices + u) among the nodes of
// `fans` (a closed membrane's pressure fans: the nodes are its particles, the rings their
// neighbours), each of radius `radius` [m]; the air at `d.ambient` in films of `d.gap`. Empty
// when the membrane does not touch the object.
SuctionSeal capture_seal(const dem::PressureFans& fans, const std::vector<dem::Vec3>& pos, double radius,
                         const std::vector<dem::Facet>& object, const dem::Vec3& u, const SuctionDef& d);

// One step of `dt` [s]: the pockets from the positions `pos` and the object's translation `u` [m],
// their air spread at one pressure and refilled through the rim, and the forces: ext_force[i] of
// each footprint particle set (zero unless open in a pocket below the ambient pressure); the
// object's in the result.
SuctionStep step_seal(SuctionSeal& s, const std::vector<dem::Vec3>& pos, const dem::Vec3& u, double dt, const SuctionDef& d,
                      std::vector<dem::Vec3>& ext_force);

}  // namespace vpp
