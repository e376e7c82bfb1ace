// The damper run's recorder: the output folder and every file a damper run writes into it (the
// checkpoints run.ckpt and prepared.ckpt, forces.csv, energy.csv, cycles.csv, summary.json, the
// VTK frames; the plots' names, which the plot module writes, in its list of the folder's files),
// the folder's lock and the clearing of a previous run's files (--overwrite). Apart from
// DamperRun (damper/run.h), which keeps the physics and the stages and hands the recorder what
// to write, so that what a run writes, where and when, is read in one place (docs/damper.md,
// "Outputs").
// Internal to vpp/damper_*.cpp.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "dem/io/folder_lock.h"
#include "dem/world/world.h"
#include "vpp/damper/damper.h"

namespace vpp::damper_detail {

class DamperRecorder {
public:
    // out_dir empty: a run that writes nothing (a Damper of the Python module without a folder).
    explicit DamperRecorder(const std::string& out_dir) : out_(out_dir), files_(!out_dir.empty()) {}

    // Whether the run writes files at all (an out_dir was given).
    bool writes() const { return files_; }
    // The folder's run.ckpt: what the same command into the same folder resumes.
    std::filesystem::path run_checkpoint() const { return out_ / "run.ckpt"; }

    // Takes the folder's lock (held until the run ends) and, for a run that does not resume the
    // folder's own run.ckpt, clears it as `overwrite` asks (or refuses a non-empty one); `from`,
    // the checkpoint the run starts from, is spared. Nothing without an out_dir.
    void open(bool resuming, bool overwrite, const std::string& from);

    // The checkpoint clock: true, and restarted, when the run writes files and a checkpoint is
    // forced or `every` seconds of wall time [s] have passed since the last one.
    bool checkpoint_due(bool force, double every);
    // The checkpoint's World and app blob `blob` as run.ckpt / prepared.ckpt in the folder.
    void save_run(const dem::World& world, const std::string& blob) const;
    void save_prepared(const dem::World& world, const std::string& blob) const;
    // Writes the World and `blob` as a checkpoint at `path`; the mesh foil's pressure fans are
    // not in the format: saved without them, rebuilt from the foil on loading (set_foil_pressure).
    static void save_world(const std::string& path, const dem::World& world, const std::string& blob);

    // The next VTK frame, vtk/damper_NNNN_<tag>.vtk (numbered from 0 in the order written).
    void vtk_frame(const dem::World& world, const char* tag);
    // The cycling's frames fall every output.vtk_interval [s] of simulated time: whether one is
    // due at `time` [s], and the time of the next after one written at `time`.
    bool cycle_frame_due(double time) const { return time >= next_vtk_; }
    void cycle_frame_written(double time, double interval) { next_vtk_ = time + interval; }

    // forces.csv and energy.csv into `dir` (the folder, or any a caller names): the tables as
    // they are, each column's name its header's; energy.csv only when it has rows.
    static void write_forces(const std::filesystem::path& dir, const ForcesTable& forces);
    static void write_energy(const std::filesystem::path& dir, const ForcesTable& energy);
    // Both into the folder (the checkpoints while cycling write them as well).
    void write_records(const ForcesTable& forces, const ForcesTable& energy) const;
    // cycles.csv (vpp/analysis/records.h's columns) and summary.json (its text, damper_summary_json) into
    // `dir`, each atomically: the records of a finished run (write_damper_outputs).
    static void write_cycles(const std::filesystem::path& dir, const std::vector<CycleResult>& cycles);
    static void write_summary(const std::filesystem::path& dir, const std::string& summary_json);

private:
    std::filesystem::path out_;
    bool files_ = false;    // out_dir given: checkpoints, frames and records are written
    dem::FolderLock lock_;  // out_dir's, while the run lives (one writer per folder)
    std::chrono::steady_clock::time_point last_ckpt_ = std::chrono::steady_clock::now();
    int vtk_count_ = 0;     // frames written (the next frame's number)
    double next_vtk_ = 0.0; // [s] simulated time of the next cycling frame
};

}  // namespace vpp::damper_detail
