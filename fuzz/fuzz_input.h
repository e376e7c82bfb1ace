// What the fuzz targets share (docs/robustness.md): the input handed to a reader that takes a
// path, and the rule that tells a reader's refusal from a finding.
//
// A reader may refuse an input with the errors the command line turns into a message
// (src/cli/main.cpp prints e.what()): std::runtime_error (cfg::ConfigError, the CSV, checkpoint
// and STL readers' errors) and std::invalid_argument (the facet builders'). Anything else is a
// finding: a crash or a sanitizer report, a hang (libFuzzer's -timeout), and any other exception
// (std::out_of_range from a stoul, std::bad_alloc from a count taken on trust, std::logic_error,
// which the settings tables throw for a bug of the reader), left to escape so that
// std::terminate aborts the run and libFuzzer keeps the input.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace fuzz {

// A folder of this process (vppdem_fuzz_<pid>), made on first use and removed at exit (after
// an abort, by scripts/fuzz.sh): one process writes each input over the last one's file, so a
// run of millions of inputs leaves no files behind; two fuzzers (or a fuzzer and the replay
// test) never share one. In /dev/shm (memory) where there is one: on ext4, rewriting a
// truncated file forces its blocks to disk at close (auto_da_alloc), 3 ms an input, which held
// the fuzzers to 250 inputs a second.
inline const std::filesystem::path& work_dir() {
    // Never destroyed: the exit handler that removes the folder runs after static destructors
    // of objects made later, and must still find the name.
    static const std::filesystem::path* const dir = [] {
        std::error_code ec;
        const std::filesystem::path base =
            std::filesystem::is_directory("/dev/shm", ec) ? "/dev/shm" : std::filesystem::temp_directory_path();
        auto* d = new std::filesystem::path(base / ("vppdem_fuzz_" + std::to_string(::getpid())));
        std::filesystem::create_directories(*d);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(work_dir(), ec);
        });
        return d;
    }();
    return *dir;
}

// Writes `bytes` to work_dir()/name, replacing the previous input, and returns the path.
inline std::string write_file(const std::string& name, std::string_view bytes) {
    const std::string path = (work_dir() / name).string();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
        std::perror(path.c_str());  // the harness's own failure, not the reader's: stop
        std::abort();
    }
    return path;
}

inline std::string_view as_text(const uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// Runs a reader on one input: its documented refusals pass; anything else escapes (above).
// `must_name`, when not empty, is what every refusal must name (the file's path: a message
// that does not say which file is wrong is a finding too).
template <class Read> void expect_only_reader_errors(Read&& read, const std::string& must_name = {}) {
    std::string message;
    try {
        read();
        return;
    } catch (const std::runtime_error& e) {
        message = e.what();
    } catch (const std::invalid_argument& e) {
        message = e.what();
    }
    // Seeds should be accepted: VPPDEM_FUZZ_VERBOSE=1 shows which inputs a reader refuses, and why.
    static const bool verbose = std::getenv("VPPDEM_FUZZ_VERBOSE") != nullptr;
    if (verbose) std::fprintf(stderr, "fuzz: refused: %s\n", message.c_str());
    if (!must_name.empty() && message.find(must_name) == std::string::npos) {
        std::fprintf(stderr, "fuzz: the error does not name '%s': %s\n", must_name.c_str(), message.c_str());
        std::abort();
    }
}

}  // namespace fuzz
