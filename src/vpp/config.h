// Configuration of the VPP commands (tension, envelope, damper): one schema for all, so a
// damper config can be handed to any of them. Defaults are the paper's calibrated values
// (docs/model.md, ../shared/spec/model.md section 7). Every key is checked.
#pragma once

#include <cstdint>
#include <set>
#include <string>

#include <toml++/toml.h>

#include "vpp/foil.h"

namespace vpp {

struct GrainsDef {
    double radius = 2.965e-3;       // [m] r_k
    double density = 2689.639;      // [kg/m^3]
    double young = 2.3e9;           // [Pa] E_k
    double friction = 0.6;          // [-] mu_k
    double stiffness_ratio = 0.5;   // [-] ks/kn
    double volume_fraction = 0.54;  // [-] phi
    double restitution = 1.0;       // [-] normal restitution of grain contacts in the cycling (1: no dashpot)
};

struct DamperDef {
    double radius = 0.0255;  // [m] r_p
    double height = 0.100;   // [m] H_p
    double cap_friction = -1.0;  // [-] grain-cap friction; < 0: the grains' friction
    // Preparation: after the pour, add grains (re-fill, as the experiment does) until they stand
    // above the damper height, so that the cap comes down onto them and compresses them to
    // H_p (docs/damper.md, "Preparation"). false: exactly the grains of grains.volume_fraction,
    // poured once; the cap may end above them (warned).
    bool refill = true;
};

// dp is the atmosphere's pressure minus the pressure inside the foil: at most a perfect vacuum.
inline constexpr double kAtmosphericPressure = 101325.0;  // [Pa]

struct ProcessDef {
    double underpressure = 0.06e6;  // [Pa] dp in [0, kAtmosphericPressure] (the envelope command defaults to 0.01e6)
    double ramp_time = 0.02;        // [s] dp rises linearly from 0 over this time
    double hold_time = 0.08;        // [s] envelope: time held at full dp after the ramp
    double amplitude = 0.010;       // [m] dz
    double velocity = 3.33e-4;      // [m/s] v_z
    double start_offset = 0.0;      // [m] cap moved down by this (up if < 0) before cycling
    bool compression_first = true;  // direction "compression" (down first) or "extension"
    int64_t cycles = 4;
    int64_t samples_per_cycle = 500;
    double sample_window = 2e-4;    // [s]
    // The air inside (vpp/gas.h; docs/damper.md, "The air inside").
    int pressure_model = 0;           // 0 "constant": dp held (the paper); 1 "pump": gas, pump, leak
    double pump_speed = 2.0 / 3600.0; // [m^3/s] S (2 m^3/h, a small rotary-vane pump)
    double bleed_rate = 2.0 / 3600.0; // [m^3/s] B: the regulator's bleed lets air in below the set point
    double leak_rate = 0.0;           // [m^3/s] C: air leaks in at C (p_atm - p_inside)
    bool pump_down = false;           // the vacuum stage pumps down from the atmosphere (else: the ramp)
    // The stroke's shape (docs/damper.md, "Waveforms and frequency").
    int waveform = 0;                 // 0 "triangle" (the paper), 1 "sine"
    double frequency = 0.0;           // [Hz] cycles per second; 0: the period 2 A / v of velocity
    // Local damping from the vacuum on: < 0 is "auto", simulation.local_damping throughout. A
    // dynamic run keeps the preparation's damping (which brings the pour to rest) and cycles
    // with 0 and grain restitution, from one prepared sample (docs/damper.md).
    double local_damping = -1.0;      // [-] lambda after the preparation; < 0: simulation.local_damping
};


// The loading cycle's period [s]: 1 / frequency, or 2 A / v (the triangle at process.velocity).
double cycle_period(const ProcessDef& p);
// The cap's largest speed in the cycle [m/s]: 2 A / T for the triangle (process.velocity when
// no frequency is given), pi A / T for the sine.
double peak_speed(const ProcessDef& p);

struct TensionDef {
    int64_t sites_along = 37;   // sites in the pulling direction (paper: 37)
    int64_t sites_across = 12;  // sites across (paper: 12)
    double strain = 0.02;       // [-] final engineering strain
    double speed = 0.05;        // [m/s] pulling speed (quasi-static: << bond wave speed ~ 500 m/s)
};

struct SimulationDef {
    bool dt_auto = true;
    double dt = 0.0;            // [s] when not auto
    double dt_safety = 0.3;     // [-] dt = safety * critical step when auto
    double local_damping = 0.2; // [-]
    int threads = 1;            // 0 in the file = the free cores (scene/threads.h)
    uint64_t seed = 1;
    double skin = 0.0;          // [m] 0 = half the smallest radius
};

struct OutputDef {
    double interval = 0.0;      // [s] rows of the time series; 0 = command default
    double vtk_interval = 0.0;  // [s] VTK frames; 0 = command default
    bool energy = true;         // damper: energy ledger during cycling (energy.csv; ~25% slower)
    bool air = false;           // damper: the air columns of forces.csv with the constant model too
};

// Post-processing of the recorded loops; acts on no simulation, so it never needs a new run.
struct AnalysisDef {
    double settle_tolerance = 0.03;  // [-] relative scatter of one cycle's W when stationary (vpp/settle.h)
};

struct Config {
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
};

// The local damping of the vacuum stage and the cycling [-]: process.local_damping, or when that
// is "auto" simulation.local_damping (which the preparation always uses).
double cycling_local_damping(const Config& c);

// Defaults that differ between commands.
struct CommandDefaults {
    double underpressure = 0.06e6;  // [Pa] the envelope check uses 0.01 MPa
    double dt_safety = 0.3;         // [-]
    int threads = 1;                // 0 = the free cores (scene/threads.h)
};

// Reads the config (empty path: all defaults) with --set overrides.
Config load_config(const std::string& path, const std::vector<std::string>& overrides,
                   const CommandDefaults& defaults = {});

// Time step for a world built from this config: fixed, or safety * critical step.
double resolve_dt(const SimulationDef& s, const dem::World& w);

}  // namespace vpp
