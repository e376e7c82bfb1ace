// `vppdem device FILE --out DIR`: a vacuum-packed device from its device file (vpp/device/definition.h,
// docs/devices.md), run stage by stage:
//   fill    grains on a jittered lattice inside the closed membrane (lowest sites first, no
//           overlaps), settled under gravity with local damping; the membrane's top hangs from
//           its clamp tool
//   seal    the membrane closed: its pressure fans and the air model switched on, the enclosed
//           volume recorded (a stage of no steps)
//   press   the tools' "press" segments (the gripper's bag pressed onto the object)
//   vacuum  dp ramped to stages.underpressure and held; the tools' "vacuum" segments
//   load    the tools' "load" segments (the gripper's lift)
// Records in DIR (CSV with a header, written under a temporary name and renamed): tools.csv
// (per tool its z displacement and the particles' force on it, averaged over the sample
// interval), air.csv (enclosed volume, gas volume, dp), energy.csv (the ledger from the seal on),
// summary.json (the holding force, the volume change on jamming, the inputs). A checkpoint
// (DIR/run.ckpt) after every stage and every minute of wall clock within one: `--from
// DIR/run.ckpt`, or the same command again, resumes from it, and the records come out as an
// uninterrupted run's, bit for bit.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "vpp/device/definition.h"

namespace vpp {

struct DeviceOptions {
    std::string out_dir;   // the output folder: required (an empty or blank one is refused, cfg::ConfigError naming --out)
    std::string from;      // a run.ckpt to resume ("" : DIR/run.ckpt when it exists, else a new run)
    bool quiet = false;
    bool overwrite = false;  // start afresh in a non-empty out_dir, replacing its files (its run.ckpt too)
    double checkpoint_every = 60.0;  // [s] wall clock between checkpoints within a stage (one ends every stage)
    // Stop after this stage and its checkpoint (Done: run to the end); the resume tests use it.
    DeviceStage stop_after = DeviceStage::Done;
    // [s] simulated: stop at the first step boundary at or past it, with a checkpoint (< 0: never);
    // the resume tests use it to stop within a stage.
    double stop_at_time = -1.0;
    // Polled before every step of a stage; true stops the run there as
    // stop_at_time does (a checkpoint and the records; run_device returns the stage it stopped
    // in). Python's Ctrl-C (src/python/runs.cpp); empty: never.
    std::function<bool()> stop;
};

struct DeviceResult {
    std::string stage;              // the stage the run stopped before ("done" at the end)
    std::size_t grains = 0, membrane_particles = 0, bonds = 0, samples = 0;  // grains: in the bag (after the seal)
    // The pour (grains.fill_mode = "pour"): grains placed in the column, retired in the pour
    // because they fell below the bag, and struck off at the seal (outside the membrane or
    // overlapping the opening; the spilled ones not counted again). The lattice: placed = grains.
    std::size_t grains_placed = 0, grains_spilled = 0, grains_removed_at_seal = 0;
    double seal_max_overlap = 0;    // [m] the largest overlap of a grain with a membrane particle at the seal
    double packing_seal = 0;        // [-] the grains' volume over the enclosed volume at the seal
    double dt = 0;                  // [s]
    double holding_force = 0;       // [N] largest pull (+z force of the particles) on result.object in the load stage
    double holding_time = 0;        // [s] when it was recorded
    double press_force = 0;         // [N] largest push (-F_z) on result.object before the load stage
    double object_area = 0;         // [m^2] result.object's cross-section normal to the pull (its projection on the xy plane)
    double holding_ratio = 0;       // [-] holding_force / (stages.underpressure x object_area): Brown et al.'s measure (0 without dp)
    double suction_force_max = 0;   // [N] the largest pull of the suction's seal on the object (suction.enabled)
    double seal_area = 0;           // [m^2] the seal's footprint on the object at the load stage's start (suction.enabled)
    double volume_seal = 0;         // [m^3] enclosed by the membrane at the seal
    double volume_vacuum = 0;       // [m^3] at the end of the vacuum stage
    double volume_change = 0;       // [-] (volume_vacuum - volume_seal) / volume_seal: the press's and the vacuum's
    double volume_press = 0;        // [m^3] at the start of the vacuum stage (after the press)
    double volume_change_vacuum = 0;// [-] (volume_vacuum - volume_press) / volume_press: the vacuum's alone
    double energy_residual = 0;     // [J] the ledger's residual at the last sample (0 without the ledger)
    double energy_scale = 0;        // [J] the largest |term| of the ledger over the run (its residual's scale)
    bool fill_settled = false;      // the fill came to rest before stages.fill_time
    double run_seconds = 0;         // [s] wall clock of this call
    std::vector<std::string> warnings;
    // result.cycle_tool's load-stage cycles, one entry per complete cycle: the loading branch's
    // least-squares slope [N/m], the loop's area (work done on the sample per cycle) [J], the
    // largest load [N]
    std::vector<double> cycle_stiffness, cycle_work, cycle_peak_force;
};

// Builds the device, runs (or resumes) its stages and writes the records. Throws
// cfg::ConfigError / std::runtime_error for what cannot be run (before writing anything when the
// device itself is at fault).
DeviceResult run_device(const DeviceDef& d, const DeviceOptions& o);

}  // namespace vpp
