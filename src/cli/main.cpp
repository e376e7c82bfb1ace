// The vppdem command line.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/bench_scenes.h"
#include "cli/config.h"
#include "cli/scene_runner.h"
#include "vpp/config.h"
#include "vpp/envelope.h"
#include "vpp/tension.h"

int main(int argc, char** argv) {
    CLI::App app{"vppdem: discrete element simulation of vacuum-packed particle dampers"};
    app.require_subcommand(1);

    // vppdem scene FILE.toml --out DIR [--set key=value ...] [--overwrite]
    auto* scene = app.add_subcommand("scene", "Run a generic DEM scene described in TOML (docs/scene.md)");
    std::string scene_file, out_dir;
    std::vector<std::string> sets;
    bool overwrite = false, quiet = false;
    scene->add_option("file", scene_file, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
    scene->add_option("--out", out_dir, "Output directory")->required();
    // allow_extra_args(false): one value per --set, so positionals may follow it.
    scene->add_option("--set", sets, "Override a config key: section.key=value (repeatable)")
        ->allow_extra_args(false);
    scene->add_flag("--overwrite", overwrite, "Replace files in a non-empty output directory");
    scene->add_flag("--quiet", quiet, "No progress output");

    // vppdem bench SCENE ...
    auto* bench = app.add_subcommand("bench", "Time a shared benchmark scene (../shared/bench/README.md)");
    cli::BenchOptions bo;
    bench->add_option("scene", bo.scene, "grains-in-cylinder | foil-plus-grains")
        ->required()
        ->check(CLI::IsMember({"grains-in-cylinder", "foil-plus-grains"}));
    bench->add_option("--grains", bo.grains, "grains_N.csv (grains-in-cylinder)")->check(CLI::ExistingFile);
    bench->add_option("--scene-dir", bo.scene_dir, "folder with foil_*.csv (foil-plus-grains)")
        ->check(CLI::ExistingDirectory);
    bench->add_option("--warmup", bo.warmup, "untimed steps first")->check(CLI::NonNegativeNumber);
    bench->add_option("--steps", bo.steps, "timed steps")->check(CLI::PositiveNumber);
    bench->add_option("--threads", bo.threads, "OpenMP threads")->check(CLI::PositiveNumber);
    bench->add_option("--underpressure", bo.underpressure, "[Pa] follower pressure on the foil");

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
        c.app->add_option("--out", c.out, "Output directory")->required();
        c.app->add_option("--set", c.sets, "Override a config key: section.key=value (repeatable)")
            ->allow_extra_args(false);
        c.app->add_flag("--overwrite", c.overwrite, "Replace files in a non-empty output directory");
        c.app->add_flag("--quiet", c.quiet, "No progress output");
    };
    VppCommand tension, envelope;
    add_vpp("tension", "Uniaxial tension of a foil strip (the paper's 37 x 12 test)", tension);
    add_vpp("envelope", "Empty foil cylinder under a ramped underpressure (the paper's sanity check)", envelope);

    CLI11_PARSE(app, argc, argv);
    try {
        if (*scene) {
            const auto root = cfg::load(scene_file, sets);
            const std::string base = std::filesystem::path(scene_file).parent_path().string();
            cli::Scene sc = cli::build_scene(root, base.empty() ? "." : base);
            cli::run_scene(sc, {out_dir, overwrite, quiet});
        } else if (*bench) {
            cli::run_bench(bo);
        } else if (*tension.app) {
            const vpp::Config c = vpp::load_config(tension.config, tension.sets, 0.01e6);
            cli::prepare_output_dir(tension.out, tension.overwrite);
            vpp::run_tension(c, tension.out, tension.quiet);
        } else if (*envelope.app) {
            const vpp::Config c = vpp::load_config(envelope.config, envelope.sets, 0.01e6);
            cli::prepare_output_dir(envelope.out, envelope.overwrite);
            vpp::run_envelope(c, envelope.out, envelope.quiet);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vppdem: error: %s\n", e.what());
        return 2;
    }
    return 0;
}
