// The vppdem command line: one function per command declares its options (add_NAME) into the
// arguments its run reads, one runs it (run_NAME); main() parses and calls the one given. The
// commands Python offers too turn their arguments into their options in vpp/commands/commands.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "dem/batch/batch_stepper.h"
#include "scene/bench_scenes.h"
#include "scene/build_info.h"
#include "scene/config.h"
#include "scene/scene_runner.h"
#include "scene/suggest.h"
#include "scene/threads.h"
#include "vpp/settings/config.h"
#include "vpp/analysis/analysis.h"
#include "vpp/analysis/analyze_command.h"
#include "vpp/calibration/calibrate.h"
#include "vpp/commands/commands.h"
#include "vpp/damper/damper.h"
#include "vpp/device/definition.h"
#include "vpp/device/run.h"
#include "vpp/study/device_study.h"
#include "vpp/foil_checks/envelope.h"
#include "vpp/analysis/plot.h"
#include "vpp/settings/settings.h"
#include "vpp/study/key_reference.h"
#include "vpp/study/mpi.h"
#include "vpp/study/study.h"
#include "vpp/foil_checks/tension.h"

namespace {

// The option checks: CLI11's PositiveNumber and NonNegativeNumber let "nan" through (no
// comparison holds for it) and name their bounds with std::to_string(DBL_MAX), a 309-digit
// number. These refuse every non-finite value and say the bound as it is written.
CLI::Validator finite_at_least(double lo, bool open, const char* name) {
    return CLI::Validator(
        [lo, open](std::string& in) -> std::string {
            double v = 0;
            const bool ok = CLI::detail::lexical_cast(in, v);
            if (ok && std::isfinite(v) && (open ? v > lo : v >= lo)) return "";
            char bound[32];
            std::snprintf(bound, sizeof bound, "%g", lo);
            return "value '" + in + "' must be a finite number " + (open ? "> " : ">= ") + bound;
        },
        name);
}
const CLI::Validator kPositive = finite_at_least(0.0, true, "POSITIVE");
const CLI::Validator kNonNegative = finite_at_least(0.0, false, "NONNEGATIVE");
// --out: an empty or blank value would be the current folder (scene::require_output_path).
const CLI::Validator kOutputPath(
    [](std::string& in) -> std::string {
        try {
            scene::require_output_path(in, "value");
        } catch (const std::exception& e) {
            return e.what();
        }
        return "";
    },
    "PATH");

// How a force-displacement record is laid out: `analyze` and `calibrate` read a rig's file with
// the same flags and the same meaning.
void add_record_format(CLI::App* cmd, vpp::RecordFormat& f) {
    cmd->add_option("--time-column", f.time_col, "time column (default " + f.time_col + ")");
    cmd->add_option("--displacement-column", f.disp_col, "displacement column (default " + f.disp_col + ")");
    cmd->add_option("--force-column", f.force_col, "force column (default " + f.force_col + ")");
    cmd->add_option_function<std::string>(
           "--displacement-unit", [&f](const std::string& u) { f.disp_scale = vpp::displacement_unit_scale(u); },
           "m (default) or mm")
        ->check(CLI::IsMember({"m", "mm"}));
    cmd->add_option_function<std::string>(
           "--force-unit", [&f](const std::string& u) { f.force_scale = vpp::force_unit_scale(u); }, "N (default) or kN")
        ->check(CLI::IsMember({"N", "kN"}));
    cmd->add_flag("--compression-negative", f.compression_negative,
                  "The record counts compression negative (displacement and force): flip both");
}

// vppdem scene FILE.toml --out DIR [--set key=value ...] [--overwrite]
struct SceneArgs {
    std::string file, out;
    std::vector<std::string> sets;
    bool overwrite = false, quiet = false;
};

CLI::App* add_scene(CLI::App& app, SceneArgs& a) {
    auto* cmd = app.add_subcommand("scene", "Run a generic DEM scene described in TOML (docs/scene.md)");
    cmd->add_option("file", a.file, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", a.out, "Output directory")->required()->check(kOutputPath);
    // allow_extra_args(false): one value per --set, so positionals may follow it.
    cmd->add_option("--set", a.sets, "Override a config key: section.key=value (repeatable)")->allow_extra_args(false);
    cmd->add_flag("--overwrite", a.overwrite, "Replace files in a non-empty output directory");
    cmd->add_flag("--quiet", a.quiet, "No progress output");
    return cmd;
}

int run_scene(const SceneArgs& a) {
    const auto root = cfg::load(a.file, a.sets);
    const std::string base = std::filesystem::path(a.file).parent_path().string();
    scene::Scene sc = scene::build_scene(root, base.empty() ? "." : base);
    scene::run_scene(sc, {a.out, a.overwrite, a.quiet});
    return 0;
}

// vppdem bench SCENE ...
struct BenchArgs {
    scene::BenchOptions options;
    CLI::Option* threads = nullptr;  // not given: scene::default_threads()
};

CLI::App* add_bench(CLI::App& app, BenchArgs& a) {
    auto* cmd = app.add_subcommand("bench", "Time a shared benchmark scene (docs/benchmarks.md)");
    scene::BenchOptions& bo = a.options;
    cmd->add_option("scene", bo.scene, "grains-in-cylinder | foil-plus-grains | checkpoint (the World saved in --state)")
        ->required()
        ->check(CLI::IsMember({"grains-in-cylinder", "foil-plus-grains", "checkpoint"}));
    cmd->add_option("--grains", bo.grains, "grains_N.csv (grains-in-cylinder)")->check(CLI::ExistingFile);
    cmd->add_option("--scene-dir", bo.scene_dir, "folder with foil_*.csv (foil-plus-grains)")
        ->check(CLI::ExistingDirectory);
    cmd->add_option("--warmup", bo.warmup, "untimed steps first")->check(kNonNegative);
    cmd->add_option("--steps", bo.steps, "timed steps")->check(kPositive);
    a.threads = cmd->add_option("--threads", bo.threads, std::string("threads of the step (") + scene::kDefaultThreadsHelp + ")")
        ->check(kPositive);
    cmd->add_option("--underpressure", bo.underpressure, "[Pa] follower pressure on the foil");
    cmd->add_flag("--profile", bo.profile, "Print the time per phase (neighbour search, contacts, ...)");
    cmd->add_option("--state", bo.state, "Checkpoint after the warm-up: loaded instead of warming up if it exists, else written");
    cmd->add_flag("--energy", bo.energy, "Keep the energy ledger during the timed steps");
    cmd->add_option("--batch", bo.batch, "checkpoint: step this many copies of the World as one batch (the batch "
                                         "engine's host backend, docs/gpu.md)")
        ->check(kPositive);
    cmd->add_option("--backend", bo.backend, "--batch on: host (the host backend), cuda (the device backend on the GPU; "
                                             "a build with VPPDEM_CUDA), emulated (the device backend's kernels on the host)")
        ->check(CLI::IsMember({"host", "cuda", "emulated"}));
    cmd->add_option("--chunk", bo.chunk, "--backend cuda or emulated: the device runs up to this many steps per launch "
                                         "sequence, the host only laying systems out (docs/gpu.md); 0: half step by half step")
        ->check(kNonNegative);
    cmd->add_option("--simd", bo.simd, "Run the kernels on this SIMD target only (default: the best here)");
    return cmd;
}

int run_bench(const BenchArgs& a) {
    scene::BenchOptions o = a.options;
    if (a.threads->count() == 0) o.threads = scene::default_threads();
    scene::run_bench(o);
    return 0;
}

// The options every command on a damper config has (tension, envelope, damper), into the
// fields of those names: vppdem NAME [CONFIG] --out DIR [--set ...] [--overwrite] [--quiet].
template <class Args>
CLI::App* add_config_command(CLI::App& app, const char* name, const char* help, Args& a) {
    auto* cmd = app.add_subcommand(name, help);
    cmd->add_option("config", a.config, "Config file (TOML); defaults are the paper's values")->check(CLI::ExistingFile);
    cmd->add_option("--out", a.out, "Output directory")->required()->check(kOutputPath);
    cmd->add_option("--set", a.sets, "Override a config key: section.key=value (repeatable)")->allow_extra_args(false);
    cmd->add_flag("--overwrite", a.overwrite, "Replace files in a non-empty output directory");
    cmd->add_flag("--quiet", a.quiet, "No progress output");
    return cmd;
}

// vppdem tension|envelope [CONFIG] --out DIR [--set ...]: the foil checks of the paper.
struct FoilCheckArgs {
    std::string config, out;
    std::vector<std::string> sets;
    bool overwrite = false, quiet = false;
};

int run_tension(const FoilCheckArgs& a) {
    const vpp::Config c = vpp::load_config(a.config, a.sets, vpp::CommandSet::Foil);
    // Held until the command ends: one run at a time writes into a folder.
    const dem::FolderLock lock = scene::prepare_output_dir(a.out, a.overwrite);
    vpp::run_tension(c, a.out, a.quiet);
    return 0;
}

int run_envelope(const FoilCheckArgs& a) {
    const vpp::Config c = vpp::load_config(a.config, a.sets, vpp::CommandSet::Foil);
    const dem::FolderLock lock = scene::prepare_output_dir(a.out, a.overwrite);
    vpp::run_envelope(c, a.out, a.quiet);
    return 0;
}

// vppdem damper [CONFIG] --out DIR [--from CKPT] [--no-plot]
struct DamperCommandArgs : vpp::DamperArgs {
    std::string config;
    std::vector<std::string> sets;
};

CLI::App* add_damper(CLI::App& app, DamperCommandArgs& a) {
    auto* cmd = add_config_command(app, "damper", "Simulate a VPP damper: prepare, evacuate, cycle, record, analyse", a);
    cmd->add_option("--progress-every", a.progress_every,
                    "[s] wall-clock time between progress lines (default 2 on a terminal, 30 into a file)")
        ->check(kPositive);
    cmd->add_option("--from", a.from, "Start from a checkpoint (prepared.ckpt, or run.ckpt to resume)")
        ->check(CLI::ExistingFile);
    cmd->add_flag_callback("--no-plot", [&a] { a.plot = false; }, "Do not draw the PNG loops at the end");
    cmd->add_flag("--profile", a.profile, "Print the time per phase of the cycling");
    cmd->add_option("--checkpoint-every", a.checkpoint_every, "[s] wall-clock time between checkpoints")->check(kPositive);
    cmd->add_option("--backend", a.backend,
                    "How the cycling is stepped: cpu (World, default) or cuda (the batch engine on a GPU, the steps "
                    "between samples run by the device alone; the same bits; docs/gpu.md)")
        ->check(CLI::IsMember({"cpu", "cuda"}));
    return cmd;
}

int run_damper(const DamperCommandArgs& a) {
    const vpp::Config c = vpp::load_config(a.config, a.sets);
    // Before anything runs: a cuda backend this build or machine cannot give is refused (exit 2).
    const std::unique_ptr<dem::batch::BatchStepper> device = vpp::damper_backend(a.backend);
    vpp::DamperOptions o = vpp::damper_options(a);
    o.batch = device.get();
    // Fewer cycles recorded than asked is a failed run (exit 1), not a refusal (2): the records
    // are written, summary.json says so under "warnings".
    return vpp::run_damper(c, o).incomplete ? 1 : 0;
}

// vppdem device FILE --out DIR [--from CKPT]: a vacuum-packed device from a device file (docs/devices.md).
CLI::App* add_device(CLI::App& app, vpp::DeviceArgs& a) {
    auto* cmd = app.add_subcommand("device", "Run a vacuum-packed device from meshes: fill, seal, press, vacuum, load (docs/devices.md)");
    cmd->add_option("file", a.file, "Device file (TOML)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", a.out, "Output directory (running into it again resumes from its run.ckpt)")->required()->check(kOutputPath);
    cmd->add_option("--from", a.from, "Resume from this checkpoint (a run.ckpt)")->check(CLI::ExistingFile);
    cmd->add_option("--set", a.sets, "Override a device key: section.key=value (repeatable)")->allow_extra_args(false);
    cmd->add_flag("--overwrite", a.overwrite, "Start afresh in a non-empty output directory, replacing its files (its run.ckpt too)");
    cmd->add_flag("--quiet", a.quiet, "No progress output");
    cmd->add_option("--checkpoint-every", a.checkpoint_every, "[s] wall-clock time between checkpoints within a stage")
        ->check(kPositive);
    return cmd;
}

int run_device(const vpp::DeviceArgs& a) {
    const vpp::DeviceCommand c = vpp::device_command(a);
    vpp::run_device(c.device, c.options);
    return 0;
}

// vppdem analyze FORCES.csv: cycles.csv from any force-displacement record.
CLI::App* add_analyze(CLI::App& app, vpp::AnalyzeOptions& ao) {
    auto* cmd = app.add_subcommand("analyze", "Energy per cycle and W of a forces CSV, written to a new file");
    cmd->add_option("forces", ao.forces, "CSV with a header")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", ao.out, std::string("Output file (default: ") + vpp::kAnalyzeOutput +
                                         " beside the input; an existing file needs --overwrite)")
        ->check(kOutputPath);
    cmd->add_option("--radius", ao.radius,
                    "[m] damper radius for W = energy / (pi r^2) (default: damper.radius of the summary.json "
                    "beside the input, else 0.0255, the paper's)")
        ->check(kPositive);
    cmd->add_flag("--overwrite", ao.overwrite, "Replace an existing output file");
    add_record_format(cmd, ao.format);
    cmd->add_option("--cycle-column", ao.format.cycle_col,
                    "cycle column (default cycle); empty or absent: cycles found from the displacement");
    return cmd;
}

// vppdem plot DIR
CLI::App* add_plot(CLI::App& app, std::string& dir) {
    auto* cmd = app.add_subcommand("plot", "Draw the plots of a damper, device, sweep or calibration output folder (PNG)");
    cmd->add_option("dir", dir, "damper, device, sweep (damper or device study) or calibration output folder")
        ->required()
        ->check(CLI::ExistingDirectory);
    return cmd;
}

// The options sweep and calibrate share: vppdem NAME STUDY.toml --out DIR [--jobs N] ...
CLI::App* add_study_command(CLI::App& app, const char* name, const char* help, vpp::StudyArgs& a) {
    auto* cmd = app.add_subcommand(name, help);
    cmd->add_option("study", a.study, "Study file (TOML; docs/studies.md)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", a.out, "Output directory (re-running into it resumes the study)")->required()->check(kOutputPath);
    cmd->add_option("--jobs", a.jobs, "Cases run at once on this machine (default: the free cores / threads per case; "
                                      "free cores: the cores this process may use minus those busy with other work)")
        ->check(kNonNegative);
    cmd->add_option("--set", a.sets, "Fixed override for every case: section.key=value (repeatable)")
        ->allow_extra_args(false);
    cmd->add_option("--checkpoint-every", a.checkpoint_every, "[s] wall-clock time between checkpoints of a case")
        ->check(kPositive);
    cmd->add_option("--progress-every", a.progress_every,
                    "[s] wall-clock time between the study's progress lines (cases done, the running cases' "
                    "stages, time left; default 2 on a terminal, 30 into a file)")
        ->check(kPositive);
    cmd->add_option("--seeds", a.seeds, "Ensemble: run every case with simulation.seed = 1..N (replaces the "
                                        "study's seeds; docs/studies.md)")
        ->check(CLI::Range(1, vpp::kMaxSeeds, "1.." + std::to_string(vpp::kMaxSeeds)));
    cmd->add_flag("--quiet", a.quiet, "No progress output");
    cmd->add_flag_callback("--no-plot", [&a] { a.plot = false; }, "Do not draw the PNG plots at the end");
    cmd->add_option("--backend", a.backend,
                    "How the cases' cycling is stepped: cpu (each case its own World, default), batch (the "
                    "running cases in lockstep through the batch engine's host backend, the same bits), cuda "
                    "(the batch engine on a GPU; docs/gpu.md)")
        ->check(CLI::IsMember({"cpu", "batch", "cuda"}));
    cmd->add_option("--publish", a.publish,
                    "Keep the finished cases' small records (case.toml, summary.json, cycles.csv, build.json) and "
                    "the tables in this folder, each file through a temporary name; records there that --out "
                    "lacks are put back first and count as finished (docs/studies.md, \"Publishing\")");
    cmd->add_flag("--mix-builds", a.mix_builds,
                  "Continue in a folder whose cases another build ran (refused without it: their build.json "
                  "names the builds; docs/studies.md, \"Resuming\")");
    return cmd;
}

// vppdem sweep STUDY.toml --out DIR [--jobs N] [--list | --report-only]
struct SweepCommandArgs : vpp::SweepArgs {
    bool list = false;  // check the study and list its cases; run nothing
};

CLI::App* add_sweep(CLI::App& app, SweepCommandArgs& a) {
    auto* cmd = add_study_command(
        app, "sweep", "Run a parameter study: every combination of a grid of config values (docs/studies.md)", a);
    auto* list_flag = cmd->add_flag("--list", a.list, "Check the study and list its cases and preparations; run nothing");
    cmd->add_flag("--report-only", a.report_only,
                  "Run nothing: write summary.csv, summary_cases.csv (and summary_paired.csv) from the cases finished "
                  "in --out, the others marked 'not run' (docs/studies.md, \"Resuming\")")
        ->excludes(list_flag);
    return cmd;
}

// A device study (docs/devices.md, "Studies"): its runs one after the other on this process,
// each a `vppdem device` run with the threads its device file sets.
int run_device_sweep(const SweepCommandArgs& a, const vpp::SweepCommand& c) {
    if (a.list) {
        std::printf("%s", vpp::list_device_runs(*c.device_study).c_str());
        return 0;
    }
    if (a.progress_every > 0 && !a.quiet)
        std::fprintf(stderr, "warning: --progress-every is not used by a device study: its runs print "
                             "their own progress lines\n");
    const vpp::DeviceSweepResult r = vpp::run_device_study(*c.device_study, c.device_options);
    // Each number against the case (sweep_numbers.png), as a damper study's plots; --no-plot skips it.
    if (a.plot && !a.report_only) vpp::plot_device_study_dir(a.out, a.quiet);
    return r.failed && !a.report_only ? 1 : 0;
}

int run_damper_sweep(const SweepCommandArgs& a, const vpp::SweepCommand& c) {
    if (a.list) {
        const auto cases = vpp::expand_study(*c.study);
        // With samples_from, the sample each group would branch from (its folder's path).
        std::map<int, std::string> samples;
        for (const auto& [group, path] : vpp::find_shared_samples(*c.study, c.options, cases)) samples[group] = path.string();
        if (a.rank == 0) std::printf("%s", vpp::list_cases(cases, samples).c_str());
        return 0;
    }
    const vpp::SweepResult r = vpp::run_sweep(*c.study, c.options);  // holds --out's lock for the plots too
    if (a.rank == 0 && a.plot && !a.report_only) vpp::plot_sweep_dir(a.out, a.quiet);
    // A report is a success whatever the cases' state: unfinished and unreadable cases are in
    // its tables.
    return r.failed && !a.report_only ? 1 : 0;
}

int run_sweep(const SweepCommandArgs& a) {
    const vpp::SweepCommand c = vpp::sweep_command(a);
    const int rc = c.device_study ? run_device_sweep(a, c) : run_damper_sweep(a, c);
    vpp::mpi_finalize();
    return rc;
}

// vppdem calibrate STUDY.toml --experiment EXP.csv --out DIR
CLI::App* add_calibrate(CLI::App& app, vpp::CalibrateArgs& a) {
    auto* cmd = add_study_command(
        app, "calibrate", "Grid search of a study against a measured force-displacement loop (docs/studies.md)", a);
    cmd->add_option("--experiment", a.experiment, "Measured loop: CSV with a header")->required()->check(CLI::ExistingFile);
    add_record_format(cmd, a.format);
    cmd->add_option("--simulated-force", a.force_column,
                    "simulated column compared: force_zeroed, force_total, or force_machine_zeroed (the pump "
                    "model's testing-machine force, docs/damper.md \"The air inside\")")
        ->check(CLI::IsMember({"force_zeroed", "force_total", "force_machine_zeroed"}));
    cmd->add_option("--points", a.points, "displacements per branch in the misfit")->check(CLI::Range(4, 100000));
    cmd->add_option("--predict", a.predict, "run the best point at other values: key=v1,v2,...");
    cmd->add_option("--predict-experiment", a.predict_experiments,
                    "measured loop for each --predict value, in order (repeatable)")
        ->allow_extra_args(false)
        ->check(CLI::ExistingFile);
    return cmd;
}

int run_calibrate(const vpp::CalibrateArgs& a) {
    const vpp::CalibrateCommand c = vpp::calibrate_command(a);
    const int rc = vpp::run_calibration(c.study, c.options);
    vpp::mpi_finalize();
    return rc;
}

// vppdem config-reference: docs/config.md, from the settings table.
CLI::App* add_config_reference(CLI::App& app) {
    return app.add_subcommand("config-reference",
                              "Print the reference of every config key (Markdown; docs/config.md is its output)");
}

int run_config_reference() {
    std::printf("%s", vpp::config_reference_markdown().c_str());
    return 0;
}

// An unknown command word: names it and the nearest command, and returns 2 (CLI11 alone only
// says "A subcommand is required", which hides the typo); 0 for a known one or none.
int refuse_unknown_command(CLI::App& app, int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') return 0;
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) names.push_back(sub->get_name());
    const std::string word = argv[1];
    if (std::find(names.begin(), names.end(), word) != names.end()) return 0;
    const std::string near = scene::nearest(word, names);
    std::string all;
    for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
    std::fprintf(stderr, "vppdem: error: unknown command '%s'%s (commands: %s; vppdem --help)\n", word.c_str(),
                 near.empty() ? "" : ("; did you mean '" + near + "'?").c_str(), all.c_str());
    return 2;
}

// A command: its CLI11 subcommand, its run and, for a study, its arguments (MPI when launched so:
// their rank and ranks).
struct Command {
    CLI::App* app;
    std::function<int()> run;
    vpp::StudyArgs* study = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vppdem: discrete element simulation of vacuum-packed particle dampers"};
    app.require_subcommand(1);
    // The build a run's build.json records (scene/build_info.h).
    app.set_version_flag("--version", std::string("vppdem ") + scene::build_commit() + " (build " + scene::build_id() + ")");

    // Every command's arguments, filled by the parse; the commands in the order --help lists them.
    SceneArgs scene;
    BenchArgs bench;
    FoilCheckArgs tension, envelope;
    DamperCommandArgs damper;
    vpp::DeviceArgs device;
    vpp::AnalyzeOptions analyze;
    std::string plot_dir;
    SweepCommandArgs sweep;
    vpp::CalibrateArgs calibrate;
    const std::vector<Command> commands = {
        {add_scene(app, scene), [&] { return run_scene(scene); }},
        {add_bench(app, bench), [&] { return run_bench(bench); }},
        {add_config_command(app, "tension", "Uniaxial tension of a foil strip (the paper's 37 x 12 test)", tension),
         [&] { return run_tension(tension); }},
        {add_config_command(app, "envelope", "Empty foil cylinder under a ramped underpressure (the paper's sanity check)",
                            envelope),
         [&] { return run_envelope(envelope); }},
        {add_damper(app, damper), [&] { return run_damper(damper); }},
        {add_device(app, device), [&] { return run_device(device); }},
        {add_analyze(app, analyze), [&] { vpp::run_analyze(analyze); return 0; }},
        {add_plot(app, plot_dir), [&] { return vpp::plot_dir(plot_dir, false) == 0 ? 0 : 2; }},
        {add_sweep(app, sweep), [&] { return run_sweep(sweep); }, &sweep},
        {add_calibrate(app, calibrate), [&] { return run_calibrate(calibrate); }, &calibrate},
        {add_config_reference(app), [] { return run_config_reference(); }},
    };

    if (const int rc = refuse_unknown_command(app, argc, argv)) return rc;
    // Every refusal exits 2, whatever CLI11's own code for its kind of error (105 a failed
    // check, 106 a missing required option, 109 an excluded one, ...): the scripts that drive
    // vppdem tell a refused command from a failed run by that one code. --help and --version
    // stay 0.
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }
    for (const Command& c : commands) {
        if (!*c.app) continue;
        if (c.study) vpp::mpi_init_if_launched(&argc, &argv, &c.study->rank, &c.study->ranks);
        try {
            return c.run();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "vppdem: error: %s\n", e.what());
            vpp::mpi_abort_if_active(2);
            vpp::mpi_finalize();
            return 2;
        }
    }
    return 0;
}
