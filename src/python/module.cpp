// The Python module's compiled core (vppdem._core): the damper's stages (vpp::Damper), the
// generic DEM World, the sweep and the calibration, over the same C++ as the command line.
// vppdem/__init__.py wraps it (settings as dicts, progress bars, summary as a dict). One file a
// bound class and one for the runs (src/python/bindings.h lists them); this one makes the module.
#include "bindings.h"

#include <exception>

#include "scene/build_info.h"
#include "scene/config.h"

PYBIND11_MODULE(_core, m) {
    m.doc() = "vppdem's compiled core; use the vppdem package";
    m.def("build", [] {
        py::dict d;
        d["commit"] = scene::build_commit();
        d["id"] = scene::build_id();
        return d;
    });

    // C++ errors with the command line's messages: bad config keys and values (cfg::ConfigError)
    // as vppdem.ConfigError (a ValueError), the others as RuntimeError (pybind11's default for
    // std::runtime_error; std::invalid_argument gives ValueError).
    static py::exception<cfg::ConfigError> config_error(m, "ConfigError", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const cfg::ConfigError& e) {
            config_error(e.what());
        }
    });

    bindings::bind_config(m);
    bindings::bind_settings(m);
    bindings::bind_damper(m);
    bindings::bind_world(m);
    bindings::bind_runs(m);
}
