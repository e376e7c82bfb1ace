// The checks of the damper's input against its scene (damper/checks.h): the process against the
// built foil, the time step and the sampling against the world, the grains against the foil.
#include "vpp/damper/checks.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "scene/shared_keys.h"
#include "vpp/damper/stored_settings.h"
#include "vpp/settings/settings.h"

namespace vpp::damper_detail {

namespace {

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

// Of the keys that set the critical step sqrt(m/k), the one given farthest from its default (in
// decades, either way), as "key = value": the one a message about the step should name first.
std::string step_key(const Config& c) {
    const std::pair<const char*, double> parts[] = {{"grains.young", c.grains.young},     {"foil.young", c.foil.young},
                                                    {"foil.thickness", c.foil.thickness}, {"grains.density", c.grains.density},
                                                    {"foil.density", c.foil.density},     {"grains.radius", c.grains.radius}};
    std::string best = "grains.young = " + show_value("", c.grains.young);
    double most = -1.0;
    for (const auto& [key, value] : parts) {
        const Setting* s = find_setting(key);
        if (s == nullptr || !(s->def > 0.0) || !(value > 0.0)) continue;
        const double d = std::abs(std::log10(value / s->def));
        if (d > most) most = d, best = std::string(key) + " = " + show_value("", value);
    }
    return best;
}

}  // namespace

std::vector<std::string> check_process(const DamperScene& scene) {
    const Config& config = scene.config;
    std::vector<std::string> warnings;
    const ProcessDef& p = config.process;
    const double H = scene.z_top, A = p.amplitude, off = p.start_offset;
    // The stroke against the sample's height H. A poured packing (about 0.6) reaches the densest
    // packing of spheres (0.74) at a compression of 1 - 0.6 / 0.74 = 19% of its height: beyond
    // about 20% the grains themselves must deform, i.e. the contact model's overlaps carry the
    // stroke (warned). At half the height they would overlap by about their own size, and the
    // linear contact law means nothing (refused; start_offset 0.02 on a 30 mm damper gave W
    // -440, amplitude 0.035 gave W 9.7e6). Upwards the foil is stretched by the same fraction
    // of its height: beyond 50% a polymer foil tears (tension.strain is limited to 0.5 too).
    constexpr double kWarnStrain = 0.2, kMaxStrain = 0.5;  // [-] of the damper height
    const double down = off + (p.compression_first ? A : 0.0);  // [m] the cap's lowest point below its start
    const double up = -off + (p.compression_first ? 0.0 : A);   // [m] its highest above
    auto blame = [&](bool downward) {
        const bool stroke = downward ? p.compression_first : !p.compression_first;
        const double offset_part = downward ? off : -off;
        if (stroke && offset_part <= 0.0) return std::string("process.amplitude' = ") + show_value("", A);
        if (!stroke) return std::string("process.start_offset' = ") + show_value("", off);
        return std::string("process.start_offset' = ") + show_value("", off) + " with 'process.amplitude' = " + show_value("", A);
    };
    auto refuse = [&](bool downward, double d) {
        throw std::runtime_error(
            "config key '" + blame(downward) + ": the cap would move " + fmt("%.4g", 1e3 * d) + " mm " +
            (downward ? "down" : "up") + ", " + fmt("%.0f", 100.0 * d / H) + "% of the sample's height " +
            fmt("%.4g", 1e3 * H) + " mm (damper.height); allowed: less than " + fmt("%.0f", 100.0 * kMaxStrain) +
            "% of the height (" + fmt("%.4g", 1e3 * kMaxStrain * H) + " mm here): " +
            (downward ? "beyond, the grains would overlap by about their own size (a crushed sample, not a damper)"
                      : "beyond, the foil would be stretched past tearing"));
    };
    if (down >= kMaxStrain * H) refuse(true, down);
    if (up >= kMaxStrain * H) refuse(false, up);
    if (down > kWarnStrain * H)
        warnings.push_back("process: the cap moves " + fmt("%.4g", 1e3 * down) + " mm down, " +
                           fmt("%.0f", 100.0 * down / H) + "% of the sample's height: beyond about 20% a poured "
                           "packing is past the densest packing and the grains' overlaps carry the stroke; W measures "
                           "the contact model, not the damper (docs/config.md, \"Limits from the physics\")");
    if (up > kWarnStrain * H)
        warnings.push_back("process: the cap moves " + fmt("%.4g", 1e3 * up) + " mm up, " +
                           fmt("%.0f", 100.0 * up / H) + "% of the sample's height: the foil is stretched by about as "
                           "much (docs/config.md, \"Limits from the physics\")");
    // The contacts against the load. The underpressure dp (or, without it, the weight of the
    // column, rho g H) presses a grain over its cross-section (2 r)^2 into contacts of stiffness
    // about E r / 2 (linear law, harmonic mean of E r): an overlap of delta / r = 8 load / E. At
    // half the radius the grains sit in each other (a modulus of 5e-324 Pa gave NaN): refused. The
    // foil, a cylinder of radius R under dp, stretches by the hoop strain dp R / (E_f t_f); beyond
    // 50% a polymer foil tears (as tension.strain and the stroke up).
    {
        constexpr double kMaxOverlap = 0.5;    // [grain radii]
        constexpr double kMaxHoopStrain = 0.5; // [-]
        constexpr double kGravity = 9.81;      // [m/s^2]
        const double weight = config.grains.density * kGravity * H;  // [Pa] at the column's foot
        const double load = std::max(p.underpressure, weight);    // [Pa]
        const double overlap = 8.0 * load / config.grains.young;
        const std::string by = weight > p.underpressure
                                   ? " with 'grains.density' = " + show_value("", config.grains.density) + ": under the column's "
                                     "weight rho g H = " + fmt("%.4g", weight) + " Pa"
                                   : ": under process.underpressure = " + show_value("", p.underpressure) + " Pa";
        if (!(overlap <= kMaxOverlap))
            throw std::runtime_error(
                "config key 'grains.young' = " + show_value("", config.grains.young) + by + " the grains would overlap by about " +
                fmt("%.3g", overlap) + " of their radius (8 load / E); allowed: at least " +
                fmt("%.4g", 8.0 * load / kMaxOverlap) + " Pa here (an overlap under half the radius)");
        const double strain = p.underpressure * scene.lattice.radius / (config.foil.young * config.foil.thickness);
        if (!(strain <= kMaxHoopStrain))
            throw std::runtime_error(
                "config key 'foil.young' = " + show_value("", config.foil.young) + " with 'foil.thickness' = " +
                show_value("", config.foil.thickness) + ": under process.underpressure = " + show_value("", p.underpressure) +
                " Pa the foil would stretch by " + fmt("%.3g", strain) + " (the hoop strain dp R / (E_f t_f), R = " +
                fmt("%.4g", scene.lattice.radius) + " m); allowed: E_f t_f at least " +
                fmt("%.4g", p.underpressure * scene.lattice.radius / kMaxHoopStrain) + " N/m here (a strain under 50%: beyond, "
                "a polymer foil tears)");
    }
    // Local damping above 0.5: an oscillation already loses most of its amplitude each half
    // period; more holds the grains back, and the loop's area is then largely the damping's.
    if (cycling_local_damping(config) > 0.5)
        warnings.push_back("local damping " + show_value("", cycling_local_damping(config)) + " from the vacuum on (" +
                           (config.process.local_damping >= 0.0 ? "process" : "simulation") + ".local_damping) is above 0.5: "
                           "it holds the grains back, and W is then largely the damping's (cycles.csv "
                           "damping_dissipation)");
    // A frequency sets the period and the start offset's speed (2 A f): the velocity is then
    // not used at all.
    if (p.frequency > 0.0 && config.given.count("process.velocity"))
        warnings.push_back("process.velocity = " + show_value("", p.velocity) + " m/s is not the cap's speed: process.frequency = " +
                           show_value("", p.frequency) + " Hz sets the period (peak speed " +
                           fmt("%.4g", peak_speed(p)) + " m/s) and the start offset's speed: the velocity is not used");
    // A pump-down runs until the pump has drawn the gas down: time constant V / S, the stage
    // waiting five of them. The gas volume is at most the foil's interior less the poured grains.
    if (p.pressure_model == PressureModel::Pump && p.pump_down && p.pump_speed > 0.0) {
        constexpr double kMaxPumpDown = 60.0;  // [s] of simulated time: a minute (2 m^3/h on the paper's damper: 0.7 s)
        const double r_in = scene.lattice.radius - config.foil.particle_radius;
        const double gas = std::numbers::pi * r_in * r_in * H * (1.0 - config.grains.volume_fraction);
        const double t = 5.0 * gas / p.pump_speed;
        if (t > kMaxPumpDown)
            throw std::runtime_error(
                "config key 'process.pump_speed' = " + show_value("", p.pump_speed) + ": the pump-down (process.pump_down) "
                "would take about " + fmt("%.3g", t) + " s (" + fmt("%.3g", t / 3600.0) + " h) of simulated time to "
                "draw the gas (about " + fmt("%.3g", gas * 1e3) + " L) down (5 V / S); allowed: at most " +
                fmt("%g", kMaxPumpDown) + " s, i.e. process.pump_speed >= " + fmt("%.3g", 5.0 * gas / kMaxPumpDown) +
                " m^3/s here, or process.pump_down = false");
    }
    return warnings;
}

void check_steps(const DamperScene& scene) {
    const Config& config = scene.config;
    const SimulationDef& sim = config.simulation;
    const ProcessDef& p = config.process;
    const double dt = scene.world.params.dt, critical = scene.world.critical_dt();
    // The automatic step comes from every contact's stiffness and every particle's mass; a
    // message names first the key farthest from its default (step_key).
    auto from_auto = [&] {
        return "simulation.dt_safety = " + show_value("", sim.dt_safety) + " times the critical step sqrt(m/k) of the "
               "contacts, here from " + step_key(config) + " (of grains.young, grains.density, grains.radius, "
               "foil.young, foil.thickness, foil.density, the stiffness ratios)";
    };
    const bool tiny = !(dt >= std::numeric_limits<double>::min());
    // A modulus of 1e300 or 5e-324 leaves a step of 0, a subnormal or infinity: nothing to integrate with.
    if (tiny || !std::isfinite(dt)) {
        const std::string key = sim.dt_auto ? step_key(config) : "simulation.dt = " + show_value("", sim.dt);
        throw std::runtime_error("config key '" + key.substr(0, key.find(' ')) + "' = " + key.substr(key.find('=') + 2) +
                                 ": the time step " + fmt("%.3g", dt) + " s (" +
                                 (sim.dt_auto ? from_auto() : key) + ") is not a positive finite number of "
                                 "seconds; allowed: moduli, densities and sizes of real materials");
    }
    const std::string source = sim.dt_auto ? from_auto() : "simulation.dt = " + show_value("", sim.dt);
    // A fixed step has the automatic one's bound: the largest simulation.dt_safety times one contact's
    // critical step (scene/shared_keys.h).
    constexpr double bound = cfg::keys::dt_safety.limits.hi;
    static_assert(bound == 0.5, "the message says \"half the critical step\"");
    if (!sim.dt_auto && std::isfinite(critical) && sim.dt > bound * critical)
        throw std::runtime_error("config key 'simulation.dt' = " + show_value("", sim.dt) + ": more than half the critical "
                                 "step sqrt(m/k) = " + fmt("%.4g", critical) + " s of the stiffest contact (the bound of "
                                 "simulation.dt_safety); allowed: at most " + fmt("%.4g", bound * critical) +
                                 " s here, or \"auto\"");
    // The neighbour lists' skin: a few tenths of a radius saves list rebuilds; ten radii already
    // lists hundreds of pairs per grain that never touch, and 1e300 m overflowed the cell grid.
    const double max_skin = 10.0 * scene.sizes.max_radius();
    if (!(sim.skin <= max_skin))
        throw std::runtime_error("config key 'simulation.skin' = " + show_value("", sim.skin) + ": allowed: at most ten "
                                 "times the largest grain radius (" + fmt("%.4g", max_skin) + " m here; 0: half the "
                                 "smallest radius)");
    // The steps the run needs from the vacuum on: the ramp, the hold and every cycle. 1e12 steps
    // are 33,000 of the paper's cycles (3e7 steps each), months on any machine: beyond, a value is
    // a slip (a velocity of 1e-300 m/s, a modulus of 1e300 Pa), not a run.
    constexpr double kMaxSteps = 1e12;
    const double T = cycle_period(p), cycling = double(p.cycles) * T;
    const double total = cycling + p.ramp_time + p.hold_time;  // [s] of simulated time
    if (!(total / dt <= kMaxSteps)) {
        // The count is a ratio: the message leads with the factor farther outside what a damper
        // run has (up to 1000 s of simulated time; a step of at least 1 ns).
        const bool blame_step = std::log10(1e-9 / dt) > std::log10(total / 1e3);
        std::string what;
        if (blame_step) {
            const std::string key = sim.dt_auto ? step_key(config) : "simulation.dt = " + show_value("", sim.dt);
            what = key;
        } else if (cycling >= p.ramp_time && cycling >= p.hold_time) {
            // One cycle longer than a whole run: the period's key; else the count of cycles.
            const std::string period = p.frequency > 0.0 ? "process.frequency = " + show_value("", p.frequency)
                                                         : "process.velocity = " + show_value("", p.velocity) +
                                                               " (period 2 process.amplitude / process.velocity)";
            what = T > 1e3 ? period + ", " + std::to_string(p.cycles) + " cycles of " + fmt("%.4g", T) + " s"
                           : "process.cycles = " + std::to_string(p.cycles) + " cycles of " + fmt("%.4g", T) + " s (" +
                                 period + ")";
        }
        else if (p.ramp_time >= p.hold_time)
            what = "process.ramp_time = " + show_value("", p.ramp_time);
        else
            what = "process.hold_time = " + show_value("", p.hold_time);
        throw std::runtime_error("config key '" + what.substr(0, what.find(' ')) + "' (" + what + "): the run would take " +
                                 fmt("%.3g", total / dt) + " steps, " + fmt("%.4g", total) + " s of simulated time (the "
                                 "cycles, process.ramp_time and process.hold_time) over a time step of " +
                                 fmt("%.3g", dt) + " s (" + source + "); allowed: at most " + fmt("%.0e", kMaxSteps) +
                                 " steps (months on any machine)");
    }
}

std::vector<std::string> check_sampling(const DamperScene& scene, bool refuse) {
    const Config& config = scene.config;
    std::vector<std::string> warnings;
    const ProcessDef& p = config.process;
    const double T = cycle_period(p), dt = scene.world.params.dt;
    if (!(dt > 0.0)) return warnings;
    const double spacing = T / double(p.samples_per_cycle);  // [s] between two samples
    // One sample per step at most: more samples per cycle than steps fall behind, and the run
    // ends with fewer cycles recorded than asked.
    // The period's own keys are named too: a velocity of 1e300 m/s is the slip, not the count.
    const std::string period = p.frequency > 0.0 ? "process.frequency = " + show_value("", p.frequency)
                                                 : "2 process.amplitude / process.velocity = 2 x " + show_value("", p.amplitude) +
                                                       " m / " + show_value("", p.velocity) + " m/s";
    if (spacing < dt && refuse)
        throw std::runtime_error("config key 'process.samples_per_cycle' = " + std::to_string(p.samples_per_cycle) +
                                 ": a sample every " + fmt("%.3g", spacing) + " s (the period " + fmt("%.4g", T) +
                                 " s, " + period + ", / samples_per_cycle) is less than the time step " + fmt("%.3g", dt) +
                                 " s; allowed: at most " + fmt("%.0f", std::floor(T / dt)) +
                                 " here (one sample per step), or a longer period");
    if (spacing < dt)
        warnings.push_back("process.samples_per_cycle = " + std::to_string(p.samples_per_cycle) + " asks for a sample every " +
                           fmt("%.3g", spacing) + " s, less than the time step " + fmt("%.3g", dt) +
                           " s: at most one sample is taken per step, so at most " +
                           fmt("%.0f", std::floor(T / dt)) + " per cycle are taken and the last cycles go unrecorded");
    // Each sample averages the forces since the previous one at most: a longer window is cut.
    if (p.sample_window > spacing)
        warnings.push_back("process.sample_window = " + show_value("", p.sample_window) + " s is longer than the samples' "
                           "spacing " + fmt("%.3g", spacing) + " s (period / process.samples_per_cycle): each force is "
                           "averaged over the spacing only");
    return warnings;
}

std::vector<std::string> check_grains_fit(const DamperScene& scene, std::size_t n) {
    const Config& config = scene.config;
    const double rk = scene.sizes.max_radius();
    const double r_in = scene.lattice.radius - config.foil.particle_radius;  // [m] inner surface of the foil
    if (rk > r_in / 3.0) {
        const std::string what = scene.sizes.kind == RadiusDistribution::Single
                                     ? "config key 'grains.radius' = " + show_value("", rk) + ": too large"
                                     : std::string("config key 'grains.radius_distribution' = \"") +
                                           word_of(config.grains.radius_distribution) + "\": its largest grain (radius " +
                                           show_value("", rk) + " m) is too large";
        throw std::runtime_error(what + " for the damper; at most a third of the foil's inner radius (" +
                                 show_value("", r_in / 3.0) + " m)");
    }
    // A clump reaches further than its volume-equivalent radius: one whose members span more
    // than half the foil's inner radius from its centre cannot turn inside the foil, and a
    // template reaching the foil's inner radius itself was accepted (issue 48) where a sphere of
    // a third of it is refused.
    if (scene.clumps() && scene.grain_reach(rk) > 0.5 * r_in) {
        const std::string what = config.grains.shape == GrainShape::Template
                                     ? "config key 'grains.clump_template' = '" + config.grains.clump_template + "'"
                                     : std::string("config key 'grains.shape' = \"") + word_of(config.grains.shape) + "\"";
        throw std::runtime_error(what + ": its grains reach " + show_value("", scene.grain_reach(rk)) + " m from their centre (at "
                                 "grains.radius " + show_value("", rk) + " m); at most half the foil's inner radius (" +
                                 show_value("", 0.5 * r_in) + " m), so that a grain can turn inside the foil");
    }
    // Fewest grains: one layer across the foil. A VPP damper is a packing that the vacuum
    // jams; grains that do not even cover the bottom once lie loose on the lower cap, the
    // cap never loads them and the "loop" is the foil's alone (0 grains gave a negative W).
    // A hexagonal layer of circles of radius r_k covers pi / (2 sqrt 3) = 0.907 of the area.
    const double v_grain = scene.sizes.mean_volume();
    const std::size_t n_layer = std::size_t(std::max(1.0, std::floor(0.9069 * (r_in / rk) * (r_in / rk))));
    if (n < n_layer) {
        const double phi_min = double(n_layer) * v_grain /
                               (std::numbers::pi * config.damper.radius * config.damper.radius * config.damper.height);
        throw std::runtime_error("config key 'grains.volume_fraction' = " + show_value("", config.grains.volume_fraction) +
                                 ": gives " + std::to_string(n) + " grain(s) in this damper; at least " +
                                 std::to_string(n_layer) + " are needed (one layer across the foil's inner radius " +
                                 show_value("", r_in) + " m), i.e. grains.volume_fraction >= " + show_value("", phi_min));
    }
    // Densest: the grains must fit into the foil once the cap is down. Poured grains settle at
    // random close packing (0.64) at most; more needs the foil to bulge out, which it does (it
    // is elastic), by a hoop strain of sqrt(phi_in / 0.64) - 1: unusual, warned. Above the
    // densest packing of spheres (0.74, a perfect crystal) the grains cannot be put into the
    // unstretched foil at all: refused.
    const double v_in = std::numbers::pi * r_in * r_in * scene.z_top;
    const double phi_in = double(n) * v_grain / v_in;
    if (phi_in > 0.74)
        throw std::runtime_error("config key 'grains.volume_fraction' = " + show_value("", config.grains.volume_fraction) +
                                 ": " + std::to_string(n) + " grains fill " + show_value("", std::round(1000 * phi_in) / 10) +
                                 "% of the foil's interior (radius " + show_value("", r_in) + " m, height " +
                                 show_value("", scene.z_top) + " m); at most 74% (the densest sphere packing) can be prepared");
    if (phi_in > 0.64) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "prepare: %zu grains fill %.1f%% of the foil's interior, above random close packing (64%%): the "
                      "foil bulges by about %.1f%% (hoop strain) when the cap compresses them",
                      n, 100.0 * phi_in, 100.0 * (std::sqrt(phi_in / 0.64) - 1.0));
        return {msg};
    }
    return {};
}

void check_preparation_damping(const Config& c) {
    // The preparation is frictionless and has no dashpot: local damping is its only dissipation.
    // Without it the pour never comes to rest and the step diverged ("cannot create std::vector
    // larger than max_size()"). From a prepared sample 0 is a dynamic run (docs/damper.md).
    if (c.simulation.local_damping == 0.0)
        throw std::runtime_error("config key 'simulation.local_damping' = 0: the preparation (frictionless, no "
                                 "dashpot) then dissipates nothing and the poured grains never come to rest; allowed "
                                 "here: in (0, 0.9] (default 0.2). For an undamped run give process.local_damping = 0: "
                                 "the preparation keeps simulation.local_damping, the vacuum and cycling have none");
}

}  // namespace vpp::damper_detail
