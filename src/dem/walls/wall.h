// Rigid boundaries: infinite planes and triangular facets. Both translate with a
// prescribed Motion; neither has mass, so particles never move them.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/walls/motion.h"

namespace dem {

struct Plane {
    Vec3 point;                 // [m] a point of the plane at t = 0
    Vec3 normal{0, 0, 1};       // unit normal; for one-sided planes the side particles live on
    uint32_t material = 0;      // index into World::materials
    uint32_t mask = 1;          // interacts with particles whose mask shares a bit
    bool one_sided = false;     // true: only spheres whose centre is on the +normal side touch it
    Motion motion;
};

struct Facet {
    std::array<Vec3, 3> vertices;  // [m] at t = 0; normal = (v1-v0) x (v2-v0), right-handed
    uint32_t material = 0;
    uint32_t mask = 1;
    bool one_sided = false;        // true: only spheres on the +normal side touch it
    Motion motion;
};

}  // namespace dem
