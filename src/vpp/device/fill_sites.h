// Where the device's grains start (docs/devices.md, "Stages", fill): sites on a jittered cubic or
// fcc lattice, inside the closed membrane and clear of it and the tools (the lattice fill), or in
// a column above the opening in its top (the pour, device/pour.h); the grains placed on them
// lowest first, each with its seeded jitter, never overlapping. Internal to vpp/device/*.cpp.
#pragma once

#include <vector>

#include "dem/core/vec3.h"
#include "dem/mesh/surface_mesh.h"
#include "vpp/device/definition.h"

namespace vpp::device_detail {

struct DeviceScene;

// The fill lattice of grains.lattice and grains.lattice_spacing.
struct FillLattice {
    double edge = 0;              // [m] a cell's edge: s r (cubic), s r sqrt 2 (fcc); s the spacing in radii
    std::vector<dem::Vec3> basis; // [cell edges] the sites of a cell (fcc: four, nearest neighbours s r apart)
    double jitter = 0;            // [m] the largest random displacement of a grain per axis
};
FillLattice fill_lattice(const DeviceDef& d);

// Whether a grain of radius r [m] at p [m] lies outside every tool surface and a tenth of its
// radius clear of it.
bool clear_of_tools(const std::vector<dem::SurfaceMesh>& tool_surfaces, const dem::Vec3& p, double r);

// The grains of the fill added to the scene's World after its membrane and tools: on the lattice
// inside `surface` (the membrane's input mesh), the lowest grains.fill of its sites, or the
// pour's column above the opening (scene.opening set first); `tool_surfaces`: the tools' that
// have a shape. Throws cfg::ConfigError naming grains.radius when no grain fits.
void add_grains(DeviceScene& scene, const dem::SurfaceMesh& surface, const std::vector<dem::SurfaceMesh>& tool_surfaces);

}  // namespace vpp::device_detail
