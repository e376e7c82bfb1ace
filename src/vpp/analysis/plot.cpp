#include "vpp/analysis/plot.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace vpp {

namespace fs = std::filesystem;

namespace {
std::string shell_quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}
}  // namespace

std::string python_interpreter() {
    // The python3 first on PATH may be another interpreter without Debian's matplotlib.
    return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

namespace {
std::string python_package_dir() {
    if (const char* d = std::getenv("VPPDEM_PYTHON_DIR"); d && *d) return d;
    return (fs::path(VPPDEM_SOURCE_DIR) / "src" / "python").string();
}

// kind: "damper", "sweep", "calibration", "device_study", or "" for what the folder holds. The
// package's folder goes in front of the caller's PYTHONPATH, which stays for whatever else the
// plots import.
int run_plot(const std::string& dir, const std::string& kind, bool quiet) {
    std::string path = python_package_dir();
    if (const char* p = std::getenv("PYTHONPATH"); p && *p) path += std::string(":") + p;
    const std::string cmd = "PYTHONPATH=" + shell_quote(path) + " " + python_interpreter() + " -m vppdem.plot " +
                            shell_quote(dir) + (kind.empty() ? "" : " --kind " + kind);
    const int rc = std::system(cmd.c_str());
    if (rc != 0 && !quiet) std::fprintf(stderr, "vppdem: plotting failed (%s); the CSV outputs are complete\n", cmd.c_str());
    return rc;
}
}  // namespace

int plot_damper_dir(const std::string& dir, bool quiet) { return run_plot(dir, "damper", quiet); }
int plot_sweep_dir(const std::string& dir, bool quiet) { return run_plot(dir, "sweep", quiet); }
int plot_calibration_dir(const std::string& dir, bool quiet) { return run_plot(dir, "calibration", quiet); }
int plot_device_study_dir(const std::string& dir, bool quiet) { return run_plot(dir, "device_study", quiet); }
int plot_dir(const std::string& dir, bool quiet) { return run_plot(dir, "", quiet); }

}  // namespace vpp
