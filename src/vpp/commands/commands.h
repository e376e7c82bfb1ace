// What the commands that both front doors offer take: the command line (src/cli) and the Python
// module (src/python) fill one plain struct of a command's arguments and call one function that
// turns it into what the run needs (its config or study and its options), so that the defaults,
// the checks the parsers cannot make and their messages are written once, here. The doors only
// parse (CLI11, pybind11) and run what the function returns. The defaults are the run's options'
// own (DamperOptions{}.checkpoint_every, ...); a door that wants another (Python is quiet unless
// told otherwise) says so where it declares the argument.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "vpp/analysis/record_format.h"
#include "vpp/calibration/calibrate.h"
#include "vpp/damper/damper.h"
#include "vpp/device/definition.h"
#include "vpp/device/run.h"
#include "vpp/study/device_study.h"
#include "vpp/study/file.h"
#include "vpp/study/study.h"

namespace vpp {

// The front door the arguments came through: a message names an option as that door spells it
// (--jobs on the command line, jobs in Python).
enum class Door { CommandLine, Python };

// `vppdem damper` and vppdem.Damper: how the run writes and reports. The config is read apart
// (vpp::load_config(file, sets)): Python reads it into a Config before it makes the Damper.
struct DamperArgs {
    std::string out;   // output folder; "": nothing written (Python only)
    std::string from;  // checkpoint to start from: prepared.ckpt, or run.ckpt to resume
    bool overwrite = false, quiet = false;
    bool plot = DamperOptions{}.plot;                          // the PNG loops at the end
    bool profile = false;                                      // the time per phase of the cycling
    double checkpoint_every = DamperOptions{}.checkpoint_every;  // [s] wall clock between run.ckpt writes
    double progress_every = DamperOptions{}.progress_every;      // [s] wall clock between progress lines
    std::string backend = "cpu";                               // cpu or cuda (vpp::damper_backend)
};
DamperOptions damper_options(const DamperArgs& a);

// `vppdem device` and vppdem.device().
struct DeviceArgs {
    std::string file;               // the device file (TOML)
    std::vector<std::string> sets;  // section.key=value overrides, in order
    std::string out;                // output folder (running into it again resumes from its run.ckpt)
    std::string from;               // a run.ckpt to resume from ("": DIR/run.ckpt when it exists)
    bool overwrite = false, quiet = false;
    double checkpoint_every = DeviceOptions{}.checkpoint_every;  // [s] wall clock within a stage
};
struct DeviceCommand {
    DeviceDef device;
    DeviceOptions options;
};
// Reads the device file with the overrides (ConfigError naming the key).
DeviceCommand device_command(const DeviceArgs& a);

// `vppdem sweep` and `vppdem calibrate`, vppdem.sweep(), vppdem.calibrate() and the study's
// cases (sweep --list, vppdem.Study): the study file and how its cases run.
struct StudyArgs {
    Door door = Door::CommandLine;
    std::string study;              // the study file (TOML; docs/studies.md)
    std::vector<std::string> sets;  // fixed overrides for every case
    int seeds = 0;                  // > 0: simulation.seed = 1..seeds replaces the study's seeds
    std::string out;                // output folder (running into it again resumes the study)
    int jobs = SweepOptions{}.jobs;  // cases at once; 0: the free cores / threads per case
    bool quiet = false, mix_builds = false;
    bool plot = true;                                            // the PNG plots at the end (rank 0)
    double checkpoint_every = SweepOptions{}.checkpoint_every;  // [s] wall clock, of each case
    double progress_every = SweepOptions{}.progress_every;      // [s] wall clock, the study's lines
    std::string backend = SweepOptions{}.backend;               // "cpu", "batch" or "cuda"
    std::string publish;                                        // results folder ("": none)
    bool watched = false;           // a progress callback follows the cases (Python)
    int rank = 0, ranks = 1;        // MPI (the command line under mpirun)
};
struct SweepArgs : StudyArgs {
    bool report_only = false;  // run nothing: the tables of the cases finished in `out`
};
// A damper study and its sweep's options, or a device study and its own: exactly one of `study`
// and `device_study` is set.
struct SweepCommand {
    std::optional<Study> study;
    SweepOptions options;
    std::optional<DeviceStudy> device_study;
    DeviceSweepOptions device_options;
};
// Reads and checks the study (ConfigError naming the key); a device study runs one case at a
// time on the CPU, and refuses what would run more (jobs, a batch backend, MPI, a progress
// callback: it has no per-case progress).
SweepCommand sweep_command(const SweepArgs& a);

struct CalibrateArgs : StudyArgs {
    std::string experiment;  // the measured loop: CSV with a header
    RecordFormat format;     // its columns, units and sign convention
    std::string force_column = CalibrateOptions{}.force_column;  // the simulated column compared
    int points = CalibrateOptions{}.points;                      // displacements per branch in the misfit
    std::string predict;                                         // "key=v1,v2,...": the best point at these values
    std::vector<std::string> predict_experiments;                // a measured loop per predicted value
};
struct CalibrateCommand {
    Study study;
    CalibrateOptions options;
};
// Reads and checks the study, which must be a damper study (ConfigError otherwise).
CalibrateCommand calibrate_command(const CalibrateArgs& a);

// A record's units as the commands name them (--displacement-unit, --force-unit): its values
// times these are metres and newtons. Throws ConfigError for another name.
double displacement_unit_scale(const std::string& unit);  // "m" 1, "mm" 1e-3
double force_unit_scale(const std::string& unit);         // "N" 1, "kN" 1e3

}  // namespace vpp
