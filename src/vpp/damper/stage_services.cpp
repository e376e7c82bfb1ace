// What a stage asks of the run around it (damper/stage_services.h): checkpoints, frames,
// warnings, the log.
#include "vpp/damper/stage_services.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include "dem/batch/batch_stepper.h"
#include "vpp/damper/stored_settings.h"

namespace vpp::damper_detail {

void StageServices::checkpoint(DamperScene& scene, const RunState& state, bool force) {
    if (!recorder_.checkpoint_due(force, options_.checkpoint_every)) return;
    if (options_.batch) options_.batch->sync(scene.world);
    if (state.settings.empty()) {
        // Before its settings are applied to the sample (while preparing), a run's run.ckpt
        // carries them all the same: resuming it continues this run. Without them, a run
        // started with --set process.velocity=0.1, killed while filling and resumed with
        // `--from DIR/run.ckpt` alone ran at the default velocity (found by
        // tools/kill_resume.py). prepared.ckpt keeps none (a sample takes the settings it is
        // given).
        RunState s = state;
        s.settings = run_settings_of(scene.config);
        recorder_.save_run(scene.world, s.save());
    } else {
        recorder_.save_run(scene.world, state.save());
    }
    if (state.stage == Stage::Cycling || state.stage == Stage::Done)
        recorder_.write_records(forces_table(state, int(scene.config.process.samples_per_cycle)), energy_table(state));
}

void StageServices::save_prepared(const DamperScene& scene, const RunState& state) {
    if (!recorder_.writes()) return;
    // A sample carries no run settings, also when this run resumed a run.ckpt that did.
    recorder_.save_prepared(scene.world, state.save_as_sample());
}

void StageServices::vtk_frame(DamperScene& scene, const char* tag) {
    if (!recorder_.writes()) return;
    if (options_.batch) options_.batch->sync(scene.world);
    recorder_.vtk_frame(scene.world, tag);
}

void StageServices::cycle_frame(DamperScene& scene) {
    const double interval = scene.config.output.vtk_interval;  // [s]
    if (interval > 0 && recorder_.cycle_frame_due(scene.world.time)) {
        vtk_frame(scene, "cycle");
        recorder_.cycle_frame_written(scene.world.time, interval);
    }
}

void StageServices::warn(RunState& state, const std::string& what) const {
    std::string w = what;
    for (char& ch : w)
        if (ch == '\n' || ch == '\r') ch = ' ';
    state.warnings.push_back(w);
    // On stderr with --quiet too: a value that does not do what it seems must not go unseen
    // (summary.json keeps it as well).
    // A study's cases run quietly side by side: each names its folder.
    if (options_.quiet && !options_.out_dir.empty()) std::fprintf(stderr, "damper %s: warning: %s\n", options_.out_dir.c_str(), w.c_str());
    else std::fprintf(stderr, "damper: warning: %s\n", w.c_str());
}

void StageServices::warn_once(RunState& state, const std::vector<std::string>& what) const {
    for (const std::string& w : what)
        if (std::find(state.warnings.begin(), state.warnings.end(), w) == state.warnings.end()) warn(state, w);
}

void StageServices::log(const char* fmt, ...) const {
    if (options_.quiet) return;
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stderr, fmt, ap);
    va_end(ap);
}

}  // namespace vpp::damper_detail
