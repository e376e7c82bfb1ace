// The pour (grains.fill_mode = "pour"; docs/devices.md, "The pour"): an opening in the membrane's
// top (its particles within grains.opening_height of the top) that the grains pass through until
// the seal, the lattice column above it they start in, and the seal's strike-off of the grains
// outside the membrane or in the opening's way. The opening is a collision mask, not a cut: until
// the seal its particles carry kMaskOpening alone, the rest of the membrane kMaskOpening and
// kFoilMask, the grains kGrainMask, so the grains pass through the opening while it stays in
// contact with the rest of the membrane and the tools do not see it. Internal to
// vpp/device/*.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/mesh/surface_mesh.h"
#include "dem/world/world.h"
#include "vpp/device/definition.h"
#include "vpp/device/fill_sites.h"
#include "vpp/membrane/membrane.h"

namespace vpp::device_detail {

struct DeviceScene;

// The opening's mask bit; bits 0 and 1 are the foil's (vpp/membrane/foil.h).
constexpr uint32_t kMaskOpening = 1u << 2;

struct PourOpening {
    std::vector<uint32_t> particles;  // the opening's membrane particles
    double z_seal = 0;                // [m] the membrane's top less grains.opening_height (at the build)
    double axis_x = 0, axis_y = 0;    // [m] the column's axis: the opening's centre
    double column_radius = 0;         // [m] the column's: the rim's aperture less the clearance
};

// The opening of the membrane `m` built in `w` (its particles' masks set as above). Refuses
// (cfg::ConfigError naming grains.opening_height, its value and what is allowed) an opening as
// high as the membrane, one with no membrane below its edge, and one with no room for a grain.
PourOpening open_membrane(const DeviceDef& d, dem::World& w, const Membrane& m);

// The pour's start: the lowest grains.pour_count sites of lattice L in a column above the
// opening, clear of the tools (`tool_surfaces`). Refuses (cfg::ConfigError naming
// grains.pour_count) a column that a tool fills.
std::vector<dem::Vec3> pour_sites(const DeviceDef& d, const PourOpening& o, const FillLattice& L,
                                  const std::vector<dem::SurfaceMesh>& tool_surfaces);

// The pour's seal: the grains outside the membrane or overlapping the opening are retired, the
// membrane's masks restored (the opening closed); returns how many were retired [-].
std::size_t strike_off(DeviceScene& scene);

}  // namespace vpp::device_detail
