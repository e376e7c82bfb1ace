#include "vpp/plot.h"

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

std::string tool_path(const std::string& script) {
    if (const char* d = std::getenv("VPPDEM_TOOLS_DIR")) return (fs::path(d) / script).string();
    return (fs::path(VPPDEM_SOURCE_DIR) / "tools" / script).string();
}

std::string python_interpreter() {
    // The python3 first on PATH may be another interpreter without Debian's matplotlib.
    return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

namespace {
int run_tool(const std::string& script, const std::string& dir, bool quiet) {
    const std::string cmd = python_interpreter() + " " + shell_quote(tool_path(script)) + " " + shell_quote(dir);
    const int rc = std::system(cmd.c_str());
    if (rc != 0 && !quiet) std::fprintf(stderr, "vppdem: plotting failed (%s); the CSV outputs are complete\n", cmd.c_str());
    return rc;
}
}  // namespace

int plot_damper_dir(const std::string& dir, bool quiet) { return run_tool("plot_damper.py", dir, quiet); }
int plot_sweep_dir(const std::string& dir, bool quiet) { return run_tool("plot_sweep.py", dir, quiet); }
int plot_calibration_dir(const std::string& dir, bool quiet) { return run_tool("plot_calibration.py", dir, quiet); }

}  // namespace vpp
