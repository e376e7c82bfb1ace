// The Python module's compiled core (vppdem._core): the damper's stages (vpp::Damper), the
// generic DEM World, the sweep and the calibration, over the same C++ as the command line.
// vppdem/__init__.py wraps it (settings as dicts, progress bars, summary as a dict).
//
// The module sits on top of vpp and dem, beside the command line; nothing below includes it.
// Stepping releases the interpreter lock; a progress hook takes it back every 256 steps to call
// the Python callback and to look for Ctrl-C (PyErr_CheckSignals), which raises
// KeyboardInterrupt out of the run.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <numbers>
#include <string>
#include <vector>

#include "scene/build_info.h"
#include "scene/config.h"
#include "scene/scene_settings.h"
#include "dem/world/world.h"
#include "dem/io/checkpoint.h"
#include "dem/walls/facet_sets.h"
#include "vpp/calibration/calibrate.h"
#include "vpp/settings/config.h"
#include "vpp/damper/damper.h"
#include "vpp/device/definition.h"
#include "vpp/device/run.h"
#include "vpp/study/device_study.h"
#include "vpp/settings/settings.h"
#include "vpp/analysis/records.h"
#include "vpp/study/study.h"

namespace py = pybind11;

namespace {

using Hook = std::function<void(const char*, uint64_t, uint64_t, double)>;

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

// Runs a sweep or a calibration (`run`, handed the sweep options' progress hook) without the
// interpreter lock, stoppable with Ctrl-C. Python sees signals only on the main thread, so the
// study runs on a thread of its own while this one wakes every 0.1 s [wall clock] to look for
// them; the study's worker threads take the lock only to call `callback` (done, total, case
// name) after each finished case. A signal, or an exception of the callback, stops the study
// (vpp::SweepOptions::progress: finished cases kept, the folder resumable) and is raised here.
template <class Run>
auto run_stoppable(const py::object& callback, Run run) {
    struct Shared {
        std::atomic<bool> stop{false};
        std::mutex mu;
        std::exception_ptr error;  // the first Python exception (a py::error_already_set)
    } sh;
    const py::object* cb = &callback;  // no copies of the object without the lock
    auto hook = [&sh, cb](std::size_t done, std::size_t total, const std::string& name) -> bool {
        if (sh.stop.load()) return false;
        if (name.empty() || cb->is_none()) return true;  // a poll between steps: no lock
        py::gil_scoped_acquire gil;
        try {
            (*cb)(done, total, name);
            return true;
        } catch (py::error_already_set&) {
            std::lock_guard<std::mutex> lk(sh.mu);
            if (!sh.error) sh.error = std::current_exception();
            sh.stop.store(true);
            return false;
        }
    };
    using Result = decltype(run(hook));
    Result result{};
    std::exception_ptr failure;
    {
        py::gil_scoped_release release;
        std::atomic<bool> finished{false};
        std::thread t([&] {
            try {
                result = run(hook);
            } catch (...) {
                failure = std::current_exception();
            }
            finished.store(true);
        });
        while (!finished.load()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            py::gil_scoped_acquire gil;
            if (!sh.stop.load() && PyErr_CheckSignals() != 0) {
                std::lock_guard<std::mutex> lk(sh.mu);
                if (!sh.error) sh.error = std::make_exception_ptr(py::error_already_set());
                sh.stop.store(true);
            }
        }
        t.join();
    }
    if (sh.error) std::rethrow_exception(sh.error);  // KeyboardInterrupt, or the callback's error
    if (failure) std::rethrow_exception(failure);
    return result;
}

// vpp::Damper as Python holds it, with who is using it. A stage (prepare, vacuum, cycle) and
// save/write run without the interpreter lock, so a second Python thread could otherwise call
// into the same object meanwhile: a second cycle() replaced the progress hook under the running
// one and both stepped one World (double free, segfault); a read (d.W) walked vectors being
// grown. Such a call is refused with a RuntimeError rather than serialised behind a lock: the
// wait would be the rest of a run (minutes to hours) with nothing saying why, and a lock would
// deadlock the one legitimate nested call, a read from the run's own progress callback (which
// runs on the running thread, between steps, where the state is consistent: allowed). The
// fields are read and written only with the interpreter lock held, which orders them.
struct PyDamper {
    std::unique_ptr<vpp::Damper> d;
    const char* running = nullptr;  // the call running without the lock, or nullptr
    std::thread::id owner;          // the thread it runs on

    [[noreturn]] void refuse(const char* what) const {
        if (owner != std::this_thread::get_id())
            throw std::runtime_error(std::string("Damper.") + what + "(): this Damper is running " + running +
                                     "() in another thread; one call at a time per Damper: wait until it returns "
                                     "(a progress callback sees the run between steps, on its own thread)");
        throw std::runtime_error(std::string("Damper.") + what + "(): called from within " + running +
                                 "() (its progress callback): a stage cannot start while another runs; "
                                 "call it after " + running + "() returns");
    }
    // A call that keeps the lock: refused while another thread runs a call on this object.
    const vpp::Damper& read(const char* what) const {
        if (running && owner != std::this_thread::get_id()) refuse(what);
        return *d;
    }
    // Marks a call that releases the lock for its duration. `stage`: it changes the run
    // (prepare, vacuum, cycle), refused even from the running call's own progress callback;
    // save and write only read, allowed there.
    class Run {
    public:
        Run(PyDamper& p, const char* what, bool stage) : p_(p) {
            if (p.running && (stage || p.owner != std::this_thread::get_id())) p.refuse(what);
            if (!p.running) {
                p.running = what;
                p.owner = std::this_thread::get_id();
                set_ = true;
            }
        }
        ~Run() {
            if (set_) p_.running = nullptr;  // the lock is held again here (declared before the release)
        }
        Run(const Run&) = delete;
        Run& operator=(const Run&) = delete;

    private:
        PyDamper& p_;
        bool set_ = false;
    };
};

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

// A wall's or particle's motion: a constant velocity [m/s] from now on, or a displacement history
// of rows (t [s], dx, dy, dz [m]) from the reference position. The core's constant velocity
// counts from t = 0 (displacement = v t), which would make a wall set moving mid-run jump; from
// Python a velocity starts where the wall stands now (`now` [s], displaced by `d_now` [m]).
dem::Motion make_motion(const std::vector<double>& velocity, const std::vector<std::vector<double>>& history,
                        double now, dem::Vec3 d_now) {
    if (!velocity.empty() && !history.empty()) throw std::invalid_argument("motion: give velocity or history, not both");
    dem::Motion m;
    if (!velocity.empty()) {
        const dem::Vec3 v = to_vec3(velocity, "velocity");
        if (now == 0.0 && d_now == dem::Vec3{}) {
            m.velocity = v;
        } else {
            constexpr double kHorizon = 1e3;  // [s] of simulated time the motion runs for
            m.history = {{now, d_now}, {now + kHorizon, d_now + v * kHorizon}};
        }
    }
    for (const auto& row : history) {
        if (row.size() != 4) throw std::invalid_argument("history: each row is (t, dx, dy, dz)");
        if (!m.history.empty() && !(row[0] > m.history.back().time))
            throw std::invalid_argument("history: times must increase");
        m.history.push_back({row[0], {row[1], row[2], row[3]}});
    }
    return m;
}

// A settings table's row as a dict: what both tables have (the rest is added by the caller).
py::dict setting_dict(const std::string& key, cfg::SettingType type, const char* unit, const std::string& allowed,
                      const std::string& doc) {
    py::dict r;
    r["key"] = key;
    r["type"] = cfg::type_name(type);
    r["unit"] = unit;
    r["allowed"] = allowed;
    r["doc"] = doc;
    return r;
}

// A numeric default as the Python value of its type.
py::object default_value(cfg::SettingType type, double v) {
    if (type == cfg::SettingType::Boolean) return py::bool_(v != 0.0);
    if (type == cfg::SettingType::Integer) return py::int_(int64_t(v));
    return py::float_(v);
}

}  // namespace

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

    // --- configuration ------------------------------------------------------------------------
    py::class_<vpp::Config>(m, "Config", "The damper's settings (vpp/settings/config.h); made by load_config")
        .def("given", [](const vpp::Config& c) { return std::vector<std::string>(c.given.begin(), c.given.end()); });
    m.def(
        "load_config",
        [](const std::string& path, const std::vector<std::string>& sets) {
            return vpp::load_config(path, sets);
        },
        py::arg("path") = "", py::arg("sets") = std::vector<std::string>{},
        "Reads a damper config (empty path: defaults) with key=value overrides, as `vppdem damper --set`");

    // The settings tables (docs/config.md) as lists of dicts, for a notebook's reference.
    m.def("damper_settings", [] {
        py::list rows;
        for (const vpp::Setting& s : vpp::settings()) {
            py::dict r = setting_dict(s.key, s.type, s.unit, cfg::allowed_text(s.type, s.limits()), s.doc);
            r["default"] = std::isnan(s.def) ? py::object(py::str(s.default_text)) : default_value(s.type, s.def);
            if (!std::isnan(s.def_foil)) r["default_tension_envelope"] = s.def_foil;
            r["acts_on"] = vpp::acts_name(s.acts);
            r["shares_preparation"] = s.shares_preparation;
            rows.append(r);
        }
        return rows;
    });
    // The records' columns (vpp/analysis/records.h): what cycles() and forces() hold, with units.
    m.def("record_columns", [] {
        py::list rows;
        auto row = [&](const char* record, const char* name, const char* unit, const char* meaning, const char* only_with) {
            py::dict r;
            r["record"] = record;
            r["name"] = name;
            r["unit"] = unit;
            r["meaning"] = meaning;
            r["only_with"] = only_with;
            rows.append(r);
        };
        for (const vpp::CycleColumn& c : vpp::cycle_columns())
            row("cycles", c.name, c.unit, c.meaning,
                c.group == vpp::CycleGroup::Energy   ? "output.energy"
                : c.group == vpp::CycleGroup::Settle ? "a damper run"
                                                     : "");
        for (const vpp::SampleColumn& c : vpp::sample_columns())
            row("forces", c.name, c.unit, c.meaning,
                c.air ? "the air record (process.pressure_model = \"pump\" or output.air)" : "");
        return rows;
    });
    m.def("scene_settings", [] {
        py::list rows;
        for (const scene::SceneSetting& s : scene::scene_settings()) {
            py::dict r = setting_dict(s.key, s.type, s.unit, cfg::allowed_text(s.type, s.limits), s.doc);
            if (s.required) r["default"] = py::none();
            else if (*s.default_text) r["default"] = s.default_text;
            else if (s.type == cfg::SettingType::Vec3) r["default"] = py::make_tuple(s.def3.x, s.def3.y, s.def3.z);
            else r["default"] = default_value(s.type, s.def);
            r["required"] = s.required;
            rows.append(r);
        }
        return rows;
    });

    // --- the damper -----------------------------------------------------------------------------
    // Every method goes through PyDamper's guards (see there): while a stage runs without the
    // interpreter lock, another thread's call on the same object is refused, not a data race.
    py::class_<PyDamper>(m, "Damper")
        .def(py::init([](const vpp::Config& c, const std::string& out, const std::string& from, bool overwrite,
                         bool quiet) {
                 vpp::DamperOptions o;
                 o.out_dir = out;
                 o.from = from;
                 o.overwrite = overwrite;
                 o.quiet = quiet;
                 o.plot = false;
                 auto p = std::make_unique<PyDamper>();
                 py::gil_scoped_release release;  // pours the grains (or loads the checkpoint); no step
                 p->d = std::make_unique<vpp::Damper>(c, o);
                 return p;
             }),
             py::arg("config"), py::arg("out") = "", py::arg("from_checkpoint") = "", py::arg("overwrite") = false,
             py::arg("quiet") = true)
        .def("prepare", [](PyDamper& p, py::object progress) {
                 PyDamper::Run run(p, "prepare", true);
                 p.d->set_progress(python_hook(progress));  // replaced with the lock held: it holds a Python object
                 py::gil_scoped_release release;
                 p.d->prepare();
             }, py::arg("progress") = py::none())
        .def("vacuum", [](PyDamper& p, py::object progress) {
                 PyDamper::Run run(p, "vacuum", true);
                 p.d->set_progress(python_hook(progress));
                 py::gil_scoped_release release;
                 p.d->vacuum();
             }, py::arg("progress") = py::none())
        .def("cycle", [](PyDamper& p, int n, py::object progress) {
                 // n < 0 is the C++ "all that remain"; only -1 means it here (vppdem.Damper.cycle
                 // passes -1 for None), so that a negative count is not taken for "all".
                 if (n < -1) throw std::invalid_argument("cycle(): n = " + std::to_string(n) + ": a count of cycles >= 1 (-1: all that remain)");
                 PyDamper::Run run(p, "cycle", true);
                 p.d->set_progress(python_hook(progress));
                 py::gil_scoped_release release;
                 return p.d->cycle(n);
             }, py::arg("n") = -1, py::arg("progress") = py::none())
        .def("save", [](PyDamper& p, const std::string& path) {
                 PyDamper::Run run(p, "save", false);
                 const vpp::Damper& d = *p.d;
                 py::gil_scoped_release release;
                 d.save(path);
             }, py::arg("path"))
        .def("stage", [](const PyDamper& p) { return p.read("stage").stage(); })
        .def("cycles_done", [](const PyDamper& p) { return p.read("cycles_done").cycles_done(); })
        .def("cycles_total", [](const PyDamper& p) { return p.read("cycles_total").cycles_total(); })
        .def("busy", [](const PyDamper& p) { return p.running ? py::object(py::str(p.running)) : py::object(py::none()); },
             "The stage call running now (\"prepare\", \"vacuum\", \"cycle\"), or None")
        .def("samples",
             [](const PyDamper& p) {
                 // (n, 4): time [s], displacement [m], grains [N], foil [N]
                 const auto& s = p.read("samples").samples();
                 py::array_t<double> a({py::ssize_t(s.size()), py::ssize_t(4)});
                 auto v = a.mutable_unchecked<2>();
                 for (std::size_t k = 0; k < s.size(); ++k) {
                     v(py::ssize_t(k), 0) = s[k].time;
                     v(py::ssize_t(k), 1) = s[k].displacement;
                     v(py::ssize_t(k), 2) = s[k].grains;
                     v(py::ssize_t(k), 3) = s[k].foil;
                 }
                 return a;
             })
        .def("air",
             [](const PyDamper& p) {
                 // (n, 6): enclosed volume [m^3], gas volume [m^3], p_inside [Pa], dp [Pa], lid
                 // area [m^2], gas work [J]; (0, 6) unless the air is recorded
                 const auto& s = p.read("air").air();
                 py::array_t<double> a({py::ssize_t(s.size()), py::ssize_t(6)});
                 auto v = a.mutable_unchecked<2>();
                 for (std::size_t k = 0; k < s.size(); ++k) {
                     const double row[6] = {s[k].enclosed, s[k].gas, s[k].p_inside, s[k].dp, s[k].lid_area, s[k].gas_work};
                     for (py::ssize_t j = 0; j < 6; ++j) v(py::ssize_t(k), j) = row[j];
                 }
                 return a;
             })
        .def("energy",
             [](const PyDamper& p) {
                 const auto rows = p.read("energy").energy();
                 const std::size_t nc = vpp::Damper::energy_columns().size();
                 py::array_t<double> a({py::ssize_t(rows.size()), py::ssize_t(nc)});
                 auto v = a.mutable_unchecked<2>();
                 for (std::size_t k = 0; k < rows.size(); ++k)
                     for (std::size_t j = 0; j < nc; ++j) v(py::ssize_t(k), py::ssize_t(j)) = rows[k][j];
                 return a;
             })
        .def_static("energy_columns", &vpp::Damper::energy_columns)
        .def("cycles",
             [](const PyDamper& p) {
                 // Per cycle, every column of the record's table (vpp/analysis/records.h): cycles.csv's and
                 // summary.json's, NaN where a cycle lacks the column's group (no energy ledger).
                 const vpp::DamperResult r = p.read("cycles").result();
                 const double nan = std::numeric_limits<double>::quiet_NaN();
                 py::dict out;
                 for (const vpp::CycleColumn& col : vpp::cycle_columns()) {
                     std::vector<double> v;
                     for (const auto& c : r.cycles) v.push_back(vpp::cycle_has(c, col.group) ? col.get(c) : nan);
                     out[col.name] = double_array(v);
                 }
                 return out;
             })
        .def("forces",
             [](const PyDamper& p) {
                 // forces.csv's columns as arrays (vpp/analysis/records.h, sample_columns()), from the same
                 // rows the file is written from.
                 const vpp::ForcesTable t = p.read("forces").forces();
                 py::dict out;
                 for (std::size_t j = 0; j < t.columns.size(); ++j) {
                     std::vector<double> v;
                     v.reserve(t.rows.size());
                     for (const auto& row : t.rows) v.push_back(row[j]);
                     out[t.columns[j].c_str()] = double_array(v);
                 }
                 return out;
             })
        .def("summary_json", [](const PyDamper& p, const std::string& from) {
                 return vpp::damper_summary_json(p.read("summary_json").result(), from);
             }, py::arg("from_checkpoint") = "")
        .def("write", [](PyDamper& p, const std::string& out, const std::string& from) {
                 PyDamper::Run run(p, "write", false);
                 const vpp::Damper& d = *p.d;
                 vpp::DamperOptions o;
                 o.out_dir = out;
                 o.from = from;
                 py::gil_scoped_release release;
                 vpp::write_damper_outputs(d, o);
             }, py::arg("out"), py::arg("from_checkpoint") = "")
        .def("config", [](const PyDamper& p) { return p.read("config").config(); })
        .def("positions", [](const PyDamper& p) { return vec3_array(p.read("positions").world().particles.pos); })
        .def("radii", [](const PyDamper& p) { return double_array(p.read("radii").world().particles.radius); })
        .def("time", [](const PyDamper& p) { return p.read("time").world().time; });

    // --- the generic World -----------------------------------------------------------------------
    py::class_<dem::World>(m, "World")
        .def(py::init<>())
        .def("add_material",
             [](dem::World& w, const std::string& name, double density, double young, double stiffness_ratio,
                double friction, double restitution) {
                 return w.add_material({name, density, young, stiffness_ratio, friction, restitution});
             },
             py::arg("name") = "", py::arg("density") = 2800.0, py::arg("young") = 4.8e10,
             py::arg("stiffness_ratio") = 0.5, py::arg("friction") = 0.35, py::arg("restitution") = 1.0,
             "Adds a material; returns its index. density [kg/m^3], young: particle modulus [Pa] (kn = E r for "
             "two equal spheres), stiffness_ratio ks/kn [-], friction: Coulomb coefficient [-], restitution: "
             "normal coefficient [-] (1: no viscous damping)")
        .def("add_sphere",
             [](dem::World& w, const std::vector<double>& position, double radius, uint32_t material,
                const std::vector<double>& velocity, const std::vector<double>& angular_velocity, uint32_t mask) {
                 if (material >= w.materials.size()) throw std::invalid_argument("add_sphere: no material " + std::to_string(material) + "; add_material first");
                 dem::SphereDef d;
                 d.position = to_vec3(position, "position");
                 d.radius = radius;
                 d.material = material;
                 d.velocity = to_vec3(velocity, "velocity");
                 d.angular_velocity = to_vec3(angular_velocity, "angular_velocity");
                 d.mask = mask;
                 return w.add_sphere(d);
             },
             py::arg("position"), py::arg("radius"), py::arg("material") = 0,
             py::arg("velocity") = std::vector<double>{0, 0, 0}, py::arg("angular_velocity") = std::vector<double>{0, 0, 0},
             py::arg("mask") = 1,
             "Adds a sphere; returns its index. position [m], radius [m], velocity [m/s], angular_velocity "
             "[rad/s]; mask: bodies interact when their masks share a bit")
        .def("add_clump",
             [](dem::World& w, const std::vector<double>& position, const py::object& shape, double radius,
                uint32_t material, const std::vector<double>& orientation, const std::vector<double>& velocity,
                const std::vector<double>& angular_velocity, uint32_t mask) {
                 if (material >= w.materials.size()) throw std::invalid_argument("add_clump: no material " + std::to_string(material) + "; add_material first");
                 dem::ClumpShape cs;
                 if (py::isinstance<py::str>(shape)) {
                     if (!(radius > 0)) throw std::invalid_argument("add_clump: a built-in shape needs radius > 0 (the volume-equivalent radius [m])");
                     cs = dem::builtin_clump_shape(shape.cast<std::string>(), radius);
                 } else {
                     // rows (x, y, z, r) [m] of the members in the grain's frame
                     std::vector<dem::ClumpMember> members;
                     for (const auto& row : shape.cast<std::vector<std::vector<double>>>()) {
                         if (row.size() != 4) throw std::invalid_argument("add_clump: each member is a row (x, y, z, r)");
                         members.push_back({{row[0], row[1], row[2]}, row[3]});
                     }
                     cs = dem::make_clump_shape(members);
                     if (radius > 0) cs = dem::scaled_to_radius(cs, radius);
                 }
                 dem::ClumpDef d;
                 d.position = to_vec3(position, "position");
                 if (orientation.size() != 4) throw std::invalid_argument("add_clump: orientation is a quaternion (w, x, y, z)");
                 d.orientation = {orientation[0], orientation[1], orientation[2], orientation[3]};
                 d.velocity = to_vec3(velocity, "velocity");
                 d.angular_velocity = to_vec3(angular_velocity, "angular_velocity");
                 d.material = material;
                 d.mask = mask;
                 const uint32_t first = uint32_t(w.particles.size());
                 const uint32_t k = w.add_clump(cs, d);
                 return py::make_tuple(k, first, cs.members.size());
             },
             py::arg("position"), py::arg("shape"), py::arg("radius") = 0.0, py::arg("material") = 0,
             py::arg("orientation") = std::vector<double>{1, 0, 0, 0}, py::arg("velocity") = std::vector<double>{0, 0, 0},
             py::arg("angular_velocity") = std::vector<double>{0, 0, 0}, py::arg("mask") = 1,
             "Adds a rigid clump; returns (clump index, first member's particle index, member count). shape: a "
             "built-in name (sphere, dimer, trimer, tetrahedron, pellet) scaled to the volume of a sphere of "
             "radius [m], or rows (x, y, z, r) [m] of member spheres (scaled likewise when radius > 0). "
             "position: centre of mass [m]; orientation: quaternion (w, x, y, z) of the principal frame; "
             "velocity [m/s], angular_velocity [rad/s] (world frame)")
        .def("clump_count", [](const dem::World& w) { return w.clumps().size(); })
        .def("clump_state",
             [](const dem::World& w, std::size_t k) {
                 const dem::Clumps& c = w.clumps();
                 if (k >= c.size()) throw std::out_of_range("clump_state: no clump " + std::to_string(k));
                 py::dict out;
                 const auto v3 = [](const dem::Vec3& v) { return py::make_tuple(v.x, v.y, v.z); };
                 out["position"] = v3(c.pos[k]);
                 out["velocity"] = v3(c.vel[k]);
                 out["orientation"] = py::make_tuple(c.q[k].w, c.q[k].x, c.q[k].y, c.q[k].z);
                 out["angular_velocity"] = v3(c.angvel[k]);
                 out["angular_momentum"] = v3(c.mom[k]);
                 out["mass"] = c.mass[k];
                 out["inertia"] = v3(c.inertia[k]);
                 out["kinetic_energy"] = w.clump_kinetic_energy(k);
                 return out;
             },
             py::arg("k"),
             "Clump k at the half step: position [m], velocity [m/s], orientation (w, x, y, z), angular_velocity "
             "[rad/s] and angular_momentum [kg m^2/s] (world frame), mass [kg], principal inertia [kg m^2], "
             "kinetic_energy [J]")
        .def("add_plane",
             [](dem::World& w, const std::vector<double>& point, const std::vector<double>& normal, uint32_t material,
                bool one_sided, uint32_t mask) {
                 dem::Plane p;
                 p.point = to_vec3(point, "point");
                 p.normal = to_vec3(normal, "normal");
                 const double n = dem::norm(p.normal);
                 if (!(n > 0)) throw std::invalid_argument("add_plane: the normal must not be zero");
                 p.normal = p.normal / n;
                 p.material = material;
                 p.one_sided = one_sided;
                 p.mask = mask;
                 return w.add_plane(p);
             },
             py::arg("point"), py::arg("normal"), py::arg("material") = 0, py::arg("one_sided") = false, py::arg("mask") = 1,
             "Adds an infinite plane through point [m] with normal (normalised); returns its wall index")
        .def("add_facets",
             [](dem::World& w, py::array_t<double, py::array::c_style | py::array::forcecast> v, uint32_t material,
                bool one_sided, uint32_t mask) {
                 // (n, 3, 3): n triangles of three vertices [m]; returns the first facet's index
                 if (v.ndim() != 3 || v.shape(1) != 3 || v.shape(2) != 3)
                     throw std::invalid_argument("add_facets: expected an array of shape (n, 3, 3)");
                 auto a = v.unchecked<3>();
                 const uint32_t first = uint32_t(w.facets.size());
                 for (py::ssize_t k = 0; k < a.shape(0); ++k) {
                     dem::Facet f;
                     for (int j = 0; j < 3; ++j) f.vertices[std::size_t(j)] = {a(k, j, 0), a(k, j, 1), a(k, j, 2)};
                     f.material = material;
                     f.one_sided = one_sided;
                     f.mask = mask;
                     w.add_facet(f);
                 }
                 return first;
             },
             py::arg("vertices"), py::arg("material") = 0, py::arg("one_sided") = false, py::arg("mask") = 1,
             "Adds triangles from an (n, 3, 3) array of vertices [m] (normal (v1 - v0) x (v2 - v0)); returns the "
             "first facet's index (wall index: plane_count + facet index)")
        .def("add_stl",
             [](dem::World& w, const py::object& file, double scale, uint32_t material, bool one_sided, uint32_t mask) {
                 const std::string path = fspath(file);
                 // scale: to metres (1e-3 for a file in millimetres); returns (first facet, count)
                 const uint32_t first = uint32_t(w.facets.size());
                 std::vector<dem::Facet> fs = dem::read_stl(path, scale);
                 for (dem::Facet& f : fs) {
                     f.material = material;
                     f.one_sided = one_sided;
                     f.mask = mask;
                     w.add_facet(f);
                 }
                 return py::make_tuple(first, fs.size());
             },
             py::arg("path"), py::arg("scale") = 1.0, py::arg("material") = 0, py::arg("one_sided") = false,
             py::arg("mask") = 1,
             "Adds the triangles of a binary or ASCII STL file, coordinates times scale (1e-3 for millimetres); "
             "returns (first facet, count)")
        .def("add_bond", &dem::World::add_bond, py::arg("i"), py::arg("j"), py::arg("kn"), py::arg("ks"),
             py::arg("rest_length") = -1.0, "Permanent bond: kn, ks [N/m]; rest_length [m] (< 0: the current distance)")
        .def_property(
            "bond_arm", [](const dem::World& w) { return dem::bond_arm_name(w.bonds().arm); },
            [](dem::World& w, const std::string& a) {
                const std::optional<dem::BondArm> arm = dem::bond_arm_from_name(a);
                if (!arm) throw py::value_error("bond_arm: '" + a + "' is not allowed (\"radius\" or \"bond_point\")");
                w.set_bond_arm(*arm);
            },
            "Where the bonds' shear springs are driven from: \"radius\" (the full radii, the paper's convention) or "
            "\"bond_point\" (where the torques act: a rigid motion loads no spring)")
        .def("set_fixed", &dem::World::set_fixed, py::arg("i"))
        .def("set_plane_motion",
             [](dem::World& w, std::size_t k, const std::vector<double>& velocity,
                const std::vector<std::vector<double>>& history) {
                 if (k >= w.planes.size()) throw std::out_of_range("set_plane_motion: no plane " + std::to_string(k));
                 w.planes[k].motion = make_motion(velocity, history, w.time, w.planes[k].motion.displacement(w.time));
                 w.invalidate_candidates();
             },
             py::arg("plane"), py::arg("velocity") = std::vector<double>{}, py::arg("history") = std::vector<std::vector<double>>{},
             "Moves plane k: velocity [m/s] from where it stands now, or history rows (t [s], dx, dy, dz [m]) "
             "of displacement from its reference position")
        .def("set_facet_motion",
             [](dem::World& w, std::size_t first, std::size_t count, const std::vector<double>& velocity,
                const std::vector<std::vector<double>>& history) {
                 if (first + count > w.facets.size()) throw std::out_of_range("set_facet_motion: facets out of range");
                 const dem::Motion m = make_motion(velocity, history, w.time, w.facets[first].motion.displacement(w.time));
                 for (std::size_t k = first; k < first + count; ++k) w.facets[k].motion = m;
                 w.invalidate_candidates();
             },
             py::arg("first"), py::arg("count"), py::arg("velocity") = std::vector<double>{},
             py::arg("history") = std::vector<std::vector<double>>{})
        .def("set_particle_motion",
             [](dem::World& w, uint32_t i, const std::vector<double>& velocity, const std::vector<std::vector<double>>& history) {
                 // from its current position (World::set_prescribed); the particle checked before
                 // the motion is added, so that a refused call leaves the world as it was
                 w.require_particle("set_particle_motion", i);
                 w.set_prescribed(i, w.add_motion(make_motion(velocity, history, w.time, {})));
             },
             py::arg("i"), py::arg("velocity") = std::vector<double>{}, py::arg("history") = std::vector<std::vector<double>>{})
        .def_property("dt", [](const dem::World& w) { return w.params.dt; }, [](dem::World& w, double v) { w.params.dt = v; },
                      "[s] time step (e.g. 0.2 * critical_dt())")
        .def_property("gravity", [](const dem::World& w) { return std::vector<double>{w.params.gravity.x, w.params.gravity.y, w.params.gravity.z}; },
                      [](dem::World& w, const std::vector<double>& g) { w.params.gravity = to_vec3(g, "gravity"); },
                      "[m/s^2] (0, 0, -9.81) by default")
        .def_property("local_damping", [](const dem::World& w) { return w.params.local_damping; },
                      [](dem::World& w, double v) { w.params.local_damping = v; }, "[-] Yade's non-viscous damping")
        .def_property("threads", [](const dem::World& w) { return w.params.threads; },
                      [](dem::World& w, int v) { w.params.threads = v; })
        .def_property("skin", [](const dem::World& w) { return w.params.skin; }, [](dem::World& w, double v) {
                // The candidate lists were built for the old skin: a new one takes effect with a
                // rebuild at the next step (a checkpoint in between resumes the same way).
                w.params.skin = v;
                w.invalidate_candidates();
            },
                      "[m] Verlet distance; 0: half the smallest radius")
        .def_property("track_energy", [](const dem::World& w) { return w.params.track_energy; },
                      [](dem::World& w, bool v) { w.params.track_energy = v; })
        .def_property_readonly("time", [](const dem::World& w) { return w.time; })
        .def_property_readonly("steps", [](const dem::World& w) { return w.steps; })
        .def("critical_dt", &dem::World::critical_dt)
        .def(
            "step",
            [](dem::World& w, uint64_t n, py::object progress) {
                if (w.particles.size() == 0) throw std::invalid_argument("step: the world has no particles");
                const Hook hook = python_hook(progress);
                py::gil_scoped_release release;
                for (uint64_t s = 1; s <= n; ++s) {
                    w.step();
                    if (!(s & 255u) || s == n) hook("step", s, n, w.time);
                }
            },
            py::arg("n") = 1, py::arg("progress") = py::none(),
            "Advances n steps without the interpreter lock; progress(stage, done, total, time [s]) every 256 "
            "steps; Ctrl-C raises KeyboardInterrupt")
        .def("__len__", [](const dem::World& w) { return w.particles.size(); })
        .def_property_readonly("positions", [](const dem::World& w) { return vec3_array(w.particles.pos); })
        .def_property_readonly("velocities", [](const dem::World& w) {
            // v(t) = v(t - dt/2) + dt/2 a(t): at the same time as the positions (after a step)
            std::vector<dem::Vec3> v(w.particles.size());
            for (std::size_t i = 0; i < v.size(); ++i) v[i] = w.velocity_at_time(i);
            return vec3_array(v);
        })
        .def_property_readonly("half_step_velocities", [](const dem::World& w) { return vec3_array(w.particles.vel); })
        .def_property_readonly("angular_velocities", [](const dem::World& w) { return vec3_array(w.particles.angvel); })
        .def_property_readonly("forces", [](const dem::World& w) { return vec3_array(w.particles.force); })
        .def_property_readonly("radii", [](const dem::World& w) { return double_array(w.particles.radius); })
        .def_property_readonly("masses", [](const dem::World& w) { return double_array(w.particles.mass); })
        .def("wall_force", [](const dem::World& w, std::size_t k) {
                 if (k >= w.wall_count()) throw std::out_of_range("wall_force: no wall " + std::to_string(k));
                 const dem::Vec3 f = w.wall_force(k);
                 return std::vector<double>{f.x, f.y, f.z};
             }, py::arg("wall"), "[N] particles on wall k (planes first, then facets) at the last step")
        .def_property_readonly("plane_count", [](const dem::World& w) { return w.planes.size(); })
        .def_property_readonly("facet_count", [](const dem::World& w) { return w.facets.size(); })
        .def_property_readonly("bond_count", [](const dem::World& w) { return w.bonds().size(); })
        .def("contact_count", &dem::World::contact_count)
        .def("save", [](const dem::World& w, const py::object& path) { dem::save_checkpoint(fspath(path), w, ""); }, py::arg("path"))
        .def_static("load", [](const py::object& path) {
                auto w = std::make_unique<dem::World>();
                dem::load_checkpoint(fspath(path), *w);
                return w;
            }, py::arg("path"));

    // --- devices from meshes (docs/devices.md) --------------------------------------------------------
    // `vppdem device FILE --out DIR`: runs (or resumes) the device; returns its result as a dict
    // (summary.json's numbers). The GIL is released while it steps.
    m.def(
        "device",
        [](const std::string& file, const std::string& out, const std::vector<std::string>& sets, const std::string& from,
           bool overwrite, bool quiet, double checkpoint_every) {
            const vpp::DeviceDef d = vpp::load_device(file, sets);
            vpp::DeviceOptions o;
            o.out_dir = out;
            o.from = from;
            o.overwrite = overwrite;
            o.quiet = quiet;
            o.checkpoint_every = checkpoint_every;
            vpp::DeviceResult r;
            {
                py::gil_scoped_release release;
                r = vpp::run_device(d, o);
            }
            py::dict res;
            res["stage"] = r.stage;
            res["grains"] = r.grains;
            res["membrane_particles"] = r.membrane_particles;
            res["bonds"] = r.bonds;
            res["samples"] = r.samples;
            res["dt"] = r.dt;
            res["holding_force"] = r.holding_force;
            res["holding_time"] = r.holding_time;
            res["press_force"] = r.press_force;
            res["volume_seal"] = r.volume_seal;
            res["volume_press"] = r.volume_press;
            res["volume_vacuum"] = r.volume_vacuum;
            res["volume_change"] = r.volume_change;
            res["volume_change_vacuum"] = r.volume_change_vacuum;
            res["energy_residual"] = r.energy_residual;
            res["energy_scale"] = r.energy_scale;
            res["fill_settled"] = r.fill_settled;
            // The fill (the pour's counts: docs/devices.md "The pour"; the lattice: placed = grains).
            res["fill_mode"] = d.fill_mode;
            res["grains_placed"] = r.grains_placed;
            res["grains_spilled"] = r.grains_spilled;
            res["grains_removed_at_seal"] = r.grains_removed_at_seal;
            res["seal_max_overlap"] = r.seal_max_overlap;
            res["packing_seal"] = r.packing_seal;
            res["run_seconds"] = r.run_seconds;
            res["warnings"] = r.warnings;
            res["cycle_stiffness"] = r.cycle_stiffness;
            res["cycle_work"] = r.cycle_work;
            res["cycle_peak_force"] = r.cycle_peak_force;
            return res;
        },
        py::arg("file"), py::arg("out"), py::arg("sets") = std::vector<std::string>{}, py::arg("from_checkpoint") = "",
        py::arg("overwrite") = false, py::arg("quiet") = true, py::arg("checkpoint_every") = 60.0);

    // --- studies ------------------------------------------------------------------------------------
    m.def(
        "sweep",
        [](const std::string& study, const std::string& out, const std::vector<std::string>& sets, int seeds, int jobs,
           bool quiet, py::object progress, const std::string& backend, bool mix_builds, const std::string& publish,
           bool report_only) {
            if (vpp::is_device_study(study)) {
                // A device study (docs/devices.md, "Studies"): its runs one after the other.
                if (jobs > 1 || backend != "cpu" || !progress.is_none())
                    throw cfg::ConfigError("study '" + study + "' is a device study: it runs one case at a time on the "
                                           "CPU (no jobs above 1, backend other than \"cpu\", or progress)");
                const vpp::DeviceStudy ds = vpp::load_device_study(study, sets, seeds);
                vpp::DeviceSweepOptions o;
                o.out_dir = out;
                o.quiet = quiet;
                o.report_only = report_only;
                o.mix_builds = mix_builds;
                o.publish = publish;
                py::gil_scoped_release release;
                return vpp::run_device_study(ds, o).failed;
            }
            const vpp::Study st = vpp::load_study(study, sets, seeds);
            vpp::SweepOptions so;
            so.out_dir = out;
            so.jobs = jobs;
            so.quiet = quiet;
            so.report_only = report_only;  // vppdem sweep --report-only
            so.backend = backend;  // "cpu", "batch" or "cuda" (vppdem sweep --backend)
            so.mix_builds = mix_builds;  // vppdem sweep --mix-builds
            so.publish = publish;        // vppdem sweep --publish (empty: none)
            return run_stoppable(progress, [&](auto hook) {
                vpp::SweepOptions o = so;
                o.progress = hook;
                return vpp::run_sweep(st, o).failed;
            });
        },
        py::arg("study"), py::arg("out"), py::arg("sets") = std::vector<std::string>{}, py::arg("seeds") = 0,
        py::arg("jobs") = 0, py::arg("quiet") = true, py::arg("progress") = py::none(), py::arg("backend") = "cpu",
        py::arg("mix_builds") = false, py::arg("publish") = "", py::arg("report_only") = false);
    // `vppdem sweep --list`: the study's cases, checked, none run.
    m.def(
        "study_cases",
        [](const std::string& study, const std::vector<std::string>& sets, int seeds) {
            if (vpp::is_device_study(study)) {
                // A device study's runs: each its own "preparation" (a device run fills its own).
                const vpp::DeviceStudy ds = vpp::load_device_study(study, sets, seeds);
                py::list out;
                std::size_t i = 0;
                for (const vpp::DeviceStudyRun& r : vpp::expand_device_study(ds)) {
                    py::dict d;
                    d["index"] = ++i;
                    d["name"] = r.folder;
                    d["group"] = i;
                    d["prepares"] = true;
                    d["branches_from"] = py::none();
                    d["case"] = ds.cases[r.case_index].name;
                    d["seed"] = r.seed;
                    d["overrides"] = r.overrides;
                    out.append(d);
                }
                return out;
            }
            const std::vector<vpp::StudyCase> cases = vpp::expand_study(vpp::load_study(study, sets, seeds));
            py::list out;
            for (const vpp::StudyCase& c : cases) {
                py::dict d;
                d["index"] = c.index + 1;  // 1-based, as --list prints them
                d["name"] = c.name;
                d["group"] = c.group + 1;
                d["prepares"] = c.preparer == c.index;
                d["branches_from"] = c.preparer == c.index ? py::object(py::none()) : py::str(cases[c.preparer].name);
                out.append(d);
            }
            return out;
        },
        py::arg("study"), py::arg("sets") = std::vector<std::string>{}, py::arg("seeds") = 0);
    m.def(
        "calibrate",
        [](const std::string& study, const std::string& experiment, const std::string& out,
           const std::vector<std::string>& sets, int seeds, int jobs, bool quiet, double disp_scale, double force_scale,
           bool compression_negative, const std::string& simulated_force, int points, bool plot,
           const std::string& time_column, const std::string& displacement_column, const std::string& force_column,
           py::object progress, bool mix_builds) {
            vpp::Study st = vpp::load_study(study, sets, seeds);
            vpp::CalibrateOptions co;
            co.sweep.out_dir = out;
            co.sweep.jobs = jobs;
            co.sweep.quiet = quiet;
            co.sweep.mix_builds = mix_builds;  // vppdem calibrate --mix-builds
            co.experiment = experiment;
            co.format.disp_scale = disp_scale;
            co.format.force_scale = force_scale;
            co.format.compression_negative = compression_negative;
            co.format.time_col = time_column;
            co.format.disp_col = displacement_column;
            co.format.force_col = force_column;
            co.force_column = simulated_force;
            co.points = points;
            co.plot = plot;
            return run_stoppable(progress, [&](auto hook) {
                vpp::CalibrateOptions o = co;
                o.sweep.progress = hook;
                return vpp::run_calibration(st, o);
            });
        },
        py::arg("study"), py::arg("experiment"), py::arg("out"), py::arg("sets") = std::vector<std::string>{},
        py::arg("seeds") = 0, py::arg("jobs") = 0, py::arg("quiet") = true, py::arg("disp_scale") = 1.0,
        py::arg("force_scale") = 1.0, py::arg("compression_negative") = false,
        py::arg("simulated_force") = "force_zeroed", py::arg("points") = 50, py::arg("plot") = false,
        py::arg("time_column") = "time", py::arg("displacement_column") = "displacement", py::arg("force_column") = "force",
        py::arg("progress") = py::none(), py::arg("mix_builds") = false);
}
