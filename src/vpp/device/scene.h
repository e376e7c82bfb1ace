// The device's scene: its World and the parts in it (the membrane, the tools, the grains and,
// for a pour, the opening in the membrane's top), built from the device file by the constructor
// (the grains' sites: device/fill_sites.h; the opening: device/pour.h), and what can be asked of
// or done to them with nothing but the scene: the grains in the run, their volume and kinetic
// energy, the enclosed volume. The stages (device/stages.h) act on it; run_device owns it. A
// plain aggregate: the stages read and move its parts directly. Internal to vpp/device/*.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dem/world/tool.h"
#include "dem/world/world.h"
#include "vpp/device/definition.h"
#include "vpp/device/pour.h"
#include "vpp/membrane/membrane.h"

namespace vpp::device_detail {

struct DeviceScene {
    // Builds the membrane, the tools (their facets, the clamp), the opening (a pour) and the
    // grains, and sets the time step. Throws cfg::ConfigError for what the device file cannot
    // make (no grain fits, an opening with no room), std::runtime_error for no usable time
    // step; nothing is written.
    explicit DeviceScene(const DeviceDef& d);
    DeviceScene(const DeviceScene&) = delete;
    DeviceScene& operator=(const DeviceScene&) = delete;

    // Grain i [particle index] is in the run: a pour retires the grains that fall below the bag
    // or are struck off at the seal (mask 0).
    bool active_grain(uint32_t i) const { return world.particles.mask[i] != 0; }
    // [-] the grains in the run
    std::size_t active_grains() const;
    // [m^3] their volume
    double active_grain_volume() const;
    // Takes grain i out of the run: it interacts with nothing (mask 0) and stands still (fixed).
    // The World has no removal of particles; a retired grain stays in its arrays, left out of the
    // counts, the grains' volume and the VTK frames.
    void retire_grain(uint32_t i);
    // [m] The largest overlap of a grain with a membrane particle now (0: none touches).
    double largest_membrane_overlap() const;
    // [m^3] the volume the membrane encloses through its particles' centres
    double enclosed() const { return enclosed_volume(membrane, world.particles.pos); }
    // [J] the grains' translational kinetic energy
    double grains_kinetic_energy() const;
    // [m] the membrane's lowest particle centre
    double membrane_z_min() const;

    DeviceDef def;                 // the device file
    dem::World world;
    Membrane membrane;             // its particles first in the World (material 0)
    std::vector<dem::Tool> tools;  // in the file's order (the columns of tools.csv)
    uint32_t first_grain = 0, end_grain = 0;  // the grains' particle range (a pour's retired ones included)
    uint32_t grain_mat = 0;        // the grains' material (its friction: fill_friction until the seal)
    double grain_volume = 0;       // [m^3] of the active grains (a pour's struck-off grains left out)
    bool pour = false;             // grains.fill_mode = "pour"
    PourOpening opening;           // pour: the opening in the membrane's top and the column above it
};

}  // namespace vpp::device_detail
