// The Python module's compiled core (vppdem._core), one file per bound class: the damper's
// config (config.cpp), its stages (damper.cpp, vpp::Damper), the generic DEM World (world.cpp);
// beside them the settings tables (settings.cpp) and the runs of the commands (runs.cpp: device,
// sweep, the study's cases, calibrate). Each file's bind_NAME(m) adds its part; module.cpp calls
// them. What they share is declared here (common.cpp).
//
// The module sits on top of vpp and dem, beside the command line; nothing below includes it.
// Stepping releases the interpreter lock; a progress hook takes it back every 256 steps to call
// the Python callback and to look for Ctrl-C (PyErr_CheckSignals), which raises
// KeyboardInterrupt out of the run.
#pragma once

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dem/core/vec3.h"

namespace py = pybind11;

namespace bindings {

void bind_config(py::module_& m);    // Config, load_config
void bind_settings(py::module_& m);  // damper_settings, scene_settings, record_columns
void bind_damper(py::module_& m);    // Damper
void bind_world(py::module_& m);     // World
void bind_runs(py::module_& m);      // device, sweep, study_cases, calibrate

// A C++ stage's progress hook (stage, steps done, steps expected, simulated time [s]) that calls
// a Python callback (None: none) and stops the run on Ctrl-C.
using Hook = std::function<void(const char*, uint64_t, uint64_t, double)>;
Hook python_hook(py::object callback);

py::array_t<double> vec3_array(const std::vector<dem::Vec3>& v);  // n x 3
py::array_t<double> double_array(const std::vector<double>& v);
std::string fspath(const py::object& p);                              // a str or os.PathLike
dem::Vec3 to_vec3(const std::vector<double>& v, const char* what);  // 3 components, else ValueError naming `what`

}  // namespace bindings
