// A wall as the wall bodies read it (dem/kernels/step_bodies.h, wall_pair and wall_geometry): World's
// wall kernel and touch test and the batch engine's kernels (WallState::now). Plain data, also
// for the device (docs/gpu.md).
#pragma once

#include "dem/core/vec3.h"

namespace dem {

// Where a wall is now: a plane (point, normal) or a facet (vertices), and its velocity over the
// last step.
struct WallNow {
    bool plane = true;
    bool one_sided = false;
    Vec3 point, normal;  // [m], [-] (planes)
    Vec3 v0, v1, v2;     // [m] (facets)
    Vec3 velocity;       // [m/s]
};

}  // namespace dem
