// What a stage of the damper run asks of the run around it (damper/stages.h): the options (the
// progress hook, the batch stepper, quiet), the checkpoints and VTK frames through the run's
// recorder, the warnings kept in the run state, the log on the terminal. The stages see the run
// through this alone; the run (damper/run.h) owns the options and the recorder it refers to.
// Internal to vpp/damper_*.cpp.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scene/progress.h"
#include "vpp/damper/damper.h"
#include "vpp/damper/recorder.h"
#include "vpp/damper/scene.h"
#include "vpp/damper/state.h"

namespace vpp::damper_detail {

// The terminal's progress line and the caller's hook (DamperOptions::progress).
// `at_most`: the total is the most the stage can take (it ends when the sample is at rest).
class StageProgress {
public:
    StageProgress(std::string stage, uint64_t total, const DamperOptions& o, bool at_most = false)
        : prog_(stage, total, o.quiet, at_most, o.progress_every), stage_(std::move(stage)), total_(total),
          hook_(o.progress) {}
    void update(uint64_t done, double sim_time) {
        prog_.update(done, sim_time);
        // Every 256 steps, as often as the progress line looks at the clock: the hook may take
        // a lock (the Python interpreter's) and must not slow the steps down.
        if (hook_ && !(done & 255u)) hook_(stage_.c_str(), done, total_, sim_time);
    }

private:
    scene::Progress prog_;
    std::string stage_;
    uint64_t total_;
    const std::function<void(const char*, uint64_t, uint64_t, double)>& hook_;
};

class StageServices {
public:
    // Refers to the run's options and recorder, which outlive it.
    StageServices(const DamperOptions& options, DamperRecorder& recorder) : options_(options), recorder_(recorder) {}

    const DamperOptions& options() const { return options_; }
    // run.ckpt when the recorder's clock says one is due (or `force`), and while cycling
    // forces.csv and energy.csv with it (the batch stepper's state synced first).
    void checkpoint(DamperScene& scene, const RunState& state, bool force);
    // prepared.ckpt: the sample as the preparation left it, without run settings.
    void save_prepared(const DamperScene& scene, const RunState& state);
    // The next VTK frame of the world as it stands (the batch stepper's state synced first).
    void vtk_frame(DamperScene& scene, const char* tag);
    // The cycling's frame when one is due (every output.vtk_interval [s] of simulated time).
    void cycle_frame(DamperScene& scene);
    // Logs a warning and keeps it in the state for summary.json (and the checkpoints, so
    // branches and resumed runs report it too).
    void warn(RunState& state, const std::string& what) const;
    // Warns what is not yet among the state's warnings (a resumed run has its first start's).
    void warn_once(RunState& state, const std::vector<std::string>& what) const;
    // printf to stderr unless quiet.
    void log(const char* fmt, ...) const;

private:
    const DamperOptions& options_;
    DamperRecorder& recorder_;
};

}  // namespace vpp::damper_detail
