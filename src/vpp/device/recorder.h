// The device run's recorder: the output folder and every file a device run writes into it (the
// checkpoint run.ckpt, tools.csv, air.csv, energy.csv, summary.json, the VTK frames; each under a
// temporary name, then renamed), the folder's lock and the checkpoints' wall clock. So that what
// a run writes, where and when, is read in one place (docs/devices.md, "Records").
// Internal to vpp/device/*.cpp.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "dem/io/folder_lock.h"
#include "dem/world/world.h"
#include "vpp/device/scene.h"
#include "vpp/device/state.h"

namespace vpp::device_detail {

class DeviceRecorder {
public:
    explicit DeviceRecorder(const std::string& out_dir) : out_(out_dir) {}

    // The folder's run.ckpt: what the same command into the same folder resumes.
    std::filesystem::path run_checkpoint() const { return out_ / "run.ckpt"; }

    // Takes the folder's lock (held until the run ends). A run that resumes the folder's own
    // run.ckpt (`resumed_from`) lists this build in build.json; any other run starts afresh: in
    // an empty folder, in one that holds only what a run killed before its first checkpoint
    // leaves (holds_only_a_killed_run; its stale files removed, `log` told) or, with
    // `overwrite`, in any; otherwise it refuses (cfg::ConfigError naming --out and a file there).
    void open(const std::string& resumed_from, bool overwrite, const std::function<void(const std::string&)>& log);

    // The checkpoint clock: true, and restarted, when `every` seconds [s] of wall clock have
    // passed since the last checkpoint (or the run's start).
    bool checkpoint_due(double every);
    // run.ckpt: the World and the state's blob; the membrane's pressure fans follow from the
    // membrane, which the device file rebuilds: saved without them, restored on load.
    void save_checkpoint(dem::World& world, const DeviceState& state) const;
    // VTK frame vtk/NAME.vtk (particles and bonds; a pour's retired grains left out) and
    // vtk/NAME_tools.vtk (the tools' facets).
    void vtk_frame(const DeviceScene& scene, const std::string& name) const;
    // tools.csv, air.csv, energy.csv (output.energy) and summary.json as the state stands.
    void write_records(const DeviceScene& scene, const DeviceState& state) const;

private:
    std::filesystem::path out_;
    dem::FolderLock lock_;  // out_'s, while the run lives (one writer per folder)
    std::chrono::steady_clock::time_point last_ckpt_ = std::chrono::steady_clock::now();
};

// Whether folder `dir` holds nothing but what a device run killed before its first checkpoint
// leaves (docs/devices.md, "Stages"): its lock file, build.json, VTK frames (vtk/frame_*,
// vtk/stage_*, whole or partly written) and a partial checkpoint (run.ckpt.part); an empty
// folder does too. `stale` gets the frames and the partial checkpoint, which a new run there
// clears; `other` the first entry that is none of these.
bool holds_only_a_killed_run(const std::filesystem::path& dir, std::vector<std::filesystem::path>& stale,
                             std::filesystem::path& other);

}  // namespace vpp::device_detail
