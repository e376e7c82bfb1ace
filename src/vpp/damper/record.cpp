// The damper run's record: the result (the cycles analysed, the warnings over the whole record),
// summary.json's text, the report on the terminal; run_damper(). The files of a run's folder are
// written by its recorder (damper/recorder.cpp): here what goes into them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "scene/scene_runner.h"
#include "dem/detect/cell_grid.h"
#include "dem/io/csv.h"
#include "dem/io/json.h"
#include "vpp/damper/run.h"
#include "vpp/analysis/events.h"
#include "vpp/analysis/records.h"
#include "vpp/analysis/plot.h"

#include "vpp/settings/settings.h"

namespace vpp {

namespace fs = std::filesystem;

namespace damper_detail {

namespace {

// Energy per cycle: ledger differences between the first samples of consecutive cycles (`rows`,
// one per sample, S a cycle); the last cycle ends at `last`, the last step of cycling (one step
// before the cycle's end).
void add_cycle_energies(std::vector<CycleResult>& cycles, const std::vector<EnergyRow>& rows, const EnergyRow& last,
                        int S) {
    for (CycleResult& cr : cycles) {
        const std::size_t a = std::size_t(cr.cycle - 1) * std::size_t(S), b = a + std::size_t(S);
        if (a >= rows.size()) continue;
        const EnergyRow& e0 = rows[a];
        const EnergyRow& e1 = b < rows.size() ? rows[b] : last;
        auto d = [&](std::string_view column) {
            const std::size_t k = dem::energy_column(column);
            return e1.v[k] - e0.v[k];
        };
        cr.has_energy = true;
        cr.boundary_work = d("boundary_work");
        cr.friction_dissipation = d("friction_dissipation");
        cr.damping_dissipation = d("damping_dissipation");
        cr.viscous_dissipation = d("viscous_dissipation");
        cr.energy_residual = d("residual");
    }
}

// Each cycle's dissipation split into rearrangement events and the creep between them (the
// detector: vpp/analysis/events.h) from the ledger's rows, a row per sample; the cycle's last
// interval ends at the next cycle's first row (or the run's last state, `last`).
void add_cycle_events(std::vector<CycleResult>& cycles, const std::vector<EnergyRow>& rows, const EnergyRow& last,
                      int S, double threshold) {
    const std::size_t ke = dem::energy_column("kinetic"), fr = dem::energy_column("friction_dissipation"),
                      da = dem::energy_column("damping_dissipation"), vi = dem::energy_column("viscous_dissipation");
    for (CycleResult& cr : cycles) {
        const std::size_t a = std::size_t(cr.cycle - 1) * std::size_t(S), b = a + std::size_t(S);
        if (a >= rows.size()) continue;
        EventSeries s;
        for (std::size_t k = a; k <= b; ++k) {
            const EnergyRow& e = k < rows.size() ? rows[k] : last;
            s.kinetic.push_back(e.v[ke]);
            s.friction.push_back(e.v[fr]);
            s.damping.push_back(e.v[da]);
            s.viscous.push_back(e.v[vi]);
            if (k >= rows.size()) break;
        }
        const EventSplit split = split_events(s, threshold);
        cr.has_events = true;
        cr.events = split.events;
        cr.event_fraction = split.event_fraction;
        cr.friction_in_events = split.friction;
        cr.damping_in_events = split.damping;
        cr.viscous_in_events = split.viscous;
    }
}

// The machine's loop: forces.csv's force_machine_zeroed (the grains' and foil's force `ls`, the
// lid's -dp A added, zeroed at the first sample) through the same analysis, and the air's range
// over each cycle (`air`, one row per sample).
std::vector<AirCycle> air_by_cycle(LoopSeries ls, const std::vector<AirSample>& air, double radius) {
    std::vector<AirCycle> out;
    const double m0 = ls.force[0] - air[0].dp * air[0].lid_area;
    for (std::size_t k = 0; k < ls.force.size(); ++k) ls.force[k] += -air[k].dp * air[k].lid_area - m0;
    for (const CycleResult& m : analyze_cycles(ls, radius)) {
        AirCycle a;
        a.cycle = m.cycle;
        a.W_machine = m.W;
        a.peak_force_machine = m.peak_force;
        a.min_force_machine = m.min_force;
        a.underpressure_min = a.gas_volume_min = std::numeric_limits<double>::infinity();
        a.underpressure_max = a.gas_volume_max = -std::numeric_limits<double>::infinity();
        double dp_sum = 0;
        std::size_t dp_n = 0;
        for (std::size_t k = 0; k < ls.cycle.size(); ++k) {
            if (ls.cycle[k] != m.cycle) continue;
            dp_sum += air[k].dp;
            ++dp_n;
            a.underpressure_min = std::min(a.underpressure_min, air[k].dp);
            a.underpressure_max = std::max(a.underpressure_max, air[k].dp);
            a.gas_volume_min = std::min(a.gas_volume_min, air[k].gas);
            a.gas_volume_max = std::max(a.gas_volume_max, air[k].gas);
        }
        a.underpressure_mean = dp_n ? dp_sum / double(dp_n) : 0.0;
        out.push_back(a);
    }
    return out;
}

// The pump model's warnings: a cycle whose mean dp fell short of the set value, and one whose dp
// fell below half of it (each the first such cycle).
void add_pump_warnings(DamperResult& r, const Config& config) {
    // The pump model's dp follows the gas: a leak that outruns the pump lets it fall below the set
    // value, and W is then that of a lower underpressure (W grows with dp: a leak of 1e-3 m^3/s
    // held 35.8 of 60 kPa and gave W 313 against 419 J/m^2). Warned from 5% below, a cycle's mean.
    for (const AirCycle& a : r.air)
        if (a.underpressure_mean < (1.0 - kUnderpressureShortfall) * config.process.underpressure) {
            char msg[400];
            std::snprintf(msg, sizeof msg,
                          "pump model: the mean dp of cycle %d was %.4g Pa, %.1f%% below the set "
                          "process.underpressure %.4g Pa (the run held %.4g Pa over its cycles): the leak "
                          "(process.leak_rate %.3g m^3/s) or the stroke outruns the pump (process.pump_speed "
                          "%.3g m^3/s); W is that of the lower dp",
                          a.cycle, a.underpressure_mean,
                          100.0 * (1.0 - a.underpressure_mean / config.process.underpressure),
                          config.process.underpressure, r.underpressure_held, config.process.leak_rate,
                          config.process.pump_speed);
            r.warnings.push_back(msg);
            break;
        }
    for (const AirCycle& a : r.air)
        if (a.underpressure_min < 0.5 * config.process.underpressure) {
            char msg[400];
            std::snprintf(msg, sizeof msg,
                          "pump model: dp fell to %.4g Pa in cycle %d, below half the set process.underpressure "
                          "%.4g Pa: the leak (process.leak_rate %.3g m^3/s) or the stroke outruns the pump "
                          "(process.pump_speed %.3g m^3/s); this is not a run at the set underpressure",
                          a.underpressure_min, a.cycle, config.process.underpressure, config.process.leak_rate,
                          config.process.pump_speed);
            r.warnings.push_back(msg);
            break;
        }
}

}  // namespace

DamperResult DamperRun::result() const {
    const dem::World& world = scene_.world;
    const Config& config = scene_.config;
    DamperResult r;
    r.grains = scene_.grain_count_now();
    r.foil_particles = scene_.lattice.particles.size();
    r.bonds = world.bonds().size();
    r.foil_columns = scene_.lattice.cols;
    r.foil_rows = scene_.lattice.rows;
    r.foil_radius = scene_.lattice.radius;
    r.foil_column_pitch = scene_.lattice.column_pitch;
    for (const LatticeBond& b : scene_.lattice.bonds)
        (b.along_row ? r.foil_bond_kn_hoop : r.foil_bond_kn_axial) = world.bonds().phys[b.index].kn;
    if (scene_.mesh_foil()) {
        r.foil_vacancies = scene_.membrane.vacancies;
        double sum = 0;
        for (uint32_t b : scene_.membrane.bonds) sum += world.bonds().phys[b].kn;
        r.foil_bond_kn_mean = scene_.membrane.bonds.empty() ? 0.0 : sum / double(scene_.membrane.bonds.size());
    }
    r.height = scene_.z_top;
    r.dt = world.params.dt;
    r.inertial_number = inertial_number(config, scene_.z_top);
    LoopSeries ls;
    const int S = int(config.process.samples_per_cycle);
    // Only the cycles the run finished are analysed: a cycle stopped part way (Ctrl-C in Python,
    // a run.ckpt written mid-cycle and loaded) has a loop cut short, whose area is not the
    // cycle's W (77 J/m^2 for 25 of 80 samples where the full cycle gives 388). Its samples stay
    // in forces.csv (they are data); cycles.csv and summary.json leave it out and say so.
    const std::size_t complete = std::min(state_.samples.size(), std::size_t(cycles_done()) * std::size_t(S));
    std::string incomplete;
    if (complete < state_.samples.size())
        incomplete = "cycle " + std::to_string(cycles_done() + 1) + " incomplete: the run stopped part way (interrupted, or a "
                     "checkpoint written mid-cycle), after " + std::to_string(state_.samples.size() - complete) + " of its " +
                     std::to_string(S) + " samples; left out of W, cycles.csv and summary.json's cycles (forces.csv "
                     "holds its samples); cycle() continues it";
    for (std::size_t k = 0; k < complete; ++k) {
        ls.time.push_back(state_.samples[k].time);
        ls.displacement.push_back(state_.samples[k].displacement);
        ls.force.push_back(state_.samples[k].grains + state_.samples[k].foil);
        ls.cycle.push_back(int(k / S) + 1);
    }
    r.cycles = analyze_cycles(ls, config.damper.radius);
    if (!state_.energy.empty() && state_.energy.size() == state_.samples.size()) {
        const EnergyRow last = energy_row(world.energy(), world.energy().time - state_.cycle_t0);
        add_cycle_energies(r.cycles, state_.energy, last, S);
        if (config.analysis.event_threshold > 0.0)
            add_cycle_events(r.cycles, state_.energy, last, S, config.analysis.event_threshold);
    }
    r.settling = mark_settled(r.cycles, config.analysis.settle_tolerance);
    if (air_complete(state_) && !ls.force.empty()) r.air = air_by_cycle(std::move(ls), state_.air, config.damper.radius);
    r.report = state_.report;
    r.warnings = state_.warnings;
    if (!incomplete.empty()) r.warnings.push_back(incomplete);
    const std::size_t asked = std::size_t(config.process.cycles) * std::size_t(S);
    if (state_.stage == Stage::Done && state_.samples.size() < asked) {
        r.incomplete = true;
        r.warnings.push_back("incomplete: " + std::to_string(state_.samples.size() / std::size_t(S)) + " of process.cycles = " +
                             std::to_string(config.process.cycles) + " cycles recorded (" +
                             std::to_string(state_.samples.size()) + " of " + std::to_string(asked) +
                             " samples): the samples fell behind the time step; lower process.samples_per_cycle or "
                             "the frequency (process.frequency, process.velocity)");
    }
    // The dp the run had: the mean over every recorded cycle's samples (each cycle has as many).
    if (!r.air.empty()) {
        double sum = 0;
        for (const AirCycle& a : r.air) sum += a.underpressure_mean;
        r.underpressure_held = sum / double(r.air.size());
    }
    if (config.process.pressure_model == PressureModel::Pump) add_pump_warnings(r, config);
    r.run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    r.config = config;
    return r;
}

}  // namespace damper_detail

namespace {

// The warnings of summary.json that look at the whole record: not quasi-static, W not stationary.
void add_summary_warnings(DamperResult& r) {
    const double I = r.inertial_number;
    const bool quasi_static = I < kQuasiStaticInertialNumber;
    char msg[768];
    if (!quasi_static) {
        std::snprintf(msg, sizeof msg, "not quasi-static: inertial number %.2g >= %.2g: W is likely biased high "
                      "(8-45%% measured above it; docs/studies.md \"Velocity convergence\"); lower process.velocity", I,
                      kQuasiStaticInertialNumber);
        r.warnings.push_back(msg);
    }
    if (r.settling.count == 0 && !r.cycles.empty()) {
        std::string w;
        for (const CycleResult& c : r.cycles) {
            char b[32];
            std::snprintf(b, sizeof b, "%s%.4g", w.empty() ? "" : ", ", c.W);
            w += b;
        }
        char tail[96] = "no complete cycle";
        if (r.settling.tail_first > 0)
            std::snprintf(tail, sizeof tail, "cycles %d-%d", r.settling.tail_first, r.settling.tail_last);
        std::snprintf(msg, sizeof msg,
                      "W not stationary: fewer than %zu final cycles without a trend or jump beyond the per-cycle "
                      "scatter of %g%% (W per cycle: %s J/m^2; stationary tail: %s); run more cycles "
                      "(a larger process.cycles continues the run from its run.ckpt) or, if this damper scatters "
                      "more, raise analysis.settle_tolerance",
                      kSettleMinCycles, 100.0 * r.settling.tolerance, w.c_str(), tail);
        r.warnings.push_back(msg);
    }
}

}  // namespace

DamperResult Damper::result() const {
    DamperResult r = run_->result();
    add_summary_warnings(r);
    return r;
}

std::string damper_summary_json(const DamperResult& r, const std::string& from) {
    const Config& c = r.config;  // what the run used: a resumed run's settings are its checkpoint's
    const double I = r.inertial_number;
    const bool quasi_static = I < kQuasiStaticInertialNumber;
    const std::string cycles = cycles_json(r.cycles);
    dem::JsonObject inputs;
    std::vector<Setting> keys = summary_inputs();
    // Every key the run was given, too: a record must hold every value that was set (the
    // time-step study's simulation.dt_safety was in case.toml only). In the table's order after
    // the fixed ones; numbers as the table keeps them, a file key as its path.
    for (const Setting& k : settings())
        if (k.summary == 0 && c.given.count(k.key)) keys.push_back(k);
    for (const Setting& k : keys) {
        if (k.type == SettingType::Boolean) inputs.boolean(k.key, k.get(c) != 0.0);
        else if (std::string(k.key) == "grains.sieve_curve") inputs.str(k.key, c.grains.sieve_curve);
        else if (std::string(k.key) == "grains.clump_template") inputs.str(k.key, c.grains.clump_template);
        else inputs.num(k.key, k.get(c));
    }
    const std::string in = inputs.value();
    // The report's entries with this prefix, without it (absent ones are left out: a sample of
    // an older vppdem did not measure them).
    auto report_json = [&](const std::string& prefix) {
        dem::JsonObject o;
        for (const auto& [k, v] : r.report)
            if (k.starts_with(prefix) && k != "prepare.funnel_height") o.num(k.substr(prefix.size()), v);
        return o.value();
    };
    dem::JsonObject j;
    j.raw("inputs", in)
        .num("underpressure", c.process.underpressure)
        .num("grains", double(r.grains))
        .num("foil_particles", double(r.foil_particles))
        .num("foil_bonds", double(r.bonds))
        .num("foil_columns", r.foil_columns)
        .num("foil_rows", r.foil_rows)
        .num("foil_radius", r.foil_radius)
        .num("height", r.height)
        .num("particle_modulus", particle_modulus(c.foil))
        .num("bond_kn", c.damper.foil_builder == FoilBuilder::Mesh ? r.foil_bond_kn_mean : bond_normal_stiffness(c.foil))
        .num("dt", r.dt)
        .num("cycle_steps", cycle_period(c.process) / r.dt)
        .num("inertial_number", I)
        .boolean("quasi_static", quasi_static)
        .raw("cycles", cycles)
        .num("settle_tolerance", r.settling.tolerance)
        .raw("first_settled_cycle", r.settling.first > 0 ? std::to_string(r.settling.first) : "null")
        .num("settled_cycles", double(r.settling.count))
        .num("W_settled", r.settling.W_mean)
        .num("settle_slope", r.settling.slope)
        .num("settle_slope_limit", r.settling.slope_limit)
        .num("inner_radius", r.foil_radius - c.foil.particle_radius)
        .raw("preparation", report_json("prepare."))
        .raw("start_of_cycling", report_json("cycle."));
    // The mesh foil (docs/membrane.md): what it is made of; foil_columns and foil_rows are 0.
    if (c.damper.foil_builder == FoilBuilder::Mesh)
        j.str("foil_builder", "mesh").num("foil_vacancies", double(r.foil_vacancies));
    else
        // The lattice's row (hoop) and column (axial) bonds: both bond_kn on the paper's grid; at
        // the exact radius (foil.exact_radius) the bar rule with the column pitch (docs/foil.md).
        j.num("foil_column_pitch", r.foil_column_pitch).num("bond_kn_hoop", r.foil_bond_kn_hoop)
            .num("bond_kn_axial", r.foil_bond_kn_axial);
    if (!r.air.empty()) {
        std::string air_cycles = "[";
        for (std::size_t k = 0; k < r.air.size(); ++k) {
            const AirCycle& a = r.air[k];
            dem::JsonObject o;
            o.num("cycle", a.cycle).num("W_machine", a.W_machine).num("peak_force_machine", a.peak_force_machine)
                .num("min_force_machine", a.min_force_machine).num("underpressure_min", a.underpressure_min)
                .num("underpressure_max", a.underpressure_max).num("underpressure_mean", a.underpressure_mean)
                .num("gas_volume_min", a.gas_volume_min)
                .num("gas_volume_max", a.gas_volume_max);
            air_cycles += (k ? ", " : "") + o.value();
        }
        dem::JsonObject air;
        air.str("pressure_model", word_of(c.process.pressure_model))
            .num("underpressure_set", c.process.underpressure)
            .num("underpressure_held", r.underpressure_held)
            .raw("cycles", air_cycles + "]");
        j.raw("air", air.value());
    }
    j.raw("warnings", dem::json_string_array(r.warnings))
        .num("run_seconds", r.run_seconds)
        .str("from", from);
    return j.text();
}

DamperResult write_damper_outputs(const Damper& d, const DamperOptions& opt) {
    d.write_records(opt.out_dir);
    DamperResult r = d.result();
    damper_detail::DamperRecorder::write_cycles(opt.out_dir, r.cycles);
    damper_detail::DamperRecorder::write_summary(opt.out_dir, damper_summary_json(r, opt.from));
    return r;
}

DamperResult run_damper(const Config& config, const DamperOptions& opt) {
    Damper d(config, opt);
    try {
        d.prepare();
        d.vacuum();
        d.cycle();
    } catch (const dem::SimulationUnstable& e) {
        // Name the settings that size the step, and their values (a diverged run failed with
        // "cannot create std::vector larger than max_size()").
        const Config& c = d.config();
        char dt[32];
        std::snprintf(dt, sizeof dt, "%g", c.simulation.dt);
        char msg[512];
        std::snprintf(msg, sizeof msg,
                      "%s; stage '%s', time step %.4g s (simulation.dt = %s, simulation.dt_safety = %g); lower "
                      "simulation.dt_safety (default %g) or check the stiffnesses (grains.young, foil.young, "
                      "*.stiffness_ratio)",
                      e.what(), d.stage().c_str(), d.world().params.dt,
                      c.simulation.dt_auto ? "\"auto\"" : dt, c.simulation.dt_safety, Config().simulation.dt_safety);
        throw std::runtime_error(msg);
    }
    const DamperResult r = write_damper_outputs(d, opt);
    // Said whatever --quiet says: the caller then fails (exit 1, a failed case).
    if (r.incomplete)
        for (const std::string& w : r.warnings)
            if (w.starts_with("incomplete: ")) std::fprintf(stderr, "vppdem: error: %s\n", w.c_str());
    const Config& c = r.config;
    const double I = r.inertial_number;
    const bool quasi_static = I < kQuasiStaticInertialNumber;
    if (!opt.quiet) {
        std::fprintf(stderr, "\n=== vppdem damper: %s ===\n", opt.out_dir.c_str());
        if (c.damper.foil_builder == FoilBuilder::Mesh)
            std::fprintf(stderr, "grains %zu, mesh foil %zu particles (%zu vacancies, radius %.4g mm), height %.4g mm, dt %.3g s\n",
                         r.grains, r.foil_particles, r.foil_vacancies, 1e3 * r.foil_radius, 1e3 * r.height, r.dt);
        else
            std::fprintf(stderr, "grains %zu, foil %zu particles (%d x %d, radius %.4g mm), height %.4g mm, dt %.3g s\n",
                         r.grains, r.foil_particles, r.foil_columns, r.foil_rows, 1e3 * r.foil_radius, 1e3 * r.height, r.dt);
        // With the air recorded, the dp the run held beside the set one (a leaking pump's falls).
        char held[64] = "";
        if (!r.air.empty()) std::snprintf(held, sizeof held, " set, %.4g MPa held", r.underpressure_held * 1e-6);
        std::fprintf(stderr, "dp %.4g MPa%s, amplitude %.3g mm, velocity %.4g m/s, inertial number %.2g",
                     c.process.underpressure * 1e-6, held, c.process.amplitude * 1e3, c.process.velocity, I);
        if (quasi_static) std::fprintf(stderr, " (quasi-static)\n");
        else std::fprintf(stderr, "  WARNING: not quasi-static (I >= %.2g); lower process.velocity\n", kQuasiStaticInertialNumber);
        std::fprintf(stderr, "cycle  dissipated [J]   W [J/m^2]   peak [N]   min [N]\n");
        for (const auto& cr : r.cycles)
            std::fprintf(stderr, "%5d  %13.5g  %10.5g  %9.4g  %8.4g\n", cr.cycle, cr.dissipated_energy, cr.W,
                         cr.peak_force, cr.min_force);
        if (!r.cycles.empty() && r.cycles[0].has_energy) {
            std::fprintf(stderr, "cycle  boundary work [J]  friction [J]  damping [J]  viscous [J]  residual [%% of work]\n");
            for (const auto& cr : r.cycles)
                std::fprintf(stderr, "%5d  %16.5g  %12.5g  %11.5g  %11.5g  %10.3g\n", cr.cycle, cr.boundary_work,
                             cr.friction_dissipation, cr.damping_dissipation, cr.viscous_dissipation,
                             cr.boundary_work != 0 ? 100.0 * cr.energy_residual / std::abs(cr.boundary_work) : 0.0);
        }
        if (r.settling.count > 0)
            std::fprintf(stderr,
                         "W stationary over cycles %d-%d (slope %.3g J/m^2 per cycle, within +-%.3g for a scatter of "
                         "%g%%): W_settled = %.5g J/m^2\n",
                         r.settling.first, r.settling.first + int(r.settling.count) - 1, r.settling.slope,
                         r.settling.slope_limit, 100.0 * r.settling.tolerance, r.settling.W_mean);
        for (const std::string& w : r.warnings) std::fprintf(stderr, "WARNING: %s\n", w.c_str());
        // The files the folder holds now, not a fixed list: a run never claims a file it did not write.
        std::string listed;
        for (const char* f : {"forces.csv", "energy.csv", "air.csv", "cycles.csv", "summary.json", "prepared.ckpt",
                              "run.ckpt", "vtk"})
            if (std::filesystem::exists(std::filesystem::path(opt.out_dir) / f))
                listed += std::string(" ") + f + (std::string(f) == "vtk" ? "/" : "");
        std::fprintf(stderr, "run time %.1f s; outputs in %s:%s%s\n", r.run_seconds, opt.out_dir.c_str(),
                     listed.c_str(), opt.plot ? " (plots next: loops*.png)" : "");
    }
    if (opt.plot) plot_damper_dir(opt.out_dir, opt.quiet);
    return r;
}

}  // namespace vpp
