// Which build made a run (issue 46): the commit the sources came from and a build id that
// changes with any source file or with how it was compiled (cmake/build_info.cmake writes both
// at every build). Every command that writes an output folder records them there, in
// build.json, so that results of two builds are never mixed unknowingly: a resumed run made by
// another build lists it (`resumed_by`), and a study refuses to continue in a folder that holds
// another build's runs unless told (vppdem sweep --mix-builds).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace scene {

const char* build_commit();  // `git describe --always --dirty` of the sources, "unknown" outside git
const char* build_id();      // 16 hex digits: the same for the same sources built the same way

struct BuildStamp {
    std::string commit, id;
};

// What DIR/build.json says: the build that started the run, then every other build that
// resumed it, in order. nullopt when the folder has no build.json (a run of a vppdem before
// builds were recorded) or it cannot be read.
std::optional<std::vector<BuildStamp>> read_build_record(const std::string& dir);

// Records this build in DIR/build.json (written to a temporary name, then renamed). fresh: a new
// run (the file is this build alone); otherwise a resumed one: this build is appended to
// `resumed_by` when it is not the last build there. Throws std::runtime_error when it cannot write.
void record_build(const std::string& dir, bool fresh);

// The builds other than this one in DIR/build.json (empty when none, or no record).
std::vector<BuildStamp> other_builds(const std::string& dir);

}  // namespace scene
