// What the bindings share (src/python/bindings.h): the progress hook, arrays, paths and vectors.
#include "bindings.h"

#include <algorithm>
#include <stdexcept>

namespace bindings {

// A progress hook for the C++ stages: runs with the interpreter lock released around it, takes
// it back, stops the run on a pending signal (KeyboardInterrupt on Ctrl-C) and calls `callback`
// (stage, done, total, time [s]) when it is not None.
Hook python_hook(py::object callback) {
    return [callback](const char* stage, uint64_t done, uint64_t total, double time) {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!callback.is_none()) callback(stage, done, total, time);
    };
}

// n x 3 array of Vec3 [units of the source].
py::array_t<double> vec3_array(const std::vector<dem::Vec3>& v) {
    py::array_t<double> a({py::ssize_t(v.size()), py::ssize_t(3)});
    auto m = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < v.size(); ++i) {
        m(py::ssize_t(i), 0) = v[i].x;
        m(py::ssize_t(i), 1) = v[i].y;
        m(py::ssize_t(i), 2) = v[i].z;
    }
    return a;
}

// A str or os.PathLike as a path.
std::string fspath(const py::object& p) { return py::str(py::module_::import("os").attr("fspath")(p)); }

py::array_t<double> double_array(const std::vector<double>& v) {
    py::array_t<double> a(py::ssize_t(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

dem::Vec3 to_vec3(const std::vector<double>& v, const char* what) {
    if (v.size() != 3) throw std::invalid_argument(std::string(what) + ": expected 3 components, got " + std::to_string(v.size()));
    return {v[0], v[1], v[2]};
}

}  // namespace bindings
