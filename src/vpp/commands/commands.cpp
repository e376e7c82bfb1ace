// The commands' arguments turned into their runs' inputs and options (vpp/commands/commands.h).
#include "vpp/commands/commands.h"

#include "scene/config.h"

namespace vpp {

namespace {

// How the study's cases run, from the arguments both study commands share.
SweepOptions study_sweep_options(const StudyArgs& a) {
    SweepOptions o;
    o.out_dir = a.out;
    o.jobs = a.jobs;
    o.quiet = a.quiet;  // every rank reports its cases; rank 0 the totals
    o.checkpoint_every = a.checkpoint_every;
    o.progress_every = a.progress_every;
    o.rank = a.rank;
    o.ranks = a.ranks;
    o.backend = a.backend;
    o.mix_builds = a.mix_builds;
    o.publish = a.publish;
    return o;
}

// A device study runs its cases one after the other on this process, each a `vppdem device` run
// with the threads its device file sets, and reports no progress per case.
void require_one_case_at_a_time(const StudyArgs& a) {
    if (a.jobs > 1 || a.backend != "cpu" || a.ranks > 1 || a.watched)
        throw cfg::ConfigError("study '" + a.study + "' is a device study: it runs one case at a time on the CPU (no " +
                               (a.door == Door::CommandLine ? "--jobs above 1, --backend other than cpu, or MPI"
                                                            : "jobs above 1, backend other than \"cpu\", or progress") +
                               ")");
}

}  // namespace

DamperOptions damper_options(const DamperArgs& a) {
    DamperOptions o;
    o.out_dir = a.out;
    o.from = a.from;
    o.quiet = a.quiet;
    o.plot = a.plot;
    o.overwrite = a.overwrite;
    o.checkpoint_every = a.checkpoint_every;
    o.progress_every = a.progress_every;
    o.profile = a.profile;
    return o;
}

DeviceCommand device_command(const DeviceArgs& a) {
    DeviceCommand c{load_device(a.file, a.sets), {}};
    c.options.out_dir = a.out;
    c.options.from = a.from;
    c.options.quiet = a.quiet;
    c.options.overwrite = a.overwrite;
    c.options.checkpoint_every = a.checkpoint_every;
    return c;
}

SweepCommand sweep_command(const SweepArgs& a) {
    SweepCommand c;
    if (is_device_study(a.study)) {
        // A device study (docs/devices.md, "Studies").
        require_one_case_at_a_time(a);
        c.device_study = load_device_study(a.study, a.sets, a.seeds);
        c.device_options.out_dir = a.out;
        c.device_options.publish = a.publish;
        c.device_options.quiet = a.quiet;
        c.device_options.report_only = a.report_only;
        c.device_options.mix_builds = a.mix_builds;
        c.device_options.checkpoint_every = a.checkpoint_every;
        return c;
    }
    c.study = load_study(a.study, a.sets, a.seeds);
    c.options = study_sweep_options(a);
    c.options.report_only = a.report_only;
    return c;
}

CalibrateCommand calibrate_command(const CalibrateArgs& a) {
    if (is_device_study(a.study))
        throw cfg::ConfigError("study '" + a.study + "' is a device study (key 'device'): calibrate takes a damper study");
    CalibrateCommand c{load_study(a.study, a.sets, a.seeds), {}};
    c.options.sweep = study_sweep_options(a);
    c.options.experiment = a.experiment;
    c.options.format = a.format;
    c.options.force_column = a.force_column;
    c.options.points = a.points;
    c.options.plot = a.plot && a.rank == 0;
    c.options.predict = a.predict;
    c.options.predict_experiments = a.predict_experiments;
    return c;
}

double displacement_unit_scale(const std::string& unit) {
    if (unit == "m") return 1.0;
    if (unit == "mm") return 1e-3;
    throw cfg::ConfigError("displacement unit '" + unit + "': m or mm");
}

double force_unit_scale(const std::string& unit) {
    if (unit == "N") return 1.0;
    if (unit == "kN") return 1e3;
    throw cfg::ConfigError("force unit '" + unit + "': N or kN");
}

}  // namespace vpp
