// Plots through matplotlib (Debian's python3-matplotlib under /usr/bin/python3).
#pragma once

#include <string>

namespace vpp {

// Path of a script in the repository's tools/ folder (VPPDEM_TOOLS_DIR overrides it).
std::string tool_path(const std::string& script);
// The interpreter that sees Debian's python3-* packages.
std::string python_interpreter();
// Runs tools/plot_damper.py on a damper output folder; returns the exit status (0 = ok).
int plot_damper_dir(const std::string& dir, bool quiet);
// Runs tools/plot_sweep.py on a sweep output folder (one holding summary.csv).
int plot_sweep_dir(const std::string& dir, bool quiet);
// Runs tools/plot_calibration.py on a calibration output folder (calibration.json).
int plot_calibration_dir(const std::string& dir, bool quiet);

}  // namespace vpp
