// The study file of `vppdem sweep` (docs/studies.md): reading and checking it, and expanding its
// grid into cases, each with its config and preparation group.
//
// A study file (TOML) holds an optional base config, fixed overrides and a grid:
//     base = "damper.toml"                 # optional, relative to the study file
//     share_preparation = true             # optional (default true)
//     seeds = 3                            # optional: an ensemble, simulation.seed = 1..3
//     [set]                                # fixed overrides for every case
//     "damper.radius" = 0.012
//     [grid]                               # every combination is one case
//     "grains.friction" = [0.0, 0.3, 0.6]  # a list, or "start:stop:step" (stop included)
//     "process.underpressure" = [0.02e6, 0.08e6]
// Its keys are described once, in study_keys() (docs/config.md, "Study files").
// Cases whose grid values differ only in keys that do not act before the end of the preparation
// (vpp/settings/settings.h, shares_preparation: grain and cap friction, process.*, output.*, analysis.*,
// threads) share one preparation: the first case of each group prepares, the others branch from
// its prepared.ckpt.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "vpp/settings/config.h"

namespace vpp {

// A top-level key of a study file, as the reader checks it and docs/config.md shows it.
struct StudyKey {
    const char* key;   // "seeds"; a table as "[set]"
    const char* type;  // as the reference shows it
    const char* def;   // the default, as text
    const char* doc;
};
const std::vector<StudyKey>& study_keys();

// docs/config.md's "Study files" section (`vppdem config-reference`).
std::string study_reference_markdown();

// One [grid] key and its values, in the order written.
struct GridAxis {
    std::string key;                    // dotted config key, e.g. "grains.friction"
    std::vector<std::string> literals;  // TOML literals handed to --set ("0.3", "2", "\"extension\"")
    std::vector<std::string> labels;    // the values as shown in names and summary.csv ("0.3", "2", "extension")
};

struct Study {
    std::string path;                // the study file
    std::string base;                // base config path (resolved), empty: the damper's defaults
    std::vector<std::string> set;    // "key=literal" fixed overrides ([set], then --set)
    std::vector<GridAxis> grid;      // in file order
    bool share_preparation = true;
    // The prepared samples of other studies (`samples_from`, a name or a list of names): their
    // folders, each a path relative to the folder that holds this study's --out (a sibling study by
    // its name: "radius_underpressure") or absolute, searched in the order given (a group takes the
    // first fitting sample of the first folder that has one: the time-step study's seeds 1-3 from
    // the friction study, 4-5 from the radius study); empty: every preparation group prepares its
    // own. samples_match "preparation"
    // (false here): a sample fits a group when its geometry and the keys that act during the
    // preparation are the group's; "geometry" (true): the geometry alone, the case cycling the
    // sample with its own settings (the time-step study).
    std::vector<std::string> samples_from;
    bool samples_match_geometry = false;
    // A second leg (`continues`): the folder of a study whose finished runs this study's cases of
    // the same names continue, copied, to this study's larger process.cycles (relative to the
    // folder that holds --out, or absolute; copy_continued_runs); empty: none.
    std::string continues;
};

// Keys whose values may differ between cases sharing one preparation (the damper's --from
// accepts them): the settings table's shares_preparation (vpp/settings/settings.h).
bool is_shareable_key(const std::string& key);

// Reads and checks a study file (ConfigError naming the key on bad input); extra_sets are
// appended to [set]. An empty [grid] (or none) gives one case.
// Ensembles: `seeds = N` (top level; or seeds_override > 0, the command line's --seeds, which
// also replaces a [grid] list of simulation.seed) adds simulation.seed = 1..N as the last grid
// key. A [grid] list "simulation.seed" = [...] is an ensemble too.
inline constexpr int kMaxSeeds = 1000;
Study load_study(const std::string& path, const std::vector<std::string>& extra_sets = {}, int seeds_override = 0);

// A device study (docs/devices.md, "Studies"): named cases of one device file, each run with
// every seed, run by `vppdem sweep` like a damper study (a study file with the key `device` is
// a device study):
//     description = "holding force against underpressure"
//     device = "../../examples/devices/gripper.toml"   # relative to the study file
//     seeds = 5                                        # simulation.seed = 1..5
//     [set]                                            # fixed overrides of every case
//     "output.vtk" = false
//     [cases.dp0]                                      # a case: its name and its overrides
//     "stages.underpressure" = 0
struct DeviceStudyCase {
    std::string name;              // the case's folder name before the seed ("dp0": dp0_s1, ...)
    std::vector<std::string> set;  // its overrides "key=literal", in file order
};
struct DeviceStudy {
    std::string path;                    // the study file
    std::string device;                  // the device file (resolved)
    std::vector<std::string> set;        // [set], then the command line's --set
    std::vector<DeviceStudyCase> cases;  // in file order
    int seeds = 0;                       // simulation.seed = 1..seeds; 0: one run per case, the device file's seed
};
// Whether the study file is a device study (it has a top-level key `device`). Reads the file;
// false for one that cannot be parsed (load_study then says why).
bool is_device_study(const std::string& path);
// Reads and checks a device study (ConfigError naming the key, the value and what is allowed):
// every case's overrides are checked against the device file as `vppdem device --set` would.
DeviceStudy load_device_study(const std::string& path, const std::vector<std::string>& extra_sets = {},
                              int seeds_override = 0);

// Index of the ensemble axis (grid key simulation.seed), -1 without one.
int seed_axis(const Study& s);

// Parses "start:stop:step" (stop included when it lies on the grid, to 1e-9 of a step);
// integers when all three are integers. Throws ConfigError naming `key`.
std::vector<double> parse_range(const std::string& key, const std::string& text, bool* integers = nullptr);

// A grid axis from command-line text: "v1,v2,..." (each a TOML value or a bare word) or a range
// "start:stop:step". Throws ConfigError naming the key.
GridAxis axis_from_text(const std::string& key, const std::string& values);

struct StudyCase {
    std::size_t index = 0;
    std::string name;                    // folder name: swept keys and values, filesystem-safe
    std::string name_without_seed;       // the name without the seed axis ("" when there is none)
    std::vector<std::string> labels;     // one per grid axis
    std::vector<std::string> overrides;  // all --set assignments of the case, in order
    Config config = Config::unread();    // loaded by expand_study
    int group = 0;                       // preparation group
    std::size_t preparer = 0;            // index of the case that prepares for this group
};

// Expands the grid (first key outermost) and loads every case's config (errors name the case).
std::vector<StudyCase> expand_study(const Study& s);

// One line per case: index, folder name, preparation group and whether it prepares or branches.
std::string list_cases(const std::vector<StudyCase>& cases,
                       const std::map<int, std::string>& samples = {});

}  // namespace vpp
