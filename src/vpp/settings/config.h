// Configuration of the VPP commands (tension, envelope, damper): one schema for all, so a
// damper config can be handed to any of them. Every key is checked.
//
// The structs below hold values, not defaults: every default (the paper's calibrated values,
// docs/model.md) lives in one place, the settings table (vpp/settings/settings.cpp), and Config's
// constructor fills every field from it, so code that builds a Config directly runs the same
// model as the command line.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "dem/clumps/clump_shape.h"
#include "scene/size_distribution.h"
#include "vpp/membrane/foil.h"
#include "vpp/settings/choices.h"

namespace vpp {

struct GrainsDef {
    double radius{};              // [m] r_k; with a size distribution its number mean
    RadiusDistribution radius_distribution{};  // grain sizes (vpp/settings/choices.h)
    double radius_spread{};       // [-] uniform: half-width over radius; lognormal: sd of ln r
    std::string sieve_curve;      // CSV of sieve openings [m] and mass fractions passing (Sieve)
    double sieve_curve_id{};      // fingerprint of the curve's numbers (0: none): the sample's geometry check
    GrainShape shape{};           // spheres or clumps (vpp/settings/choices.h)
    std::string clump_template;   // CSV x, y, z, r [m] of the members in the grain's frame (Template)
    double clump_template_id{};   // fingerprint of the template's numbers (0: none)
    double density{};             // [kg/m^3]
    double young{};               // [Pa] E_k
    double friction{};            // [-] mu_k
    double stiffness_ratio{};     // [-] ks/kn
    double volume_fraction{};     // [-] phi
    double restitution{};         // [-] normal restitution of grain contacts in the cycling (1: no dashpot)
};

struct DamperDef {
    double radius{};              // [m] r_p
    double height{};              // [m] H_p
    double cap_friction{};        // [-] grain-cap friction; < 0: the grains' friction
    // Preparation: after the pour, add grains (re-fill, as the experiment does) until they stand
    // above the damper height, so that the cap comes down onto them and compresses them to
    // H_p (docs/damper.md, "Preparation"). false: exactly the grains of grains.volume_fraction,
    // poured once; the cap may end above them (warned).
    bool refill{};
    // Packing target (0: off): the re-fills add grains until their volume is this fraction of the
    // foil's interior up to H_p (pi r_in^2 H_p), instead of until their level reaches H_p, so that
    // dampers of other radii are prepared at the same packing (docs/damper.md, "Preparation").
    double packing_target{};      // [-] 0, or in (0, 0.74)
    // The foil's builder (key foil.builder; docs/membrane.md, "A cylinder given as a mesh").
    FoilBuilder foil_builder{};
    // The foil's sites on the circle of `radius` itself (key foil.exact_radius): the column count
    // as ever, the row bonds the chord (vpp/membrane/foil.h build_cylinder; docs/foil.md). false:
    // the circle of chord 2 r_f for that count, up to 1.3% off `radius` on the paper's radii.
    bool foil_exact_radius{};
};

// dp is the atmosphere's pressure minus the pressure inside the foil: at most a perfect vacuum.
inline constexpr double kAtmosphericPressure = 101325.0;  // [Pa]

struct ProcessDef {
    double underpressure{};       // [Pa] dp in [0, kAtmosphericPressure]
    double ramp_time{};           // [s] dp rises linearly from 0 over this time
    double hold_time{};           // [s] envelope: time held at full dp after the ramp
    double amplitude{};           // [m] dz
    double velocity{};            // [m/s] v_z
    double start_offset{};        // [m] cap moved down by this (up if < 0) before cycling
    bool compression_first{};     // direction "compression" (down first) or "extension"
    int64_t cycles{};
    int64_t samples_per_cycle{};
    double sample_window{};       // [s]
    // The air inside (vpp/membrane/gas.h; docs/damper.md, "The air inside").
    PressureModel pressure_model{};  // Constant: dp held (the paper); Pump: gas, pump, leak
    double pump_speed{};          // [m^3/s] S (2 m^3/h, a small rotary-vane pump)
    double bleed_rate{};          // [m^3/s] B: the regulator's bleed lets air in below the set point
    double leak_rate{};           // [m^3/s] C: air leaks in at C (p_atm - p_inside)
    bool pump_down{};             // the vacuum stage pumps down from the atmosphere (else: the ramp)
    // The stroke's shape (docs/damper.md, "Waveforms and frequency").
    Waveform waveform{};          // Triangle (the paper) or Sine
    double frequency{};           // [Hz] cycles per second; 0: the period 2 A / v of velocity
    // Local damping from the vacuum on: < 0 is "auto", simulation.local_damping throughout. A
    // dynamic run keeps the preparation's damping (which brings the pour to rest) and cycles
    // with 0 and grain restitution, from one prepared sample (docs/damper.md).
    double local_damping{};       // [-] lambda after the preparation; < 0: simulation.local_damping
};


// The loading cycle's period [s]: 1 / frequency, or 2 A / v (the triangle at process.velocity).
double cycle_period(const ProcessDef& p);
// The cap's largest speed in the cycle [m/s]: 2 A / T for the triangle (process.velocity when
// no frequency is given), pi A / T for the sine.
double peak_speed(const ProcessDef& p);

struct TensionDef {
    int64_t sites_along{};        // sites in the pulling direction
    int64_t sites_across{};       // sites across
    double strain{};              // [-] final engineering strain
    double speed{};               // [m/s] pulling speed (quasi-static: << bond wave speed ~ 500 m/s)
};

struct SimulationDef {
    bool dt_auto{};
    double dt{};                  // [s] when not auto
    double dt_safety{};           // [-] dt = safety * critical step when auto
    double local_damping{};       // [-]
    int threads{};                // 0 in the file = the free cores (scene/threads.h)
    uint64_t seed{};
    double skin{};                // [m] 0 = half the smallest radius
};

struct OutputDef {
    double interval{};            // [s] rows of the time series; 0 = command default
    double vtk_interval{};        // [s] VTK frames; 0 = command default
    bool energy{};                // damper: energy ledger during cycling (energy.csv; ~25% slower)
    bool air{};                   // damper: the air columns of forces.csv with the constant model too
};

// Post-processing of the recorded loops; acts on no simulation, so it never needs a new run.
struct AnalysisDef {
    double settle_tolerance{};    // [-] relative scatter of one cycle's W when stationary (vpp/analysis/settle.h)
    double event_threshold{};     // [-] 0: no event split; > 1: kinetic energy above this many times the
                                  //     cycle's median is a rearrangement event (vpp/analysis/events.h)
};

// The defaults differ between the commands for a few keys (Setting::def_foil): the damper
// commands (damper, sweep, calibrate) and the foil's checks (tension, envelope).
enum class CommandSet { Damper, Foil };

struct Config {
    // The table's defaults for these commands: what a config file without keys gives.
    explicit Config(CommandSet commands = CommandSet::Damper);

    GrainsDef grains;
    FoilDef foil;
    DamperDef damper;
    ProcessDef process;
    TensionDef tension;
    SimulationDef simulation;
    OutputDef output;
    AnalysisDef analysis;
    // Dotted keys the file or a --set gave (e.g. "process.velocity"); the others hold defaults.
    // A run from a checkpoint takes the checkpoint's value of a key not given here.
    std::set<std::string> given;

    // Zeros, read from nothing: a placeholder that a reader assigns (a study's cases before
    // their configs are loaded). Reading the defaults is not free: simulation.threads = 0 has
    // the reader sample the machine's free cores for 150 ms (scene/threads.h).
    static Config unread() { return Config(Unread{}); }

private:
    struct Unread {};
    explicit Config(Unread) {}
    // A file's keys, the others the table's defaults for these commands (load_config).
    Config(const toml::table& file, CommandSet commands);
    friend Config load_config(const std::string&, const std::vector<std::string>&, CommandSet);
};

// The local damping of the vacuum stage and the cycling [-]: process.local_damping, or when that
// is "auto" simulation.local_damping (which the preparation always uses).
// The grains' size distribution (the sieve curve read from its file): what the fill draws from.
scene::SizeDistribution grain_sizes(const Config& c);
// The members of a clump template file (CSV x, y, z, r [m]) as a shape scaled to the volume of a
// sphere of radius 1 m. Throws std::runtime_error naming the file and the reason.
dem::ClumpShape clump_template_shape(const std::string& path);
// The grains' shape at a volume-equivalent radius of 1 m (a clump unless GrainShape::Sphere; scale it to
// a grain's radius with dem::scaled); the template is read from grains.clump_template.
dem::ClumpShape grain_shape(const Config& c);
double cycling_local_damping(const Config& c);

// Reads the config (empty path: all defaults) with --set overrides.
Config load_config(const std::string& path, const std::vector<std::string>& overrides,
                   CommandSet commands = CommandSet::Damper);

// Time step [s] for a world built from this config: fixed, or safety * critical step (scene/time_step.h).
double resolve_dt(const SimulationDef& s, const dem::World& w);

}  // namespace vpp
