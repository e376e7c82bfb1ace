// `vppdem damper`: the VPP damper end to end (paper section 4; spec sections 5-7).
//   prepare: foil cylinder, grains generated in the foil and a funnel above it, frictionless
//            fall, upper cap down to the damper height, funnel removed  -> prepared.ckpt
//   vacuum:  grain friction restored, dp ramped up, sample brought to rest
//   cycle:   upper cap and top foil ring moved together, triangular displacement
//   record:  forces.csv (grains on the cap, foil on the top ring), cycles.csv, summary.json
#pragma once

#include <map>
#include <string>
#include <vector>

#include "vpp/analysis.h"
#include "vpp/config.h"
#include "vpp/settle.h"

namespace vpp {

struct DamperOptions {
    std::string out_dir;
    std::string from;        // checkpoint to start from (prepared.ckpt or run.ckpt); empty: prepare
    bool quiet = false;
    bool plot = true;
    bool overwrite = false;  // replace files in a non-empty out_dir (resuming from it needs none)
    double checkpoint_every = 60.0;  // [s] wall clock between run.ckpt writes
    bool profile = false;    // print the time per phase of the cycling (dem/core/profile.h)
};

struct DamperResult {
    std::size_t grains = 0, foil_particles = 0, bonds = 0;
    int foil_columns = 0, foil_rows = 0;
    double foil_radius = 0, height = 0, dt = 0;
    double inertial_number = 0;
    std::vector<CycleResult> cycles;  // with the stationarity flag (settled) of each
    Settling settling;                // analysis.settle_tolerance applied to the cycles' W
    // The preparation and the start of cycling as measured ("prepare.cap_force",
    // "cycle.packing_fraction", ...; summary.json "preparation", "start_of_cycling").
    std::map<std::string, double> report;
    // Every warning of the run, the preparation's included (summary.json "warnings").
    std::vector<std::string> warnings;
    double run_seconds = 0;
    Config config;  // the settings the run used: a run from a checkpoint takes some of its values
};

// With opt.from: the checkpoint's geometry replaces the config's (a geometry key the config
// gives with another value is an error), and a checkpoint of a run that started (run.ckpt past
// the preparation) also gives its contact, process and simulation settings (kRunKeys in
// damper.cpp; a key given with another value is an error naming both values).
DamperResult run_damper(const Config& c, const DamperOptions& opt);

// Number of grains for the volume fraction: round(phi * pi r_p^2 H_p / (4/3 pi r_k^3)).
std::size_t grain_count(const Config& c);

// Inertial number I = gamma_dot d sqrt(rho / p) of the cycling: gamma_dot = v_z / H,
// d = 2 r_k, p = dp. Quasi-static when I << 1e-3.
double inertial_number(const Config& c, double height);

}  // namespace vpp
