// Shared helpers for the tests that drive the vppdem binary as a user does (damper, studies,
// energy through the damper): run a command, read its CSV outputs, scratch folders.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <functional>
#include <thread>
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
// narrow, loose packing, fast loading, few samples, at the default time step (the golden results).
inline const std::string kSmallDamperAtTheDefaultStep =
    "--set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 "
    "--set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=2 "
    "--set process.samples_per_cycle=80 --set simulation.threads=1 --no-plot --quiet";
// The feature tests' damper: the same, mass-scaled. These tests check features (resuming,
// records, refusals, bits), not the step's convergence or the grains' inertia: dt_safety 0.45 and
// both densities 100 times the paper's make the time step 10 times longer (dt ~ sqrt(m/k)) and a
// run about 5 times quicker (gravity settles the pour in the same simulated time), which keeps the
// README's test command within minutes. The golden results keep the paper's densities and step.
inline const std::string kMassScaled = " --set grains.density=268963.9 --set foil.density=15177";
inline const std::string kSmallDamper = kSmallDamperAtTheDefaultStep + " --set simulation.dt_safety=0.45" + kMassScaled;
// At the paper's densities, for the tests whose question is a run's physics that the scaled
// grains' inertia changes (the air's pressure swing, energy closure over many steps).
inline const std::string kSmallDamperPaperMasses = kSmallDamperAtTheDefaultStep + " --set simulation.dt_safety=0.45";

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

// A word for the shell, single-quoted.
inline std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}
inline std::string quote(const fs::path& p) { return quote(p.string()); }

// A command's exit code: 128 + the signal when one killed it (-1: it did not run).
struct RunResult {
    int rc = -1;
    std::string output;  // stdout and stderr together
};

// `vppdem ARGS` by the binary's quoted path, from the folder `cwd` when given.
inline RunResult run_vppdem(const std::string& args, const fs::path& cwd = {}) {
    const Outcome o = shell((cwd.empty() ? std::string() : "cd " + quote(cwd) + " && ") + quote(kBinary) + " " + args);
    const int s = o.status;
    return {s == -1 ? -1 : WIFEXITED(s) ? WEXITSTATUS(s) : 128 + WTERMSIG(s), o.output};
}

// The factor on every wall-clock budget of a test that waits for a run: VPPDEM_TEST_TIME_SCALE
// (default 1). Under AddressSanitizer and UndefinedBehaviorSanitizer a run is 20 to 50 times
// slower, and a budget sized for the optimised build would fail a clean test
// (scripts/sanitize.sh sets 50). A value that is not a positive number is ignored.
inline double time_scale() {
    const char* v = std::getenv("VPPDEM_TEST_TIME_SCALE");
    if (!v) return 1.0;
    char* end = nullptr;
    const double s = std::strtod(v, &end);
    return (end != v && *end == '\0' && std::isfinite(s) && s > 0.0) ? s : 1.0;
}

// Starts `vppdem ARGS` in the background (output discarded), waits until `ready()` holds
// (polled every 10 ms), then kills it (SIGKILL). Returns true when the kill interrupted the
// command; false when it ended first (finished or failed) or `ready()` never held in timeout_s
// (times time_scale()).
// The tests of resuming kill a run at a known point instead of after a fixed time, which a fast
// machine outruns and a busy one never reaches.
inline bool kill_when(const std::string& args, const std::function<bool()>& ready, double timeout_s = 300) {
    const std::string cmd = "exec " + kBinary + " " + args + " > /dev/null 2>&1";
    const pid_t pid = fork();
    if (pid < 0) return false;
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd.c_str(), (char*)nullptr);
        _exit(127);
    }
    timeout_s *= time_scale();
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < timeout_s) {
        if (waitpid(pid, nullptr, WNOHANG) == pid) return false;  // ended by itself
        if (ready()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const bool running = waitpid(pid, nullptr, WNOHANG) == 0;
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    return running && ready();
}

// Starts `vppdem ARGS` in the background, its stdout and stderr into `log`; returns its pid
// (the caller waits for it: finish()).
inline pid_t start(const std::string& args, const fs::path& log) {
    const std::string cmd = "exec " + kBinary + " " + args + " > '" + log.string() + "' 2>&1";
    const pid_t pid = fork();
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd.c_str(), (char*)nullptr);
        _exit(127);
    }
    return pid;
}

// Waits for a start()ed command; its exit status (-1 when it did not exit normally).
inline int finish(pid_t pid) {
    int status = 0;
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Polls `ready()` every 10 ms while the start()ed `pid` runs; false when it ended first or
// timeout_s (times time_scale()) passed.
inline bool wait_while_running(pid_t pid, const std::function<bool()>& ready, double timeout_s = 300) {
    timeout_s *= time_scale();
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < timeout_s) {
        if (ready()) return true;
        siginfo_t info{};  // WNOWAIT: an ended command is left for finish() to reap
        if (waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0 || info.si_pid != 0) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

// Holds a start()ed command stopped (SIGSTOP) for the object's lifetime, so that a test can act
// while it is certainly still running (a small run may otherwise end within the test's next
// step); it continues on destruction. `held()` is false when the command had already ended.
class Held {
public:
    explicit Held(pid_t pid) : pid_(pid) {
        siginfo_t info{};
        held_ = kill(pid_, SIGSTOP) == 0 && waitid(P_PID, id_t(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
                info.si_pid == 0;
    }
    ~Held() { kill(pid_, SIGCONT); }
    Held(const Held&) = delete;
    Held& operator=(const Held&) = delete;
    bool held() const { return held_; }

private:
    pid_t pid_;
    bool held_ = false;
};

// Rows of a CSV file after its header (0 when it is missing).
inline std::size_t data_rows(const fs::path& p) {
    std::ifstream in(p);
    std::size_t n = 0;
    std::string line;
    if (!std::getline(in, line)) return 0;
    while (std::getline(in, line))
        if (!line.empty()) ++n;
    return n;
}

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

// The number after "key": in a JSON text (a summary.json), searched from the first occurrence
// of "within": (an enclosing object's key) when given; NaN when missing or null.
inline double json_number(const std::string& js, const std::string& key, const std::string& within = "") {
    std::size_t p = 0;
    if (!within.empty()) {
        p = js.find("\"" + within + "\":");
        if (p == std::string::npos) return std::nan("");
    }
    p = js.find("\"" + key + "\":", p);
    if (p == std::string::npos) return std::nan("");
    const char* s = js.c_str() + p + key.size() + 3;
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    return end == s ? std::nan("") : v;
}

inline void write_file(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

}  // namespace cli_test
