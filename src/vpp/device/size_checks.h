// A device file against the sizes and the run it asks for (issue 61, items 3 and 4): what the
// device would build and how long it would run, estimated from the file and its closed surfaces
// before anything is built (load_device calls check_device_inputs once every key and mesh has
// passed), refused with a cfg::ConfigError naming the key, the value and what is allowed:
//   sizes    the membrane's particles (its surface's area over the site area of its spacing, as
//            the remesher places them) and the grains (the fill lattice's sites in the enclosed
//            volume), together at most kMaxDeviceParticles; a mesh file whose size looks like
//            millimetres read as metres is named with the scale that fixes it;
//   tools    a tool whose surface holds the membrane's, or part of it, names the tool's own keys
//            (the fill would otherwise find no room and blame grains.radius);
//   foil     a membrane spacing whose triangles let a grain through, a membrane too thin (E_f t_f)
//            to hold the grains under the underpressure or their weight;
//   motion   tool speeds past the impact that overlaps a particle by half its radius; strokes
//            (move.to, force.max_travel, cycle.amplitude) past twice the device's height beyond
//            the tool's gap to it; durations past kMaxDeviceSteps steps of the estimated step.
// Before these checks a millimetre STL without `scale` built a 9 m bag (2 GB in 30 s, nothing
// printed), a 1 km membrane grew until std::bad_alloc, a segment of 1e300 s never ended, and a
// speed of 1e308 m/s, membrane.spacing = 0.003 or membrane.thickness = 1e-9 failed mid-stage
// without a key.
#pragma once

#include <vector>

#include "dem/core/vec3.h"
#include "dem/mesh/surface_mesh.h"
#include "vpp/device/definition.h"

namespace vpp {

// [-] The most particles (membrane and grains) a device may have: the damper's bound on its foil
// (vpp/settings/config.cpp) and grains.pour_count's. At 10^7 particles a run holds about 25 GB
// (kDeviceBytesPerParticle) and a step takes seconds on a CPU, so the 10^5-10^6 steps of a device
// run take months; the shipped devices have 2600 (gripper) and 6000 (beam). Fixed, not a key:
// past it the input is a slip of units or sizes, not a device this program can run.
constexpr double kMaxDeviceParticles = 1e7;
// [-] The most steps one duration of a run may take (a stage's time, a tool segment's): 10^10,
// months at the shipped gripper's 1300 steps a second on one core. A duration past it is a
// slip (1e300 s, a speed of 1e-300 m/s), not a run.
constexpr double kMaxDeviceSteps = 1e10;
// [B] The run's memory per particle, for the messages: the peak resident memory of the gripper
// (2643 particles, 14.4 MB), of the gripper at twice its radius (14077, 39.0 MB) and of the beam
// (6048, 23.0 MB) grows 2.2-2.5 kB a particle (measured; docs/devices.md "Sizes and inputs checked").
constexpr double kDeviceBytesPerParticle = 2500.0;

// What the device would build, estimated from its closed surface without remeshing.
struct DeviceSizeEstimate {
    dem::Vec3 lo, hi;               // [m] the membrane surface's bounding box
    double membrane_area = 0;       // [m^2] of the membrane's closed surface
    double membrane_spacing = 0;    // [m] the sites' mean spacing L: membrane.spacing, or 2 r_f
    double membrane_particles = 0;  // [-] 2 A / (sqrt(3) L^2) sites (the remesher's mean edge is L), less the vacancies
    double enclosed_volume = 0;     // [m^3] inside the membrane's surface
    // [m^3] the part of it the lattice's clearance c = r + r_f + 0.1 r leaves (Steiner's formula,
    // V - A c + M c^2 - 4 pi c^3 / 3, M the integral of the mean curvature)
    double fill_volume = 0;
    double grains = 0;              // [-] lattice: fill x the lattice's sites in fill_volume; pour: pour_count
    double bytes = 0;               // [B] (membrane_particles + grains) kDeviceBytesPerParticle
};

DeviceSizeEstimate estimate_device_size(const DeviceDef& d, const dem::SurfaceMesh& membrane);

// [s] The run's time step: simulation.dt when fixed, else about what DeviceRun takes,
// simulation.dt_safety times the smallest sqrt(m / kn) of a grain against a grain and of a
// membrane particle against a grain or through an equilateral bond (dem::critical_dt's rule;
// the remeshed bonds vary, so the run's step is about this or shorter).
double estimate_device_dt(const DeviceDef& d);

// The checks above. `membrane` the membrane's closed surface, `tools` each tool's (an empty mesh
// for shape = "none"), as device_surface makes them. Throws cfg::ConfigError.
void check_device_inputs(const DeviceDef& d, const dem::SurfaceMesh& membrane, const std::vector<dem::SurfaceMesh>& tools);

}  // namespace vpp
