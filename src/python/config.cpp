// vppdem._core.Config: the damper's settings as the C++ reads them (vpp/settings/config.h), and
// load_config, which makes one.
#include "bindings.h"

#include "vpp/settings/config.h"

namespace bindings {

void bind_config(py::module_& m) {
    py::class_<vpp::Config>(m, "Config", "The damper's settings (vpp/settings/config.h); made by load_config")
        .def("given", [](const vpp::Config& c) { return std::vector<std::string>(c.given.begin(), c.given.end()); });
    m.def(
        "load_config",
        [](const std::string& path, const std::vector<std::string>& sets) {
            return vpp::load_config(path, sets);
        },
        py::arg("path") = "", py::arg("sets") = std::vector<std::string>{},
        "Reads a damper config (empty path: defaults) with key=value overrides, as `vppdem damper --set`");
}

}  // namespace bindings
