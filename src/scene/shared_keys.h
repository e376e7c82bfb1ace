// The keys that more than one settings table reads, each declared once: its type, unit, range
// (with the sentence an error gives), default and doc. Three tables read them: the scene runner's
// (scene/scene_settings.cpp: `vppdem scene`), the damper's (vpp/settings/settings.cpp: damper,
// sweep, calibrate, tension, envelope) and the device file's (vpp/device/definition.cpp). Each
// table's row of such a key is made from its declaration here, so a value one command accepts
// another does not refuse, and the range reads the same in every message and on the reference
// page (docs/config.md).
//
// What a table may change, and why:
// - the default, where its application's differs and runs depend on it (with_default(), a
//   comment at the row): the damper's grains are the paper's, the gripper's millimetre grains; a
//   scene file without dt has always run at 1e-7 s;
// - the key of a material property (the scene's `materials[].young` is the damper's
//   `grains.young`), with a doc that says whose property it is.
// The range, the unit and the type never differ.
// Why here: src/scene is the lowest layer that every reader sees (src/dem knows no config).
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "dem/core/material.h"
#include "dem/core/vec3.h"
#include "scene/config.h"
#include "scene/setting.h"

namespace cfg {

struct KeyDecl {
    const char* key;                  // the dotted key as the files spell it (a scene's material: materials[].young)
    SettingType type;
    const char* unit;                 // SI unit; "-" a ratio, "" a count, flag or word
    double def = std::numeric_limits<double>::quiet_NaN();  // the default (NaN: default_text says it)
    const char* default_text = "";    // the default as the reference shows it when it is no number
    dem::Vec3 def3{};                 // Vec3: the default
    Limits limits{};                  // the range and the sentence an error gives
    const char* doc = "";
};

// The same declaration with another default [the key's unit], for a table whose application's
// default differs (the comment at the row says why).
constexpr KeyDecl with_default(KeyDecl k, double def) {
    k.def = def;
    k.default_text = "";
    return k;
}

namespace keys {

// The core's material defaults (dem/core/material.h): a scene's [[materials]] entry without them.
inline constexpr dem::Material kCoreMaterial{};

// [simulation]
inline constexpr KeyDecl dt{
    .key = "simulation.dt", .type = SettingType::RealOrAuto, .unit = "s", .default_text = "\"auto\"",
    .limits = {.check = Check::Custom, .allowed = "must be a time step in seconds (> 0) or \"auto\""},
    .doc = "time step; \"auto\": dt_safety times the critical step, the minimum over free spheres of sqrt(m / kn) "
           "(needs a sphere that is not fixed)"};
// At most 0.5: sqrt(m/k) (dem/integrate/critical_dt.h) is 1 / omega of one spring holding a
// particle against a wall, and the leapfrog is stable below 2 / omega. A particle with several
// contacts vibrates faster (z springs to fixed walls: omega = sqrt(z k / m), a stable step below
// 2 / sqrt(z) of sqrt(m/k), 0.58 for the densest packing's 12 contacts), and so do neighbours
// moving against it, its rotation through the tangential springs and the foil's bonds: half one
// spring's step keeps a margin under all of them. Measured: 0.7 diverged on the tests' small
// damper ("cannot create std::vector larger than max_size()"), 0.6 ran with W 24% off 0.45's.
// Scenes and devices had allowed up to 1; no file of examples/, studies/, tests/ or docs/ gives
// more than 0.5. The damper's check of a fixed step (vpp/damper/checks.cpp) uses the same bound.
// Default 0.3: the largest step whose mean bias lies within 2% of the converged W (Richardson over
// 5 seeds of the paper's damper at 0.06 MPa; docs/paper_comparison.md, "Time step converged").
inline constexpr KeyDecl dt_safety{
    .key = "simulation.dt_safety", .type = SettingType::Real, .unit = "-", .def = 0.3,
    .limits = {.check = Check::Range, .lo = 0.0, .hi = 0.5, .lo_open = true,
               .allowed = "must be in (0, 0.5] (sqrt(m/k) is one contact's critical step; several contacts need less)"},
    .doc = "dt = safety * min sqrt(m/k) when simulation.dt is \"auto\""};
// At most 0.9: the damping removes the fraction lambda of each force's power; near 1 it holds the
// particles back instead of damping them (process.local_damping = 0.999999 gave the damper a W of
// 125,099 J/m^2 against 388). Scenes and devices had allowed [0, 1); no file gives more than 0.5.
// Default 0: a scene is undamped unless it asks.
inline constexpr KeyDecl local_damping{
    .key = "simulation.local_damping", .type = SettingType::Real, .unit = "-", .def = 0.0,
    .limits = {.check = Check::Range, .lo = 0.0, .hi = 0.9,
               .allowed = "must be in [0, 0.9] (above, the damping, not the contacts, dissipates)"},
    .doc = "Yade's non-viscous damping: each force and torque component is scaled by 1 - lambda sign(F_k v_k)"};
// 0: the free cores, measured only when asked for (scene/threads.h); the damper's default. Scenes
// and devices had allowed 1 ... 1024 only.
inline constexpr KeyDecl threads{
    .key = "simulation.threads", .type = SettingType::Integer, .unit = "", .def = 1,
    .limits = {.check = Check::Custom, .lo = 0, .hi = 1024, .allowed = "must be an integer 1..1024, or 0 for the free cores"},
    .doc = "threads of a run; 0: the free cores (src/scene/threads.h). Results do not depend on it"};
// Any integer >= 0: a seed is an unsigned 64-bit integer (the device's reader took 0 ... 2^31).
inline constexpr KeyDecl seed{
    .key = "simulation.seed", .type = SettingType::Integer, .unit = "", .def = 1,
    .limits = {.check = Check::AtLeast, .lo = 0, .allowed = "must be an integer >= 0"},
    .doc = "grain placement (the lattice's jitter)"};
inline constexpr KeyDecl skin{
    .key = "simulation.skin", .type = SettingType::Real, .unit = "m", .def = 0.0,
    .limits = {.check = Check::NonNegative},
    .doc = "Verlet distance of the neighbour lists; 0: half the smallest radius (Yade). A speed setting"};
inline constexpr KeyDecl gravity{
    .key = "simulation.gravity", .type = SettingType::Vec3, .unit = "m/s^2", .def3 = {0.0, 0.0, -9.81},
    .doc = "acceleration of gravity"};

// The grains' material: the damper's and the device's [grains] keys; the scene's [[materials]]
// keys of the same name (materials[].young) are the same properties. The defaults are the
// paper's grains (docs/model.md); a scene takes the core's (kCoreMaterial), a device the gripper's.
inline constexpr KeyDecl grain_radius{
    .key = "grains.radius", .type = SettingType::Real, .unit = "m", .def = 2.965e-3,
    .limits = {.check = Check::Positive},
    .doc = "r_k, radius of every grain; with grains.radius_distribution the number-mean radius"};
// At most 1e6 kg/m^3: 44 times osmium (22,590), room for mass scaling; 1e300 left a body that
// never comes to rest.
inline constexpr KeyDecl density{
    .key = "grains.density", .type = SettingType::Real, .unit = "kg/m^3", .def = 2689.639,
    .limits = {.check = Check::Range, .lo = 0.0, .hi = 1e6, .lo_open = true,
               .allowed = "must be in (0, 1e6] kg/m^3 (44 times osmium's 22,590: room for mass scaling)"},
    .doc = "density of the grains"};
inline constexpr KeyDecl young{
    .key = "grains.young", .type = SettingType::Real, .unit = "Pa", .def = 2.3e9, .limits = {.check = Check::Positive},
    .doc = "E_k, Young's modulus of the grains (contact stiffness)"};
inline constexpr KeyDecl friction{
    .key = "grains.friction", .type = SettingType::Real, .unit = "-", .def = 0.6,
    .limits = {.check = Check::NonNegative}, .doc = "mu_k, grain-grain Coulomb friction (the preparation is frictionless)"};
// At most 1: ks/kn of elastic spheres is 2 (1 - nu) / (2 - nu), 0.67 to 1 for Poisson ratios
// 0.5 to 0; and the time step is sized on the normal stiffness, so a stiffer tangential spring
// outruns it (1.5 blew the damper up). At least 0.01: the shear spring must carry the friction
// force (at 0 its elongation f_t / k_s is NaN). Scenes had allowed >= 0, devices (0, 1]; no file
// gives a value outside [0.01, 1].
inline constexpr KeyDecl stiffness_ratio{
    .key = "grains.stiffness_ratio", .type = SettingType::Real, .unit = "-", .def = 0.5,
    .limits = {.check = Check::Range, .lo = 0.01, .hi = 1.0,
               .allowed = "must be in [0.01, 1] (ks/kn of elastic spheres is at most 1; the time step is sized on kn; "
                          "below 0.01 the shear spring cannot carry the friction force: at 0 its elongation f_t / k_s "
                          "is NaN)"},
    .doc = "ks/kn of grain contacts"};
inline constexpr KeyDecl restitution{
    .key = "grains.restitution", .type = SettingType::Real, .unit = "-", .def = 1.0,
    .limits = {.check = Check::Range, .lo = 0.0, .hi = 1.0, .lo_open = true, .allowed = "must be in (0, 1] (1: no dashpot)"},
    .doc = "normal coefficient of restitution of grain contacts (a linear dashpot) from the vacuum on; the physical "
           "dissipation of dynamic runs, with process.local_damping = 0 (docs/damper.md, \"Waveforms and "
           "frequency\"); the preparation has none"};

}  // namespace keys

// Readers of the declared keys whose value is more than the number read; each refuses a value
// outside the declaration's range with its sentence, naming the key.
// simulation.threads: 1 ... 1024, or 0 for the free cores (scene/threads.h, measured only then).
int read_threads(Section& s, const std::string& key, int64_t def);
// simulation.seed: any integer >= 0 (an unsigned 64-bit seed, more than a double holds exactly).
uint64_t read_seed(Section& s, const std::string& key, int64_t def);

}  // namespace cfg
