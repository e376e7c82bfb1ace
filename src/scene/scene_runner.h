// `vppdem scene`: a generic DEM scene from a TOML file (see docs/scene.md).
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

#include "dem/world/world.h"
#include "dem/io/folder_lock.h"
#include "scene/shared_keys.h"

namespace scene {

// A scene read from TOML: the World plus what the runner needs around it.
struct Scene {
    dem::World world;
    double duration = 1e-3;             // [s]
    double output_interval = 1e-6;      // [s]
    double vtk_interval = 0.0;          // [s], 0 = no VTK frames
    bool dt_auto = false;
    double dt_safety = cfg::keys::dt_safety.def;  // [-] dt = safety * critical step when dt = "auto"
    std::vector<uint32_t> tracked;      // particle indices written to tracked.csv
    // Output walls: planes, then [[facets]], then each [[facet_sets]] entry as one wall;
    // wall_members[k] lists the World wall indices summed into output wall k.
    std::vector<std::vector<uint32_t>> wall_members;
    std::vector<std::string> wall_names;
    // Where each sphere came from, for messages: {-1, k} = [[spheres]] entry k, {f, r} = data
    // row r (0-based) of [[sphere_files]] entry f, {-2, k} = a member of [[clumps]] entry k.
    std::vector<std::pair<int32_t, uint32_t>> sphere_origin;
    std::vector<std::string> sphere_file_paths;  // per [[sphere_files]] entry
    // [simulation] and [output] as the run used them, defaults included (dotted key, JSON value):
    // summary.json "inputs", in the settings table's order.
    std::vector<std::pair<std::string, std::string>> inputs;
};

// "spheres[3]" or "sphere_files[0] row 17 of 'grains.csv'" for sphere `id`.
std::string sphere_name(const Scene& sc, uint32_t id);

// Builds a scene; relative file paths are resolved against `base_dir`. Refuses (ConfigError)
// spheres that start overlapping each other or a wall by more than simulation.max_initial_overlap
// times the smaller radius (scene/initial_overlaps.h), naming both bodies.
Scene build_scene(const toml::table& root, const std::string& base_dir);

struct RunOptions {
    std::string out_dir;
    bool overwrite = false;
    bool quiet = false;
};

// Runs the scene and writes tracked.csv, walls.csv, summary.json and VTK frames.
void run_scene(Scene& scene, const RunOptions& opt);

// Creates the output directory if missing and takes its lock (dem/io/folder_lock.h) for the
// caller to hold while it writes there: dem::FolderLocked (naming the holder) when another run
// writes into it. On a file system without locks: a warning on stderr, and no lock.
dem::FolderLock lock_output_dir(const std::string& dir);

// lock_output_dir(), then refuses a non-empty directory unless overwrite (the lock file alone,
// perhaps left by a killed run, does not count). The lock comes first: a second run into a
// folder in use is refused as such, before anything in it is looked at or removed. Then records
// this build as the folder's (build.json, scene/build_info.h): a run resuming in its folder calls
// lock_output_dir() and record_build(dir, false) instead.
dem::FolderLock prepare_output_dir(const std::string& dir, bool overwrite);

// Refuses an output folder given as empty or blank (ConfigError naming `what`, the option or
// argument, and the value): "" resolves to the current folder, whose files a run would then
// replace without --overwrite (issue 62). Every command's folder passes through it
// (lock_output_dir); the command line's and Python's front doors call it too.
void require_output_path(const std::string& dir, const std::string& what);

// One resume rule for every command that writes a run folder (damper, device, a sweep's cases):
// the checkpoint a run starts from: `from` when given; else the folder's run.ckpt when it is
// there and the run is not told to start afresh (overwrite), so that the same command into the
// same folder continues its run; else "" (a new run).
std::string resume_checkpoint(const std::string& out_dir, const std::string& from, bool overwrite);

}  // namespace scene
