// `vppdem sweep` on a device study (vpp/study/file.h DeviceStudy; docs/devices.md, "Studies"):
// every case of the study with every seed, seed by seed (each case gets seed 1 before any gets
// seed 2, so a study cut short is balanced), each a `vppdem device` run into DIR/<case>_s<seed>/
// (DIR/<case>/ without seeds) under the one resume rule (scene::resume_checkpoint): a finished
// run (its summary.json at stage "done") is skipped, an interrupted one resumes from its
// run.ckpt. The folder's tables DIR/summary.csv (a row per run) and DIR/summary_cases.csv (a row
// per case over its seeds: each number's n, mean, sd and 95% Student-t half width, as a damper
// study's); with a results folder, the tables and the small records of the finished runs
// (summary.json, case.toml, build.json and tools.csv.gz: tools.csv from the press on, six digits,
// gzip) published there, each through a temporary name.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "vpp/study/file.h"

namespace vpp {

// One run of a device study: a case with a seed.
struct DeviceStudyRun {
    std::string folder;              // "dp0_s1" (the case's name without seeds)
    std::size_t case_index = 0;      // into DeviceStudy::cases
    int seed = 0;                    // 0: the device file's (a study without seeds)
    std::vector<std::string> overrides;  // [set], the case's keys, then simulation.seed
};
// The runs in the order they run: seed-major.
std::vector<DeviceStudyRun> expand_device_study(const DeviceStudy& s);
// `sweep --list` of a device study: a line per run (folder, case, seed, overrides).
std::string list_device_runs(const DeviceStudy& s);

// The columns of summary.csv after case, seed and folder: the numbers of the device's
// summary.json (docs/devices.md, "Records"), then status and message.
const std::vector<std::string>& device_study_numbers();

struct DeviceRunOutcome {
    std::string status;              // "ok", "failed", "not run"
    std::string message;             // why it failed or did not run
    std::vector<double> numbers;     // device_study_numbers() of its summary.json (ok only)
};

struct DeviceSweepOptions {
    std::string out_dir;
    std::string publish;             // results folder for the small records ("" : none)
    bool quiet = false;
    bool report_only = false;        // run nothing: the table of what is finished in out_dir
    bool mix_builds = false;         // continue in a folder whose runs another build made
    double checkpoint_every = 60.0;  // [s] wall clock between checkpoints within a stage
    // Polled before every step of a run and before each run; true stops the study: the running
    // run as DeviceOptions::stop stops it (its run.ckpt resumes it), it and the runs after it
    // "not run", the tables written. Python's Ctrl-C; empty: never.
    std::function<bool()> stop;
};

struct DeviceSweepResult {
    std::vector<DeviceStudyRun> runs;
    std::vector<DeviceRunOutcome> outcomes;
    int failed = 0;
};

// Runs (or resumes) the study into opt.out_dir and writes its summary.csv and summary_cases.csv
// (and publishes). A run that fails is an outcome (its folder's FAILED marker says why); the
// others go on. Throws cfg::ConfigError before anything runs for a folder that holds another
// build's runs (without mix_builds) or a run of other settings (its case.toml).
DeviceSweepResult run_device_study(const DeviceStudy& s, const DeviceSweepOptions& opt);

}  // namespace vpp
