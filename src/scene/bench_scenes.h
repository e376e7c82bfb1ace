// `vppdem bench`: the benchmark scenes shared with other DEM codes (docs/benchmarks.md), timed.
#pragma once

#include <string>

namespace scene {

struct BenchOptions {
    std::string scene;        // "grains-in-cylinder", "foil-plus-grains" or "checkpoint" (the World of --state)
    std::string grains;       // grains-in-cylinder: CSV x,y,z,r
    std::string scene_dir;    // foil-plus-grains: folder with foil_*.csv
    long warmup = 0;          // steps before timing
    long steps = 1000;        // timed steps
    int threads = 1;
    double underpressure = 0; // [Pa] foil-plus-grains: follower pressure on the foil
    bool profile = false;     // print the time per phase of the timed steps
    std::string state;        // checkpoint of the state after the warm-up: loaded if it exists, else written
    bool energy = false;      // keep the energy ledger during the timed steps
    std::string simd;         // run the kernels on this SIMD target only (names: --simd list); "" = best
    int batch = 0;            // checkpoint: > 0 steps that many copies of the World as one batch (the
                              // batch engine's host backend, docs/gpu.md) instead of the World itself
    std::string backend = "host";  // --batch on: host (step_host), cuda (the device backend on the GPU),
                                   // emulated (the device backend's kernels on the host)
    int chunk = 0;            // device backends: 0 steps them half step by half step (DeviceBatch::step);
                              // K > 0 in chunks of up to K steps (DeviceBatch::run), one event at the end
};

// Runs the benchmark and prints one JSON line last (a contract read by outside tools). With
// `profile`, a table of the time per phase comes first and the JSON line gains "profile".
void run_bench(const BenchOptions& opt);

}  // namespace scene
