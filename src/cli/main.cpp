// The vppdem command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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
#include "vpp/damper/damper.h"
#include "vpp/device/definition.h"
#include "vpp/device/run.h"
#include "vpp/study/device_study.h"
#include "vpp/foil_checks/envelope.h"
#include "vpp/analysis/plot.h"
#include "vpp/settings/settings.h"
#include "vpp/study/key_reference.h"
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
           "--displacement-unit", [&f](const std::string& u) { f.disp_scale = u == "mm" ? 1e-3 : 1.0; }, "m (default) or mm")
        ->check(CLI::IsMember({"m", "mm"}));
    cmd->add_option_function<std::string>(
           "--force-unit", [&f](const std::string& u) { f.force_scale = u == "kN" ? 1e3 : 1.0; }, "N (default) or kN")
        ->check(CLI::IsMember({"N", "kN"}));
    cmd->add_flag("--compression-negative", f.compression_negative,
                  "The record counts compression negative (displacement and force): flip both");
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vppdem: discrete element simulation of vacuum-packed particle dampers"};
    app.require_subcommand(1);
    // The build a run's build.json records (scene/build_info.h).
    app.set_version_flag("--version", std::string("vppdem ") + scene::build_commit() + " (build " + scene::build_id() + ")");

    // vppdem scene FILE.toml --out DIR [--set key=value ...] [--overwrite]
    auto* scene = app.add_subcommand("scene", "Run a generic DEM scene described in TOML (docs/scene.md)");
    std::string scene_file, out_dir;
    std::vector<std::string> sets;
    bool overwrite = false, quiet = false;
    scene->add_option("file", scene_file, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
    scene->add_option("--out", out_dir, "Output directory")->required()->check(kOutputPath);
    // allow_extra_args(false): one value per --set, so positionals may follow it.
    scene->add_option("--set", sets, "Override a config key: section.key=value (repeatable)")
        ->allow_extra_args(false);
    scene->add_flag("--overwrite", overwrite, "Replace files in a non-empty output directory");
    scene->add_flag("--quiet", quiet, "No progress output");

    // vppdem bench SCENE ...
    auto* bench = app.add_subcommand("bench", "Time a shared benchmark scene (docs/benchmarks.md)");
    scene::BenchOptions bo;
    bench->add_option("scene", bo.scene, "grains-in-cylinder | foil-plus-grains | checkpoint (the World saved in --state)")
        ->required()
        ->check(CLI::IsMember({"grains-in-cylinder", "foil-plus-grains", "checkpoint"}));
    bench->add_option("--grains", bo.grains, "grains_N.csv (grains-in-cylinder)")->check(CLI::ExistingFile);
    bench->add_option("--scene-dir", bo.scene_dir, "folder with foil_*.csv (foil-plus-grains)")
        ->check(CLI::ExistingDirectory);
    bench->add_option("--warmup", bo.warmup, "untimed steps first")->check(kNonNegative);
    bench->add_option("--steps", bo.steps, "timed steps")->check(kPositive);
    auto* bench_threads = bench->add_option("--threads", bo.threads, std::string("threads of the step (") + scene::kDefaultThreadsHelp + ")")
        ->check(kPositive);
    bench->add_option("--underpressure", bo.underpressure, "[Pa] follower pressure on the foil");
    bench->add_flag("--profile", bo.profile, "Print the time per phase (neighbour search, contacts, ...)");
    bench->add_option("--state", bo.state, "Checkpoint after the warm-up: loaded instead of warming up if it exists, else written");
    bench->add_flag("--energy", bo.energy, "Keep the energy ledger during the timed steps");
    bench->add_option("--batch", bo.batch, "checkpoint: step this many copies of the World as one batch (the batch "
                                           "engine's host backend, docs/gpu.md)")
        ->check(kPositive);
    bench->add_option("--backend", bo.backend, "--batch on: host (the host backend), cuda (the device backend on the GPU; "
                                               "a build with VPPDEM_CUDA), emulated (the device backend's kernels on the host)")
        ->check(CLI::IsMember({"host", "cuda", "emulated"}));
    bench->add_option("--simd", bo.simd, "Run the kernels on this SIMD target only (default: the best here)");

    // vppdem tension|envelope [CONFIG] --out DIR [--set ...]: the foil checks of the paper.
    struct VppCommand {
        CLI::App* app = nullptr;
        std::string config, out;
        std::vector<std::string> sets;
        bool overwrite = false, quiet = false;
    };
    auto add_vpp = [&](const char* name, const char* help, VppCommand& c) {
        c.app = app.add_subcommand(name, help);
        c.app->add_option("config", c.config, "Config file (TOML); defaults are the paper's values")
            ->check(CLI::ExistingFile);
        c.app->add_option("--out", c.out, "Output directory")->required()->check(kOutputPath);
        c.app->add_option("--set", c.sets, "Override a config key: section.key=value (repeatable)")
            ->allow_extra_args(false);
        c.app->add_flag("--overwrite", c.overwrite, "Replace files in a non-empty output directory");
        c.app->add_flag("--quiet", c.quiet, "No progress output");
    };
    VppCommand tension, envelope;
    add_vpp("tension", "Uniaxial tension of a foil strip (the paper's 37 x 12 test)", tension);
    add_vpp("envelope", "Empty foil cylinder under a ramped underpressure (the paper's sanity check)", envelope);

    // vppdem damper [CONFIG] --out DIR [--from CKPT] [--no-plot]
    VppCommand damper;
    add_vpp("damper", "Simulate a VPP damper: prepare, evacuate, cycle, record, analyse", damper);
    std::string from;
    bool no_plot = false;
    double ckpt_every = 60.0, progress_every = 0;
    damper.app->add_option("--progress-every", progress_every,
                           "[s] wall-clock time between progress lines (default 2 on a terminal, 30 into a file)")
        ->check(kPositive);
    damper.app->add_option("--from", from, "Start from a checkpoint (prepared.ckpt, or run.ckpt to resume)")
        ->check(CLI::ExistingFile);
    damper.app->add_flag("--no-plot", no_plot, "Do not draw the PNG loops at the end");
    bool damper_profile = false;
    damper.app->add_flag("--profile", damper_profile, "Print the time per phase of the cycling");
    damper.app->add_option("--checkpoint-every", ckpt_every, "[s] wall-clock time between checkpoints")
        ->check(kPositive);

    // vppdem device FILE --out DIR [--from CKPT]: a vacuum-packed device from a device file (docs/devices.md).
    auto* device = app.add_subcommand("device", "Run a vacuum-packed device from meshes: fill, seal, press, vacuum, load (docs/devices.md)");
    std::string device_file, device_out, device_from;
    std::vector<std::string> device_sets;
    bool device_overwrite = false, device_quiet = false;
    device->add_option("file", device_file, "Device file (TOML)")->required()->check(CLI::ExistingFile);
    device->add_option("--out", device_out, "Output directory (running into it again resumes from its run.ckpt)")->required()->check(kOutputPath);
    device->add_option("--from", device_from, "Resume from this checkpoint (a run.ckpt)")->check(CLI::ExistingFile);
    device->add_option("--set", device_sets, "Override a device key: section.key=value (repeatable)")->allow_extra_args(false);
    device->add_flag("--overwrite", device_overwrite, "Start afresh in a non-empty output directory, replacing its files (its run.ckpt too)");
    device->add_flag("--quiet", device_quiet, "No progress output");
    double device_ckpt_every = 60.0;
    device->add_option("--checkpoint-every", device_ckpt_every, "[s] wall-clock time between checkpoints within a stage")
        ->check(kPositive);

    // vppdem analyze FORCES.csv: cycles.csv from any force-displacement record.
    auto* analyze = app.add_subcommand("analyze", "Energy per cycle and W of a forces CSV, written to a new file");
    vpp::AnalyzeOptions ao;
    analyze->add_option("forces", ao.forces, "CSV with a header")->required()->check(CLI::ExistingFile);
    analyze->add_option("--out", ao.out, std::string("Output file (default: ") + vpp::kAnalyzeOutput +
                                             " beside the input; an existing file needs --overwrite)")
        ->check(kOutputPath);
    analyze->add_option("--radius", ao.radius,
                        "[m] damper radius for W = energy / (pi r^2) (default: damper.radius of the summary.json "
                        "beside the input, else 0.0255, the paper's)")
        ->check(kPositive);
    analyze->add_flag("--overwrite", ao.overwrite, "Replace an existing output file");
    add_record_format(analyze, ao.format);
    analyze->add_option("--cycle-column", ao.format.cycle_col,
                        "cycle column (default cycle); empty or absent: cycles found from the displacement");

    // vppdem plot DIR
    auto* plot = app.add_subcommand("plot", "Draw the plots of a damper, sweep or calibration output folder (PNG)");
    std::string plot_dir;
    plot->add_option("dir", plot_dir, "damper, sweep or calibration output folder")->required()->check(CLI::ExistingDirectory);

    // vppdem sweep STUDY.toml --out DIR [--jobs N]; vppdem calibrate STUDY.toml --experiment EXP.csv --out DIR
    struct StudyCommand {
        CLI::App* app = nullptr;
        std::string study, out;
        std::vector<std::string> sets;
        int jobs = 0, seeds = 0;
        CLI::Option* seeds_opt = nullptr;
        bool quiet = false, no_plot = false, mix_builds = false;
        std::string publish;
        double ckpt_every = 60.0, progress_every = 0;
        std::string backend = "cpu";
    };
    auto add_study = [&](const char* name, const char* help, StudyCommand& c) {
        c.app = app.add_subcommand(name, help);
        c.app->add_option("study", c.study, "Study file (TOML; docs/studies.md)")->required()->check(CLI::ExistingFile);
        c.app->add_option("--out", c.out, "Output directory (re-running into it resumes the study)")->required()->check(kOutputPath);
        c.app->add_option("--jobs", c.jobs, "Cases run at once on this machine (default: the free cores / threads per case; "
                                            "free cores: the cores this process may use minus those busy with other work)")
            ->check(kNonNegative);
        c.app->add_option("--set", c.sets, "Fixed override for every case: section.key=value (repeatable)")
            ->allow_extra_args(false);
        c.app->add_option("--checkpoint-every", c.ckpt_every, "[s] wall-clock time between checkpoints of a case")
            ->check(kPositive);
        c.app->add_option("--progress-every", c.progress_every,
                          "[s] wall-clock time between the study's progress lines (cases done, the running cases' "
                          "stages, time left; default 2 on a terminal, 30 into a file)")
            ->check(kPositive);
        c.seeds_opt = c.app->add_option("--seeds", c.seeds, "Ensemble: run every case with simulation.seed = 1..N (replaces the "
                                              "study's seeds; docs/studies.md)")
            ->check(CLI::Range(1, vpp::kMaxSeeds, "1.." + std::to_string(vpp::kMaxSeeds)));
        c.app->add_flag("--quiet", c.quiet, "No progress output");
        c.app->add_flag("--no-plot", c.no_plot, "Do not draw the PNG plots at the end");
        c.app->add_option("--backend", c.backend,
                          "How the cases' cycling is stepped: cpu (each case its own World, default), batch (the "
                          "running cases in lockstep through the batch engine's host backend, the same bits), cuda "
                          "(the batch engine on a GPU; docs/gpu.md)")
            ->check(CLI::IsMember({"cpu", "batch", "cuda"}));
        c.app->add_option("--publish", c.publish,
                          "Keep the finished cases' small records (case.toml, summary.json, cycles.csv, build.json) and "
                          "the tables in this folder, each file through a temporary name; records there that --out "
                          "lacks are put back first and count as finished (docs/studies.md, \"Publishing\")");
        c.app->add_flag("--mix-builds", c.mix_builds,
                        "Continue in a folder whose cases another build ran (refused without it: their build.json "
                        "names the builds; docs/studies.md, \"Resuming\")");
    };
    StudyCommand sweep, calib;
    add_study("sweep", "Run a parameter study: every combination of a grid of config values (docs/studies.md)", sweep);
    bool list_only = false;
    auto* list_flag =
        sweep.app->add_flag("--list", list_only, "Check the study and list its cases and preparations; run nothing");
    bool report_only = false;
    sweep.app
        ->add_flag("--report-only", report_only,
                   "Run nothing: write summary.csv, summary_cases.csv (and summary_paired.csv) from the cases finished "
                   "in --out, the others marked 'not run' (docs/studies.md, \"Resuming\")")
        ->excludes(list_flag);
    add_study("calibrate", "Grid search of a study against a measured force-displacement loop (docs/studies.md)", calib);
    vpp::CalibrateOptions co;
    calib.app->add_option("--experiment", co.experiment, "Measured loop: CSV with a header")->required()->check(CLI::ExistingFile);
    add_record_format(calib.app, co.format);
    calib.app->add_option("--simulated-force", co.force_column,
                          "simulated column compared: force_zeroed, force_total, or force_machine_zeroed (the pump "
                          "model's testing-machine force, docs/damper.md \"The air inside\")")
        ->check(CLI::IsMember({"force_zeroed", "force_total", "force_machine_zeroed"}));
    calib.app->add_option("--points", co.points, "displacements per branch in the misfit")->check(CLI::Range(4, 100000));
    calib.app->add_option("--predict", co.predict, "run the best point at other values: key=v1,v2,...");
    calib.app->add_option("--predict-experiment", co.predict_experiments,
                          "measured loop for each --predict value, in order (repeatable)")
        ->allow_extra_args(false)
        ->check(CLI::ExistingFile);

    // vppdem config-reference: docs/config.md, from the settings table.
    auto* config_reference = app.add_subcommand(
        "config-reference", "Print the reference of every config key (Markdown; docs/config.md is its output)");

    // An unknown command word: name it and the nearest command (CLI11 alone only says "A
    // subcommand is required", which hides the typo).
    if (argc >= 2 && argv[1][0] != '-') {
        std::vector<std::string> names;
        for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) names.push_back(sub->get_name());
        const std::string word = argv[1];
        if (std::find(names.begin(), names.end(), word) == names.end()) {
            const std::string near = scene::nearest(word, names);
            std::string all;
            for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
            std::fprintf(stderr, "vppdem: error: unknown command '%s'%s (commands: %s; vppdem --help)\n", word.c_str(),
                         near.empty() ? "" : ("; did you mean '" + near + "'?").c_str(), all.c_str());
            return 2;
        }
    }
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
    int rank = 0, ranks = 1;
    if (*sweep.app || *calib.app) vpp::mpi_init_if_launched(&argc, &argv, &rank, &ranks);
    try {
        if (*config_reference) {
            std::printf("%s", vpp::config_reference_markdown().c_str());
        } else if (*scene) {
            const auto root = cfg::load(scene_file, sets);
            const std::string base = std::filesystem::path(scene_file).parent_path().string();
            scene::Scene sc = scene::build_scene(root, base.empty() ? "." : base);
            scene::run_scene(sc, {out_dir, overwrite, quiet});
        } else if (*bench) {
            if (bench_threads->count() == 0) bo.threads = scene::default_threads();
            scene::run_bench(bo);
        } else if (*tension.app) {
            const vpp::Config c = vpp::load_config(tension.config, tension.sets, vpp::CommandSet::Foil);
            // Held until the command ends: one run at a time writes into a folder.
            const dem::FolderLock lock = scene::prepare_output_dir(tension.out, tension.overwrite);
            vpp::run_tension(c, tension.out, tension.quiet);
        } else if (*envelope.app) {
            const vpp::Config c = vpp::load_config(envelope.config, envelope.sets, vpp::CommandSet::Foil);
            const dem::FolderLock lock = scene::prepare_output_dir(envelope.out, envelope.overwrite);
            vpp::run_envelope(c, envelope.out, envelope.quiet);
        } else if (*damper.app) {
            const vpp::Config c = vpp::load_config(damper.config, damper.sets);
            vpp::DamperOptions o;
            o.out_dir = damper.out;
            o.from = from;
            o.quiet = damper.quiet;
            o.plot = !no_plot;
            o.overwrite = damper.overwrite;
            o.checkpoint_every = ckpt_every;
            o.progress_every = progress_every;
            o.profile = damper_profile;
            // Fewer cycles recorded than asked is a failed run (exit 1), not a refusal (2): the
            // records are written, summary.json says so under "warnings".
            if (vpp::run_damper(c, o).incomplete) return 1;
        } else if (*device) {
            const vpp::DeviceDef d = vpp::load_device(device_file, device_sets);
            vpp::DeviceOptions o;
            o.out_dir = device_out;
            o.from = device_from;
            o.quiet = device_quiet;
            o.overwrite = device_overwrite;
            o.checkpoint_every = device_ckpt_every;
            vpp::run_device(d, o);
        } else if (*analyze) {
            vpp::run_analyze(ao);
        } else if (*sweep.app || *calib.app) {
            StudyCommand& sc = *sweep.app ? sweep : calib;
            if (vpp::is_device_study(sc.study)) {
                // A device study (docs/devices.md, "Studies"): its runs one after the other on
                // this process, each a `vppdem device` run with the threads its device file sets.
                if (*calib.app) throw cfg::ConfigError("study '" + sc.study + "' is a device study (key 'device'): "
                                                       "calibrate takes a damper study");
                if (ranks > 1 || sc.backend != "cpu" || sc.jobs > 1)
                    throw cfg::ConfigError("study '" + sc.study + "' is a device study: it runs one case at a time on "
                                           "the CPU (no --jobs above 1, --backend other than cpu, or MPI)");
                const vpp::DeviceStudy ds = vpp::load_device_study(sc.study, sc.sets, sc.seeds);
                if (list_only) {
                    std::printf("%s", vpp::list_device_runs(ds).c_str());
                    vpp::mpi_finalize();
                    return 0;
                }
                vpp::DeviceSweepOptions dso;
                dso.out_dir = sc.out;
                dso.publish = sc.publish;
                dso.quiet = sc.quiet;
                dso.report_only = report_only;
                dso.mix_builds = sc.mix_builds;
                dso.checkpoint_every = sc.ckpt_every;
                if (sc.progress_every > 0 && !sc.quiet)
                    std::fprintf(stderr, "warning: --progress-every is not used by a device study: its runs print "
                                         "their own progress lines\n");
                const vpp::DeviceSweepResult r = vpp::run_device_study(ds, dso);
                vpp::mpi_finalize();
                return r.failed && !report_only ? 1 : 0;
            }
            const vpp::Study st = vpp::load_study(sc.study, sc.sets, sc.seeds);
            vpp::SweepOptions so;
            so.out_dir = sc.out;
            so.jobs = sc.jobs;
            so.quiet = sc.quiet;  // every rank reports its cases; rank 0 the totals
            so.checkpoint_every = sc.ckpt_every;
            so.progress_every = sc.progress_every;
            so.rank = rank;
            so.ranks = ranks;
            so.backend = sc.backend;
            so.mix_builds = sc.mix_builds;
            so.publish = sc.publish;
            int rc = 0;
            if (*sweep.app && list_only) {
                const auto cases = vpp::expand_study(st);
                // With samples_from, the sample each group would branch from (its folder's path).
                std::map<int, std::string> samples;
                for (const auto& [group, path] : vpp::find_shared_samples(st, so, cases)) samples[group] = path.string();
                if (rank == 0) std::printf("%s", vpp::list_cases(cases, samples).c_str());
            } else if (*sweep.app) {
                so.report_only = report_only;
                const vpp::SweepResult r = vpp::run_sweep(st, so);  // holds --out's lock for the plots too
                if (rank == 0 && !sc.no_plot && !report_only) vpp::plot_sweep_dir(sc.out, sc.quiet);
                // A report is a success whatever the cases' state: unfinished and unreadable
                // cases are in its tables.
                rc = r.failed && !report_only ? 1 : 0;
            } else {
                co.sweep = so;
                co.plot = !sc.no_plot && rank == 0;
                rc = vpp::run_calibration(st, co);
            }
            vpp::mpi_finalize();
            return rc;
        } else if (*plot) {
            return vpp::plot_dir(plot_dir, false) == 0 ? 0 : 2;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vppdem: error: %s\n", e.what());
        vpp::mpi_abort_if_active(2);
        vpp::mpi_finalize();
        return 2;
    }
    return 0;
}
