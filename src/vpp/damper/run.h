// The damper run: its scene, its state, its recorder and the stages between them. Internal to
// vpp/damper_*.cpp; the code's layout:
//   damper/scene.h/.cpp           the scene: the World and its parts (foil, rings, grains, caps,
//                                 funnel), built from the config; the grains' and foil's measures
//   damper/state.h/.cpp           the run state besides the World (RunState), the checkpoint's app
//                                 blob, and the forces.csv/energy.csv tables read from it
//   damper/stages.h/.cpp          the protocol: fill, compress, vacuum, cycle, functions of the
//                                 scene and the run state
//   damper/stage_services.h/.cpp  what a stage asks of the run: options, checkpoints, warnings, log
//   damper/checks.h/.cpp          the input's checks against the built scene
//   damper/stored_settings.h/.cpp what a checkpoint stores of the config; adopting and comparing it
//   damper/recorder.h/.cpp        the output folder and every file written into it (DamperRecorder)
//   damper/run.cpp                DamperRun (this file's class) and vpp::Damper
//   damper/record.cpp             the result, summary.json's text, run_damper()
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dem/world/world.h"
#include "vpp/damper/damper.h"
#include "vpp/damper/recorder.h"
#include "vpp/damper/scene.h"
#include "vpp/damper/stage_services.h"
#include "vpp/damper/stages.h"
#include "vpp/damper/state.h"
#include "vpp/damper/stored_settings.h"

namespace vpp::damper_detail {

struct RunStart;  // the options and config a run starts with, a checkpoint's settings adopted (damper/run.cpp)

class DamperRun {
public:
    // Builds the scene from the config, or from o.from (a checkpoint; in o.out_dir its run.ckpt
    // resumes the run), and readies the first stage to run.
    DamperRun(const Config& c, const DamperOptions& o);
    // The stages' services refer to the options and the recorder: not copied, not moved.
    DamperRun(const DamperRun&) = delete;
    DamperRun& operator=(const DamperRun&) = delete;
    // The stages: see vpp::Damper.
    void prepare();
    void vacuum();
    int cycle(int n);
    int cycles_done() const { return stages::cycles_done(scene_, state_); }
    // The record (damper/record.cpp: result()).
    void save(const std::string& path) const;
    DamperResult result() const;
    void write_records(const std::string& dir) const;
    const dem::World& world() const { return scene_.world; }
    const Config& config() const { return scene_.config; }
    const DamperOptions& options() const { return options_; }
    void set_progress(std::function<void(const char*, uint64_t, uint64_t, double)> hook) { options_.progress = std::move(hook); }
    const RunState& state() const { return state_; }
    ForcesTable forces() const { return forces_table(state_, int(scene_.config.process.samples_per_cycle)); }  // forces.csv's
    ForcesTable energy() const { return energy_table(state_); }  // energy.csv's (no rows before cycling)

private:
    explicit DamperRun(RunStart&& start);
    // The world as the first stage to run finds it: poured, or the checkpoint's loaded.
    void setup(const CheckpointStart& from);
    // The config's run settings applied to the prepared sample; the run is bound to them.
    void apply_run_settings();

    DamperOptions options_;
    DamperRecorder recorder_;  // the output folder (out_dir) and every file written into it
    DamperScene scene_;
    RunState state_;
    StageServices services_;   // the stages' view of options_ and recorder_
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();  // for run_seconds
    // The process's and the sampling's warnings (check_process, check_sampling): given from the
    // vacuum on, so that prepared.ckpt, which cases of other process settings share, holds none.
    std::vector<std::string> process_warnings_;
};

}  // namespace vpp::damper_detail
