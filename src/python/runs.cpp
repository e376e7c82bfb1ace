// The runs of the commands from Python (vppdem/_runs.py wraps them): device, sweep, the study's
// cases (sweep --list) and calibrate, each turning its arguments into its options through the
// same function as the command line (vpp/commands/commands.h).
#include "bindings.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "vpp/commands/commands.h"

namespace bindings {

namespace {

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

// A device run's result as a dict: summary.json's numbers.
py::dict device_result(const vpp::DeviceResult& r, const vpp::DeviceDef& d) {
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
}

// `vppdem device FILE --out DIR`: runs (or resumes) the device; returns its result as a dict
// (summary.json's numbers). It steps without the GIL, stoppable with Ctrl-C (run_stoppable: the
// run stops at its next step with a checkpoint, and KeyboardInterrupt is raised).
void def_device(py::module_& m) {
    m.def(
        "device",
        [](const std::string& file, const std::string& out, const std::vector<std::string>& sets, const std::string& from,
           bool overwrite, bool quiet, double checkpoint_every) {
            vpp::DeviceArgs a;
            a.file = file;
            a.sets = sets;
            a.out = out;
            a.from = from;
            a.overwrite = overwrite;
            a.quiet = quiet;
            a.checkpoint_every = checkpoint_every;
            const vpp::DeviceCommand c = vpp::device_command(a);
            const vpp::DeviceResult r = run_stoppable(py::none(), [&](auto hook) {
                vpp::DeviceOptions o = c.options;
                o.stop = [hook] { return !hook(0, 0, std::string()); };  // a poll: no lock
                return vpp::run_device(c.device, o);
            });
            return device_result(r, c.device);
        },
        py::arg("file"), py::arg("out"), py::arg("sets") = std::vector<std::string>{}, py::arg("from_checkpoint") = "",
        py::arg("overwrite") = false, py::arg("quiet") = true,
        py::arg("checkpoint_every") = vpp::DeviceArgs{}.checkpoint_every);
}

// The arguments of a study's command (vpp::SweepArgs, vpp::CalibrateArgs) as Python passes them.
template <class Args> Args study_args(const std::string& study, const std::vector<std::string>& sets, int seeds) {
    Args a;
    a.door = vpp::Door::Python;
    a.study = study;
    a.sets = sets;
    a.seeds = seeds;
    return a;
}

// `vppdem sweep`: returns the failed cases' count; progress and Ctrl-C through run_stoppable (a
// device study's runs, one after the other, take no progress callback; Ctrl-C stops the running
// one with its checkpoint).
void def_sweep(py::module_& m) {
    m.def(
        "sweep",
        [](const std::string& study, const std::string& out, const std::vector<std::string>& sets, int seeds, int jobs,
           bool quiet, py::object progress, const std::string& backend, bool mix_builds, const std::string& publish,
           bool report_only) {
            auto a = study_args<vpp::SweepArgs>(study, sets, seeds);
            a.out = out;
            a.jobs = jobs;
            a.quiet = quiet;
            a.backend = backend;          // "cpu", "batch" or "cuda" (vppdem sweep --backend)
            a.mix_builds = mix_builds;    // vppdem sweep --mix-builds
            a.publish = publish;          // vppdem sweep --publish (empty: none)
            a.report_only = report_only;  // vppdem sweep --report-only
            a.watched = !progress.is_none();
            const vpp::SweepCommand c = vpp::sweep_command(a);
            if (c.device_study)
                return run_stoppable(py::none(), [&](auto hook) {
                    vpp::DeviceSweepOptions o = c.device_options;
                    o.stop = [hook] { return !hook(0, 0, std::string()); };  // a poll: no lock
                    return vpp::run_device_study(*c.device_study, o).failed;
                });
            return run_stoppable(progress, [&](auto hook) {
                vpp::SweepOptions o = c.options;
                o.progress = hook;
                return vpp::run_sweep(*c.study, o).failed;
            });
        },
        py::arg("study"), py::arg("out"), py::arg("sets") = std::vector<std::string>{}, py::arg("seeds") = 0,
        py::arg("jobs") = vpp::SweepArgs{}.jobs, py::arg("quiet") = true, py::arg("progress") = py::none(),
        py::arg("backend") = vpp::SweepArgs{}.backend, py::arg("mix_builds") = false, py::arg("publish") = "",
        py::arg("report_only") = false);
}

// A device study's runs as `sweep --list` shows them: each its own "preparation" (a device run
// fills its own).
py::list device_study_rows(const vpp::DeviceStudy& ds) {
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

// A damper study's cases as `sweep --list` shows them.
py::list damper_study_rows(const std::vector<vpp::StudyCase>& cases) {
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
}

// `vppdem sweep --list`: the study's cases, checked, none run.
void def_study_cases(py::module_& m) {
    m.def(
        "study_cases",
        [](const std::string& study, const std::vector<std::string>& sets, int seeds) {
            const vpp::SweepCommand c = vpp::sweep_command(study_args<vpp::SweepArgs>(study, sets, seeds));
            if (c.device_study) return device_study_rows(*c.device_study);
            return damper_study_rows(vpp::expand_study(*c.study));
        },
        py::arg("study"), py::arg("sets") = std::vector<std::string>{}, py::arg("seeds") = 0);
}

// `vppdem calibrate`: returns its exit status; progress and Ctrl-C as sweep's.
void def_calibrate(py::module_& m) {
    const vpp::CalibrateArgs defaults;
    m.def(
        "calibrate",
        [](const std::string& study, const std::string& experiment, const std::string& out,
           const std::vector<std::string>& sets, int seeds, int jobs, bool quiet, const std::string& displacement_unit,
           const std::string& force_unit, bool compression_negative, const std::string& simulated_force, int points,
           bool plot, const std::string& time_column, const std::string& displacement_column,
           const std::string& force_column, py::object progress, bool mix_builds) {
            auto a = study_args<vpp::CalibrateArgs>(study, sets, seeds);
            a.out = out;
            a.jobs = jobs;
            a.quiet = quiet;
            a.mix_builds = mix_builds;  // vppdem calibrate --mix-builds
            a.plot = plot;
            a.experiment = experiment;
            a.format.disp_scale = vpp::displacement_unit_scale(displacement_unit);
            a.format.force_scale = vpp::force_unit_scale(force_unit);
            a.format.compression_negative = compression_negative;
            a.format.time_col = time_column;
            a.format.disp_col = displacement_column;
            a.format.force_col = force_column;
            a.force_column = simulated_force;
            a.points = points;
            const vpp::CalibrateCommand c = vpp::calibrate_command(a);
            return run_stoppable(progress, [&](auto hook) {
                vpp::CalibrateOptions o = c.options;
                o.sweep.progress = hook;
                return vpp::run_calibration(c.study, o);
            });
        },
        py::arg("study"), py::arg("experiment"), py::arg("out"), py::arg("sets") = std::vector<std::string>{},
        py::arg("seeds") = 0, py::arg("jobs") = defaults.jobs, py::arg("quiet") = true, py::arg("displacement_unit") = "m",
        py::arg("force_unit") = "N", py::arg("compression_negative") = false,
        py::arg("simulated_force") = defaults.force_column, py::arg("points") = defaults.points, py::arg("plot") = false,
        py::arg("time_column") = defaults.format.time_col, py::arg("displacement_column") = defaults.format.disp_col,
        py::arg("force_column") = defaults.format.force_col, py::arg("progress") = py::none(),
        py::arg("mix_builds") = false);
}

}  // namespace

void bind_runs(py::module_& m) {
    def_device(m);
    def_sweep(m);
    def_study_cases(m);
    def_calibrate(m);
}

}  // namespace bindings
