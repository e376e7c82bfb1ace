// Plots through the Python package's vppdem.plot (numpy and matplotlib; Debian's under
// /usr/bin/python3).
#pragma once

#include <string>

namespace vpp {

// The interpreter that sees Debian's python3-* packages.
std::string python_interpreter();
// The plots of an output folder by `python3 -m vppdem.plot`, the package vppdem taken from
// VPPDEM_PYTHON_DIR when set, else from the source tree's src/python (the plots need no compiled
// module); each returns the exit status (0 = ok).
int plot_damper_dir(const std::string& dir, bool quiet);       // the loops of a damper folder
int plot_sweep_dir(const std::string& dir, bool quiet);        // the plots of a sweep (summary.csv)
int plot_calibration_dir(const std::string& dir, bool quiet);  // calibration.png (calibration.json)
int plot_device_study_dir(const std::string& dir, bool quiet); // sweep_numbers.png of a device study
// What the folder holds: a calibration's plot and its sweep's, a device study's, a sweep's, a
// device run's or a damper's.
int plot_dir(const std::string& dir, bool quiet);

}  // namespace vpp
