// Shared helpers for the tests that drive the vppdem binary as a user does (damper, studies,
// energy through the damper): run a command, read its CSV outputs, scratch folders.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "dem/io/csv.h"

namespace cli_test {

namespace fs = std::filesystem;

inline const std::string kBinary = VPPDEM_BINARY;  // the vppdem under test (set by CMake)

// The small, quick damper used by these tests (56 grains, 494 foil particles): short and
// narrow, loose packing, fast loading, few samples.
inline const std::string kSmallDamper =
    "--set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 "
    "--set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=2 "
    "--set process.samples_per_cycle=80 --set simulation.threads=1 --no-plot --quiet";

struct Outcome {
    int status;          // pclose() status: 0 for success
    std::string output;  // stdout and stderr together
};

inline Outcome shell(const std::string& command) {
    const std::string cmd = command + " 2>&1";
    Outcome r{0, ""};
    FILE* f = popen(cmd.c_str(), "r");
    char buf[4096];
    while (f && fgets(buf, sizeof buf, f)) r.output += buf;
    r.status = f ? pclose(f) : -1;
    return r;
}

// `vppdem ARGS`.
inline Outcome run(const std::string& args) { return shell(kBinary + " " + args); }

// TMP/vppdem_<tag>_<pid>/<name>: one folder per test process.
inline fs::path scratch_path(const std::string& tag, const std::string& name) {
    return fs::temp_directory_path() / ("vppdem_" + tag + "_" + std::to_string(::getpid())) / name;
}

// Columns of a CSV with a header, by name; `header_line` gets the header as written.
inline std::map<std::string, std::vector<double>> read_columns(const fs::path& p, std::string* header_line = nullptr) {
    std::vector<std::string> header;
    const auto rows = dem::read_numeric_csv(p.string(), 1, &header);
    std::map<std::string, std::vector<double>> cols;
    for (const auto& row : rows)
        for (std::size_t k = 0; k < header.size(); ++k) cols[header[k]].push_back(row[k]);
    if (header_line) {
        std::ifstream in(p);
        std::getline(in, *header_line);
    }
    return cols;
}

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline void write_file(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

}  // namespace cli_test
