// vppdem._core.Damper: the VPP damper's stages one call at a time (vpp::Damper), guarded against
// a second thread's call while a stage runs without the interpreter lock (PyDamper).
#include "bindings.h"

#include <algorithm>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "vpp/analysis/records.h"
#include "vpp/commands/commands.h"
#include "vpp/damper/damper.h"

namespace bindings {

namespace {

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

using DamperClass = py::class_<PyDamper>;

// Made from a config; prepare, vacuum and cycle without the interpreter lock; save.
void def_stages(DamperClass& cls) {
    cls
        .def(py::init([](const vpp::Config& c, const std::string& out, const std::string& from, bool overwrite,
                         bool quiet) {
                 vpp::DamperArgs a;
                 a.out = out;
                 a.from = from;
                 a.overwrite = overwrite;
                 a.quiet = quiet;
                 a.plot = false;
                 const vpp::DamperOptions o = vpp::damper_options(a);
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
             }, py::arg("path"));
}

// Where the run stands.
void def_progress(DamperClass& cls) {
    cls
        .def("stage", [](const PyDamper& p) { return p.read("stage").stage(); })
        .def("cycles_done", [](const PyDamper& p) { return p.read("cycles_done").cycles_done(); })
        .def("cycles_total", [](const PyDamper& p) { return p.read("cycles_total").cycles_total(); })
        .def("busy", [](const PyDamper& p) { return p.running ? py::object(py::str(p.running)) : py::object(py::none()); },
             "The stage call running now (\"prepare\", \"vacuum\", \"cycle\"), or None");
}

// The records (as arrays, and written to a folder) and the summary.
void def_records(DamperClass& cls) {
    cls
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
                 // summary.json's, NaN where a cycle lacks the column's group (no energy ledger); the
                 // events' columns only where the run split its cycles (analysis.event_threshold).
                 const vpp::DamperResult r = p.read("cycles").result();
                 const double nan = std::numeric_limits<double>::quiet_NaN();
                 const bool events = std::any_of(r.cycles.begin(), r.cycles.end(),
                                                 [](const vpp::CycleResult& c) { return c.has_events; });
                 py::dict out;
                 for (const vpp::CycleColumn& col : vpp::cycle_columns()) {
                     if (col.group == vpp::CycleGroup::Events && !events) continue;
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
                 vpp::DamperArgs a;
                 a.out = out;
                 a.from = from;
                 const vpp::DamperOptions o = vpp::damper_options(a);
                 py::gil_scoped_release release;
                 vpp::write_damper_outputs(d, o);
             }, py::arg("out"), py::arg("from_checkpoint") = "");
}

// The config and the world's state.
void def_state(DamperClass& cls) {
    cls
        .def("config", [](const PyDamper& p) { return p.read("config").config(); })
        .def("positions", [](const PyDamper& p) { return vec3_array(p.read("positions").world().particles.pos); })
        .def("radii", [](const PyDamper& p) { return double_array(p.read("radii").world().particles.radius); })
        .def("time", [](const PyDamper& p) { return p.read("time").world().time; });
}

}  // namespace

// Every method goes through PyDamper's guards (see there): while a stage runs without the
// interpreter lock, another thread's call on the same object is refused, not a data race.
void bind_damper(py::module_& m) {
    DamperClass cls(m, "Damper");
    def_stages(cls);
    def_progress(cls);
    def_records(cls);
    def_state(cls);
}

}  // namespace bindings
