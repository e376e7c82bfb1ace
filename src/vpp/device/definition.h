// The device file (issue 47, docs/devices.md): a vacuum-packed device built from meshes. A TOML
// file names
//   [membrane]   the closed surface the foil membrane is built on (vpp/membrane/membrane.h) and the foil;
//                the part of it clamped to a tool (the bag's neck held by the gripper's holder)
//   [grains]     the fill: sphere size and material, how full the membrane is filled
//   [[tools]]    rigid tools as closed meshes, each with a motion program ([[tools.program]]:
//                move, hold, force, cycle segments, each in one stage)
//   [stages]     the fill's settling time, the vacuum's underpressure, ramp and hold
//   [air]        the air inside: held at the set dp (constant) or a sealed gas pumped down (pump)
//   [suction]    the seal between the membrane and the object (vpp/device/suction.h)
//   [simulation] time step, damping, gravity, seed, threads
//   [output]     sampling of the records, the energy ledger
//   [result]     which tool the holding force is measured on
// Every key is checked when the file is read: a bad value or an unknown key is refused with a
// cfg::ConfigError naming the key, the value and what is allowed; a mesh with a defect
// (dem/mesh/mesh_checks.h) is refused naming the key, the file and the defect; the device's size,
// its tools, its foil and its tools' motion are checked against each other (size_checks.h).
// Nothing is built or written before the file has passed (vppdem exits 2).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/mesh/surface_mesh.h"
#include "dem/world/tool.h"
#include "scene/shared_keys.h"
#include "vpp/device/suction.h"
#include "vpp/membrane/membrane.h"
#include "vpp/membrane/air.h"

namespace vpp {

// Stages of a device run, in order; a tool segment names the stage it runs in.
enum class DeviceStage : int32_t { Fill = 0, Seal = 1, Press = 2, Vacuum = 3, Load = 4, Done = 5 };
const char* device_stage_name(DeviceStage s);

// A closed surface: generated (sphere, box, cylinder) or read from a mesh file; "none" (tools
// only) for a tool that is no more than the membrane particles clamped to it.
struct DeviceShape {
    std::string kind = "none";  // "sphere", "box", "cylinder", "mesh", "none"
    dem::Vec3 center;           // [m] sphere and box: centre; cylinder: centre of its base
    double radius = 0.0;        // [m] sphere, cylinder
    double height = 0.0;        // [m] cylinder (along z)
    dem::Vec3 size;             // [m] box: edge lengths
    int resolution = 8;         // [-] sphere: icosahedron subdivisions; cylinder: segments / 8; box: squares per edge
    std::string file;           // mesh: .stl or .obj, relative to the device file's folder
    double scale = 1.0;         // [-] mesh: factor to metres (1e-3 for a file in mm)
    dem::Vec3 offset;           // [m] mesh: added to every vertex after scaling
};

struct DeviceTool {
    std::string name;
    DeviceShape shape;
    double young = 1e9;           // [Pa] contact modulus of the tool's surface
    double friction = 0.5;        // [-]
    double stiffness_ratio = 0.5; // [-] ks/kn
    std::vector<dem::ToolSegment> program;
};

struct DeviceDef {
    std::string path;  // the device file ("" when built in code)

    // [simulation]
    double dt = 0.0;             // [s] 0: auto, dt_safety x the critical step
    double dt_safety = cfg::keys::dt_safety.def;  // [-]
    double local_damping = 0.3;  // [-] Yade's non-viscous damping of every free particle
    dem::Vec3 gravity = cfg::keys::gravity.def3;  // [m/s^2]
    uint64_t seed = uint64_t(cfg::keys::seed.def);  // [-] the fill's jitter and the membrane's vacancies
    int threads = int(cfg::keys::threads.def);      // [-] threads of the step (results do not depend on it)

    // [membrane]
    DeviceShape membrane_shape;
    MembraneDef membrane;        // the foil (E_f, t_f, r_f, density, friction, ks/kn) and spacing
    std::string clamp_tool;      // the tool the membrane's top follows ("" none)
    double clamp_height = 0.0;   // [m] membrane particles within this height below its top are clamped

    // [grains]
    double grain_radius = 1e-3;        // [m]
    double grain_density = 1500.0;     // [kg/m^3]
    double grain_young = 1e8;          // [Pa]
    double grain_friction = 0.5;       // [-]
    double fill_friction = 0.0;        // [-] the grains' friction while they settle in the fill (0: a frictionless pour, as the damper's)
    double grain_stiffness_ratio = 0.5;// [-]
    double fill = 0.8;                 // [-] fraction of the lattice sites inside the membrane filled, lowest first
    double lattice_spacing = 2.2;      // [-] the fill lattice's spacing in grain radii (> 2; the jitter keeps 5% of the gap)
    std::string lattice = "cubic";     // the fill lattice: "cubic" (packing 0.52 (2/s)^3) or "fcc" (0.74 (2/s)^3), s the spacing
    // How the grains get into the membrane: "lattice" (placed on the fill lattice inside the closed
    // membrane) or "pour" (placed on the same lattice in a column above the membrane's top and
    // poured under gravity through an opening, the membrane particles within opening_height of
    // its top, which the grains pass through until the seal; docs/devices.md "The pour").
    std::string fill_mode = "lattice";
    double opening_height = 0.0;       // [m] pour: the membrane particles within this height of its top form the opening
    int64_t pour_count = 0;            // [-] pour: the grains poured (the excess is struck off at the seal)

    // [stages]
    double fill_time = 0.1;      // [s] the fill settles for at most this long
    double fill_min_time = 0.02; // [s] and at least this long
    double underpressure = 5e4;  // [Pa] dp of the vacuum stage
    double ramp_time = 0.01;     // [s] dp ramped from 0
    double vacuum_hold = 0.02;   // [s] held after the ramp before the load stage

    // [air]
    MembraneAirDef air;          // model (constant or pump) and the pump line

    // [suction]
    SuctionDef suction;          // the seal between the membrane and result.object (off by default)

    // [output]
    double sample_interval = 1e-3;  // [s] between rows of the records (forces averaged over it)
    bool energy = true;             // energy.csv from the seal on
    bool vtk = true;                // VTK frames (particles with bonds, tool facets) at the end of every stage
    double vtk_interval = 0.0;      // [s] and every vtk_interval of simulated time (0: none)

    // [result]
    std::string object;             // the tool whose pull in the load stage is the holding force ("" none)
    double release_time = 2e-3;     // [s] the load stage ends once the object has been free this long (0: never early)
    std::string cycle_tool;         // the tool whose load-stage cycle is analysed (stiffness, work per cycle; "" none)

    std::vector<DeviceTool> tools;
};

// Reads and checks a device file, with --set style overrides ("stages.underpressure=0").
// Throws cfg::ConfigError naming the key, the value and what is allowed, or the mesh file and
// its defect; then check_device_inputs (size_checks.h).
DeviceDef load_device(const std::string& path, const std::vector<std::string>& overrides = {});

// The closed, outward surface of a shape (generated or read and checked); `key` names it in
// errors ("membrane", "tools[1]"). Throws cfg::ConfigError.
dem::SurfaceMesh device_surface(const DeviceShape& s, const std::string& key, const std::string& base_dir);

// The device's inputs as dotted keys and JSON values (summary.json "inputs").
std::vector<std::pair<std::string, std::string>> device_inputs(const DeviceDef& d);

}  // namespace vpp
