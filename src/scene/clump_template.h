// A clump template: the members of a grain (x, y, z, r [m] in the grain's frame, one per row of a
// CSV file of four numeric columns), read once for the scenes' [[clumps]] (scene_runner.cpp) and
// the damper's grains.clump_template (vpp/settings/config.cpp).
#pragma once

#include <string>

#include "dem/clumps/clump_shape.h"

namespace scene {

// The shape of the template in `path` at its own size. Throws std::runtime_error naming the file
// when it cannot be read, or when its members do not make a clump (none, or not all touching).
dem::ClumpShape read_clump_template(const std::string& path);

}  // namespace scene
