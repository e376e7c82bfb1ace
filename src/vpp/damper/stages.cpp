// The protocol stages of the damper run (damper/stages.h): fill, compress (the preparation),
// vacuum, cycle, each a function of the scene and the run state, and their helpers: the re-fill,
// the air, the cycling's motion.
#include "vpp/damper/stages.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "dem/batch/batch_stepper.h"
#include "vpp/membrane/foil_tension.h"
#include "vpp/membrane/gas.h"

namespace vpp::damper_detail::stages {

namespace {

// The grains' kinetic energy [J]: the spheres g0 .. g1's translation, or every clump's translation
// and rotation (the damper's clumps are its grains; their members' inverse mass is 0).
double grains_kinetic_energy(const dem::World& w, uint32_t g0, uint32_t g1) {
    double e = 0;
    if (!w.clumps().empty()) {
        for (std::size_t k = 0; k < w.clumps().size(); ++k) e += w.clump_kinetic_energy(k);
        return e;
    }
    return dem::kinetic_energy(w.particles, g0, g1).translation;
}

// Yade's unbalanced force: mean net force on free particles over mean contact force.
double unbalanced_force(const dem::World& w) {
    const auto& p = w.particles;
    double net = 0;
    std::size_t nfree = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.inv_mass[i] == 0.0) continue;
        const dem::Vec3 fx = p.ext_force.empty() ? dem::Vec3{} : p.ext_force[i];
        net += norm(p.force[i] + fx + w.params.gravity * p.mass[i]);
        ++nfree;
    }
    // Clumps: the net force on the body (its members' sum).
    const dem::Clumps& cl = w.clumps();
    for (std::size_t k = 0; k < cl.size(); ++k) {
        dem::Vec3 f = w.params.gravity * cl.mass[k];
        for (uint32_t e = cl.start[k]; e < cl.start[k + 1]; ++e) {
            const uint32_t i = cl.member[e];
            f += p.force[i] + (p.ext_force.empty() ? dem::Vec3{} : p.ext_force[i]);
        }
        net += norm(f);
        ++nfree;
    }
    double fc = 0;
    std::size_t nc = 0;
    w.for_each_touching([&](const dem::TouchingContact& c) {
        if (c.wall) return;
        fc += norm(c.force);
        ++nc;
    });
    if (nc == 0 || nfree == 0) return 1.0;
    return (net / double(nfree)) / (fc / double(nc));
}

// Settling checks fall at fixed times after the stage start (every `check` seconds), so a
// resumed run takes its decisions at the same steps as an uninterrupted one.
double next_check_after(const RunState& state, double t, double check) {
    return state.stage_t0 + check * (std::floor((t - state.stage_t0) / check) + 1.0);
}

// The air (docs/damper.md, "The air inside") is recorded with the pump model, or output.air.
bool air_recorded(const Config& config) { return config.process.pressure_model == PressureModel::Pump || config.output.air; }

// The re-fills made so far (the run state's report, kept in the checkpoints).
int refills_done(const RunState& state) {
    const auto it = state.report.find("prepare.refills");
    return it == state.report.end() ? 0 : int(it->second);
}

// Re-fill (damper.refill): adds grains above the settled ones when their level is below the
// damper height (or their volume below damper.packing_target); returns false when the level is
// reached (or re-filling is off or exhausted).
bool refill(DamperScene& scene, RunState& state, StageServices& services) {
    dem::World& world = scene.world;
    const Config& config = scene.config;
    if (!config.damper.refill) return false;
    // The level the grains must reach before the cap comes down: the damper height plus a
    // quarter of a grain radius, so that the cap meets the top layer, not a few grains that
    // stand out of it (kRefillMargin, measured: docs/damper.md "Preparation").
    constexpr double kRefillMargin = 0.25;  // [grain radii]
    constexpr int kMaxRefills = 8;
    const double rk = config.grains.radius, r_in = scene.lattice.radius - config.foil.particle_radius;
    const double target = scene.z_top + kRefillMargin * rk, level = scene.fill_level();
    const double v_k = scene.sizes.mean_volume();
    const double area = std::numbers::pi * r_in * r_in;
    const int done = refills_done(state);
    char msg[256];
    // With damper.packing_target the grains' volume decides, not their level: the grains missing
    // to the target (to the nearest grain), however high they then stand; the cap compresses them.
    std::size_t add = 0;
    const double phi_now = config.damper.packing_target > 0.0 ? scene.packing_fraction(r_in, scene.z_top) : 0.0;  // [-] before this re-fill
    if (config.damper.packing_target > 0.0) {
        const double missing = std::round((config.damper.packing_target - phi_now) * area * scene.z_top / v_k);
        if (missing < 1.0) {
            if (done == 0 && missing < -0.5) {
                std::snprintf(msg, sizeof msg,
                              "prepare: the pour alone fills %.4f of the foil's interior, above damper.packing_target "
                              "= %.4g: lower grains.volume_fraction to reach the target",
                              phi_now, config.damper.packing_target);
                services.warn(state, msg);
            }
            return false;
        }
        add = std::size_t(missing);
    } else if (level >= target) {
        return false;
    }
    if (done >= kMaxRefills) {
        if (config.damper.packing_target > 0.0)
            std::snprintf(msg, sizeof msg,
                          "prepare: after %d re-fills the grains fill %.4f of the foil's interior, below "
                          "damper.packing_target = %.4g", done, phi_now,
                          config.damper.packing_target);
        else
            std::snprintf(msg, sizeof msg,
                          "prepare: after %d re-fills the grains reach %.4g m, below the damper height %.4g m: the "
                          "cap compresses less than the top layer", done, level, scene.z_top);
        services.warn(state, msg);
        return false;
    }
    // Without a target: as many grains as fill the gap at the packing fraction of the bed below
    // (the grains settle to about the same packing), one more so that every re-fill adds one.
    if (add == 0) {
        const double phi_bed = double(scene.grain_count_now()) * v_k / (area * level);
        add = std::size_t(std::ceil(phi_bed * area * (target - level) / v_k)) + 1;
    }
    // Written by the fill; a checkpoint of the fill stage without it (an older vppdem's, or an
    // edited one) cannot be re-filled: say so rather than fail with a bare map lookup.
    const auto funnel = state.report.find("prepare.funnel_height");
    if (funnel == state.report.end())
        throw std::runtime_error("checkpoint '" + services.options().from + "' holds a sample in the fill stage without its funnel "
                                 "height (prepare.funnel_height): it cannot be re-filled; prepare a new sample (run "
                                 "without --from)");
    double funnel_h = funnel->second;
    if (scene.sizes.sieve_radius.empty() && scene.sizes.kind == scene::SizeDistribution::Kind::Sieve)
        throw std::runtime_error("checkpoint '" + services.options().from + "' holds a sample drawn from a sieve curve in the fill stage: "
                                 "give grains.sieve_curve (the sample's curve) to re-fill it");
    if (scene.clumps() && scene.shape.members.empty())
        throw std::runtime_error("checkpoint '" + services.options().from + "' holds clumps of a template in the fill stage: give "
                                 "grains.clump_template (the sample's template) to re-fill it");
    const auto pos = scene.refill_sites(add, funnel_h, uint64_t(done + 1));
    if (pos.empty()) {
        services.warn(state, "prepare: no room in the funnel for a re-fill; the grains stay below the damper height");
        return false;
    }
    scene.add_grains(pos, scene.draw_radii(pos.size(), uint64_t(done + 1)), uint64_t(done + 1));
    state.grains = scene.grain_count_now();
    // A smaller grain than any before lowers the critical step (one radius: the same grains).
    if (scene.sizes.kind != scene::SizeDistribution::Kind::Single)
        world.params.dt = std::min(world.params.dt, resolve_dt(config.simulation, world));
    state.report["prepare.refills"] = done + 1;
    world.invalidate_candidates();
    if (config.damper.packing_target > 0.0)
        services.log("[prepare] grains fill %.4f of the foil's interior, below the target %.4g: re-fill %d adds %zu grains (%u "
            "in all)\n", phi_now,
            config.damper.packing_target, done + 1, pos.size(), scene.grain_count_now());
    else
        services.log("[prepare] grains level %.4f m, below %.4f m: re-fill %d adds %zu grains (%u in all)\n", level, target,
            done + 1, pos.size(), scene.grain_count_now());
    return true;
}

// The drawn radii's statistics into the preparation's report (size distributions only).
void report_grain_sizes(const DamperScene& scene, RunState& state) {
    if (scene.sizes.kind == scene::SizeDistribution::Kind::Single) return;  // every grain grains.radius
    const scene::SizeStats s = scene::size_stats(scene.grain_radii());
    auto& rep = state.report;
    rep["prepare.radius_mean"] = s.mean;
    rep["prepare.radius_sd"] = s.sd;
    rep["prepare.radius_min"] = s.min;
    rep["prepare.radius_max"] = s.max;
    rep["prepare.d10"] = s.d10;
    rep["prepare.d50"] = s.d50;
    rep["prepare.d90"] = s.d90;
}

// Before each step of the vacuum and the cycling: the gas volume from the foil's shape as it
// stands, the gas's work over the last step, and with the pump model the gas advanced by the
// step and the step's dp (the regulator set to the underpressure dp_set [Pa]).
void air_step(DamperScene& scene, RunState& state, double dp_set) {
    dem::World& world = scene.world;
    const Config& config = scene.config;
    const double v = scene.foil_volume() - scene.grain_volume();
    if (!(v > 0.0))
        throw std::runtime_error("air: the gas volume inside the foil is " + std::to_string(v) +
                                 " m^3 (the foil's enclosure minus the grains); the foil has collapsed onto them");
    const bool pump = config.process.pressure_model == PressureModel::Pump;
    if (pump && state.gas_amount == 0.0) state.gas_amount = kAtmosphericPressure * v;  // sealed at the atmosphere's
    // The gas's work over the step just taken, at the amount it held (isothermal: exact for a
    // fixed amount; the constant model's gas is at p_atm - dp).
    if (state.gas_volume > 0.0) {
        state.gas_work += pump ? isothermal_work(state.gas_amount, state.gas_volume, v)
                             : (kAtmosphericPressure - world.pressure.dp) * (v - state.gas_volume);
    }
    state.gas_volume = v;
    if (!pump) return;
    const double p_set = kAtmosphericPressure - dp_set;
    if (state.stage == Stage::Vacuum && !config.process.pump_down) {
        // Evacuated along the constant model's ramp: the gas is held at the set point.
        state.gas_amount = p_set * v;
    } else {
        PumpLine line;
        line.speed = config.process.pump_speed;
        line.bleed = config.process.bleed_rate;
        line.leak = config.process.leak_rate;
        line.p_set = p_set;
        line.p_atm = kAtmosphericPressure;
        state.gas_amount = advance_gas(state.gas_amount, v, world.params.dt, line);
    }
    // At the set point (the regulator closed there: advance_gas returns p_set v itself) dp is
    // the set dp, bit for bit: a pump that keeps up runs the constant model's steps exactly.
    world.pressure.dp = state.gas_amount == p_set * v ? dp_set : kAtmosphericPressure - state.gas_amount / v;
}

// The air at a sample: the state of the step it is taken at.
AirSample air_sample(const DamperScene& scene, const RunState& state) {
    const dem::World& world = scene.world;
    AirSample a;
    a.gas = state.gas_volume;
    a.enclosed = state.gas_volume + scene.grain_volume();
    a.dp = world.pressure.dp;
    a.p_inside = kAtmosphericPressure - world.pressure.dp;
    a.lid_area = scene.lid_area();
    a.gas_work = state.gas_work;
    return a;
}

// The sample as cycling starts (after the vacuum and the start offset): the cap's height and
// force, the packing fraction in the foil as the vacuum has drawn it in (its mean radius over the
// free rows; the end rings stay at the build radius), and the cap's travel on the grains since it
// first met them in the preparation. Then what confines the grains there: the cap's mean axial
// stress over the grains' cross-section pi r_in^2 (r_in = that mean radius - r_f, the packing
// fraction's), the lattice foil's mean hoop and axial tensions (membrane/foil_tension.h; the mesh
// foil has no rows to cut: not recorded), and the sample's size in grain diameters (2 r_k, the
// number mean with a size distribution) across r_in and along the cap's height.
void record_start_of_cycling(const DamperScene& scene, RunState& state, const Sample& first) {
    const dem::World& world = scene.world;
    const Config& config = scene.config;
    double sum = 0;
    std::size_t cnt = 0;
    for (uint32_t i : scene.free_foil) {
        sum += std::hypot(world.particles.pos[i].x, world.particles.pos[i].y);
        ++cnt;
    }
    const double r_foil = cnt ? sum / double(cnt) : scene.lattice.radius;
    const double cap_z = world.plane_point(kTopCap).z;
    auto& r = state.report;
    r["cycle.foil_mean_radius"] = r_foil;
    r["cycle.cap_height"] = cap_z;
    r["cycle.cap_force"] = first.grains;
    r["cycle.packing_fraction"] = scene.packing_fraction(r_foil - config.foil.particle_radius, cap_z);
    if (r.count("prepare.grain_top")) r["cycle.cap_travel"] = std::max(0.0, r.at("prepare.grain_top") - cap_z);
    const double r_in = r_foil - config.foil.particle_radius;  // [m]
    r["cycle.cap_stress"] = first.grains / (std::numbers::pi * r_in * r_in);
    if (!scene.mesh_foil()) {
        const FoilTension t = cylinder_tension(scene.lattice, world);
        r["cycle.foil_hoop_tension"] = t.hoop;
        r["cycle.foil_axial_tension"] = t.axial;
    }
    r["cycle.diameters_across_radius"] = r_in / (2.0 * config.grains.radius);
    r["cycle.diameters_along_height"] = cap_z / (2.0 * config.grains.radius);
}

// The cap's and the top ring's knots of cycles k0 .. k1 - 1 and the end of cycle k1, from the
// start positions cap0, ring0 [m] (the knot at the start of cycle k0 too when first_knot).
void lay_out_cycles(const Config& config, const RunState& state, dem::Motion& cap, dem::Motion& ring, double cap0,
                    double ring0, int k0, int k1, bool first_knot) {
    const double A = config.process.amplitude, T = cycle_period(config.process);
    const bool sine = config.process.waveform == Waveform::Sine;
    const double sign = config.process.compression_first ? -1.0 : 1.0;  // z direction of the first leg
    // The sine as kSineKnots straight segments per cycle: within A (pi / kSineKnots)^2 / 4 =
    // 2.5e-6 A of the curve, the speed within 1.6e-6 of its own.
    constexpr int kSineKnots = 1000;
    for (int k = k0; sine && k <= k1; ++k)
        for (int j = 0; j < (k < k1 ? kSineKnots : 1); ++j) {
            if (k == k0 && j == 0 && !first_knot) continue;  // the first knot is there
            const double d = sign * A * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * j / kSineKnots));
            const double t = state.cycle_t0 + (k + double(j) / kSineKnots) * T;
            cap.history.push_back({t, {0, 0, cap0 + d}});
            ring.history.push_back({t, {0, 0, ring0 + d}});
        }
    for (int k = k0; !sine && k <= k1; ++k) {
        if (k > k0 || first_knot) {
            cap.history.push_back({state.cycle_t0 + k * T, {0, 0, cap0}});
            ring.history.push_back({state.cycle_t0 + k * T, {0, 0, ring0}});
        }
        if (k < k1) {
            cap.history.push_back({state.cycle_t0 + (k + 0.5) * T, {0, 0, cap0 + sign * A}});
            ring.history.push_back({state.cycle_t0 + (k + 0.5) * T, {0, 0, ring0 + sign * A}});
        }
    }
}

}  // namespace

void next_stage(DamperScene& scene, RunState& state, StageServices& services, Stage s) {
    dem::World& world = scene.world;
    state.stage = s;
    state.stage_t0 = world.time;
    state.cap_d0 = world.planes[kTopCap].motion.displacement(world.time).z;
    services.checkpoint(scene, state, true);
    services.vtk_frame(scene, stage_name(s));
}

void fill(DamperScene& scene, RunState& state, StageServices& services) {
    dem::World& world = scene.world;
    const double max_time = 1.5;  // [s] of falling; a column of 20 cm settles in well under 1 s
    const double check = 2e-3;    // [s] between settling checks
    // Each re-fill is a stage of its own name on the progress line and hook: its steps count
    // from its start, the most it can take is max_time again.
    const auto round_name = [&] {
        const int k = refills_done(state);
        return k ? "prepare: re-fill " + std::to_string(k) : std::string("prepare: fill");
    };
    std::optional<StageProgress> prog;
    prog.emplace(round_name(), uint64_t(max_time / world.params.dt), services.options(), true);
    double next_check = next_check_after(state, world.time, check);
    for (;;) {
        world.step();
        prog->update(uint64_t((world.time - state.stage_t0) / world.params.dt), world.time);
        services.checkpoint(scene, state, false);
        if (world.time < next_check) continue;
        next_check = next_check_after(state, world.time, check);
        const double t = world.time - state.stage_t0;
        const double ke = grains_kinetic_energy(world, scene.first_grain, scene.end_grain);
        // The grains start at rest: a minimum time lets them fall first (a re-fill's grains
        // start just above the others and fall less far).
        const bool refilled = refills_done(state) > 0;
        bool settled = false;
        if (t > (refilled ? 0.1 : 0.15) && ke < 1e-4 * scene.settle_energy_scale()) {
            services.log("[prepare] grains settled after %.3f s (kinetic energy %.3g J)\n", t, ke);
            settled = true;
        } else if (t > max_time) {
            services.warn(state, "prepare: grains not fully settled after 1.5 s of filling");
            settled = true;
        }
        if (!settled) continue;
        if (!refill(scene, state, services)) break;
        // A re-fill starts the stage again: a checkpoint with the new grains, the settling clock.
        next_stage(scene, state, services, Stage::Fill);
        prog.emplace(round_name(), uint64_t(max_time / world.params.dt), services.options(), true);
        next_check = next_check_after(state, world.time, check);
    }
}

void compress(DamperScene& scene, RunState& state, StageServices& services) {
    dem::World& world = scene.world;
    const Config& config = scene.config;
    // Bring the cap just above the highest grain (nothing touches it on the way), then move it
    // down to the top ring at 0.1 m/s and let the grains rearrange; the re-filled grains stand
    // above the top ring, so the cap meets them and pushes them down to the damper height.
    const double top = scene.highest_grain_top(), level = scene.fill_level();
    const double z_cap0 = world.planes[kTopCap].point.z;
    const double z_start = std::max(scene.z_top, top + 1e-4);
    const double speed = 0.1, hold = 0.02, window = 0.005;  // [m/s], [s], [s] (cap force averaged over the window)
    const double t0 = world.time, t1 = t0 + (z_start - scene.z_top) / speed;
    dem::Motion m;
    m.history = {{t0 - 1e-12, {0, 0, z_start - z_cap0}}, {t1 + 1e-12, {0, 0, scene.z_top - z_cap0}}};
    world.planes[kTopCap].motion = m;
    world.invalidate_candidates();
    services.log("[prepare] cap from %.4f m down to %.4f m (grains top %.4f m, level of the top layer %.4f m)\n", z_start,
        scene.z_top, top, level);
    const uint64_t n = uint64_t((t1 + hold - world.time) / world.params.dt) + 1;
    StageProgress prog("prepare: compress", n, services.options());
    double f_max = 0, f_sum = 0;
    long f_n = 0;
    for (uint64_t s = 0; s < n; ++s) {
        world.step();
        prog.update(s + 1, world.time);
        const double f = world.wall_force(kTopCap).z;  // [N] grains on the cap, pushing it up
        f_max = std::max(f_max, f);
        if (world.time > t1 + hold - window) {
            f_sum += f;
            ++f_n;
        }
    }
    world.clear_facets();  // the funnel goes
    const double r_in = scene.lattice.radius - config.foil.particle_radius;
    const double cap_force = f_n ? f_sum / double(f_n) : 0.0;
    auto& r = state.report;
    r["prepare.grains"] = double(scene.grain_count_now());
    r["prepare.grain_top"] = top;
    r["prepare.fill_level"] = level;
    r["prepare.cap_travel"] = std::max(0.0, top - scene.z_top);
    r["prepare.cap_force"] = cap_force;
    r["prepare.cap_force_max"] = f_max;
    r["prepare.packing_fraction"] = scene.packing_fraction(r_in, scene.z_top);
    r["prepare.packing_fraction_nominal"] =
        scene.packing_fraction(config.damper.radius, config.damper.height);
    report_grain_sizes(scene, state);
    services.log("[prepare] cap travel %.3g mm on the grains, cap force %.4g N at the end (%.4g N at most), packing "
        "fraction %.4f of the foil's interior\n", 1e3 * r["prepare.cap_travel"], cap_force, f_max,
        r["prepare.packing_fraction"]);
    if (!(cap_force > 0)) {
        char msg[320];
        std::snprintf(msg, sizeof msg,
                      "prepare: the cap ends above the grains (no force on it at the damper height %.4g m; their "
                      "top layer is at %.4g m): the first part of every compression meets no grains%s",
                      scene.z_top, level, config.damper.refill ? "" : "; damper.refill = true fills the foil up to the cap");
        services.warn(state, msg);
    }
}

void vacuum(DamperScene& scene, RunState& state, StageServices& services) {
    dem::World& world = scene.world;
    const Config& config = scene.config;
    const double ramp = config.process.ramp_time, min_hold = 0.02, check = 2e-3;
    scene.set_foil_pressure();
    const double dp = config.process.underpressure;
    const bool pump = config.process.pressure_model == PressureModel::Pump;
    // The pump model follows the constant model's ramp (a sample evacuated long before its
    // test) unless process.pump_down asks the pump to draw the gas down from the atmosphere:
    // time constant V / S (at 2 m^3/h on the paper's damper, 0.08 L of gas: 0.14 s), and the
    // hold may then last five of those.
    const bool pump_down = pump && config.process.pump_down;
    double max_hold = 0.5;
    if (pump_down && config.process.pump_speed > 0.0) max_hold += 5.0 * (scene.foil_volume() - scene.grain_volume()) / config.process.pump_speed;
    StageProgress prog("vacuum", uint64_t((ramp + max_hold) / world.params.dt), services.options(), true);
    double next_check = next_check_after(state, world.time, check);
    const double ke_ref = scene.settle_energy_scale();
    for (;;) {
        const double t = world.time - state.stage_t0;
        const double dp_set = dp * std::min(1.0, t / ramp);
        if (!pump) world.pressure.dp = dp_set;
        if (air_recorded(config)) air_step(scene, state, pump_down ? dp : dp_set);
        if (pump_down && !state.report.count("cycle.pump_down_time") && world.pressure.dp == dp)
            state.report["cycle.pump_down_time"] = t;
        world.step();
        prog.update(uint64_t(t / world.params.dt), world.time);
        services.checkpoint(scene, state, false);
        if (world.time < next_check) continue;
        next_check = next_check_after(state, world.time, check);
        if (t < ramp + min_hold) continue;
        // Forces of the step just taken (computing them again would advance the shear springs).
        const double ke = grains_kinetic_energy(world, scene.first_grain, scene.end_grain);
        const double ub = unbalanced_force(world);
        // A pump-down also waits for the set underpressure.
        const bool drawn = !pump_down || world.pressure.dp == dp;
        if (ke < 1e-4 * ke_ref && ub < 0.05 && drawn) {
            services.log("[vacuum] at rest %.3f s after the ramp: kinetic energy %.3g J, unbalanced force %.3g\n",
                t - ramp, ke, ub);
            break;
        }
        if (t > ramp + max_hold) {
            char msg[320];
            if (!drawn)
                std::snprintf(msg, sizeof msg, "vacuum: the pump has not drawn the set underpressure %.4g Pa %.2f s after "
                              "the ramp (dp = %.4g Pa; process.pump_speed %.3g m^3/s against process.leak_rate %.3g "
                              "m^3/s): cycling starts at this dp", dp, t - ramp, world.pressure.dp, config.process.pump_speed,
                              config.process.leak_rate);
            else
                std::snprintf(msg, sizeof msg, "vacuum: sample not at rest %.2f s after the ramp (kinetic energy %.3g J, "
                              "unbalanced force %.3g)", t - ramp, ke, ub);
            services.warn(state, msg);
            break;
        }
    }
}

void extend_cycling(DamperScene& scene, RunState& state, StageServices& services, int from) {
    dem::World& world = scene.world;
    const Config& config = scene.config;
    const int ncyc = int(config.process.cycles);
    if (ncyc <= from || (state.samples.empty() && state.window_n == 0 && state.cycle_t0 == 0.0)) return;
    // The motion ends on a knot at the cycling's start position: the end of cycle K, K = from + 1
    // (cycle() lays out a cycle more than it runs; K = from in a checkpoint of a vppdem that
    // did not). The knots of cycles K .. ncyc follow, those a run of ncyc cycles lays out.
    dem::Motion& cap = world.planes[kTopCap].motion;
    dem::Motion& ring = world.motions.at(std::size_t(world.particles.motion.at(scene.top_ring.front())));
    const double T = cycle_period(config.process);
    const int K = int(std::llround((cap.history.back().time - state.cycle_t0) / T));
    const double cap0 = cap.history.back().displacement.z, ring0 = ring.history.back().displacement.z;
    lay_out_cycles(config, state, cap, ring, cap0, ring0, K, ncyc + 1, false);
    if (K <= from)
        services.warn(state, "process.cycles raised on a checkpoint of an older vppdem: its last step held the cap where a run of " +
             std::to_string(ncyc) + " cycles moves it on, so the record is a continuation, not bitwise that run's");
    // Such a checkpoint kept no window for the next cycle's first sample either (see cycle()).
    else if (state.stage == Stage::Done && state.window_n == 0 && config.process.sample_window > world.params.dt)
        services.warn(state, "process.cycles raised: the first sample of cycle " + std::to_string(from + 1) +
             " averages a shorter window than process.sample_window");
    if (state.stage == Stage::Done) {
        // Cycling again: the end of the run (next_stage(Done)) moved the displacements' origin to
        // where the cap stood then; the cycling's is the start position, the motion's last knot.
        state.stage = Stage::Cycling;
        state.cap_d0 = cap0;
    }
    services.log("damper: process.cycles %d -> %d: the run continues with cycles %d-%d\n", from, ncyc, from + 1, ncyc);
}

void cycle(DamperScene& scene, RunState& state, StageServices& services, int upto) {
    dem::World& world = scene.world;
    const Config& config = scene.config;
    const double A = config.process.amplitude, T = cycle_period(config.process);
    const double v = config.process.frequency > 0.0 ? 2.0 * A / T : config.process.velocity;  // the offset move's speed
    const int S = int(config.process.samples_per_cycle), ncyc = int(config.process.cycles);
    const double win = config.process.sample_window;
    if (state.samples.empty() && state.window_n == 0 && state.cycle_t0 == 0.0) {
        // Start of cycling: cap and top ring follow one history: an optional offset move, then
        // `cycles` triangles of the amplitude (down first for compression, up for extension).
        const double d0 = world.planes[kTopCap].motion.displacement(world.time).z;
        const double off = config.process.start_offset;
        const double t_off = std::abs(off) / v;
        dem::Motion cap, ring;
        cap.history.push_back({world.time, {0, 0, d0}});
        ring.history.push_back({world.time, {0, 0, 0}});
        state.cycle_t0 = world.time + t_off;
        // One cycle more than the run cycles: the last step, which may end a fraction of a step
        // past the last cycle's end, moves as a longer run's does; so a run given more cycles
        // when it is resumed (extend_cycling) is that longer run, bit for bit. The run's records
        // end with the sample before (the extra knots move nothing it records).
        lay_out_cycles(config, state, cap, ring, d0 - off, -off, 0, ncyc + 1, t_off > 0);
        world.planes[kTopCap].motion = cap;
        const uint32_t m = world.add_motion(ring);
        for (uint32_t i : scene.top_ring) world.set_prescribed(i, m);
        state.cap_d0 = d0 - off;  // displacements are recorded from the cycling start position
        // Energy ledger (energy.csv); restarted at the first sample, the start of cycling.
        world.params.track_energy = config.output.energy;
        if (config.output.energy) world.reset_energy();
    } else if (!world.params.track_energy && config.output.energy) {
        services.warn(state, "energy: resumed from a checkpoint without an energy ledger (an older vppdem's); no energy.csv");
    }
    const bool energy = world.params.track_energy;
    const double t_end = state.cycle_t0 + upto * T;  // the end of cycle `upto`
    const uint64_t total = uint64_t(std::ceil((t_end - world.time) / world.params.dt));
    StageProgress prog("cycle", total, services.options());
    uint64_t done = 0;
    auto sample_time = [&](std::size_t s) { return state.cycle_t0 + double(s) * T / S; };
    world.profile().enable(services.options().profile);
    world.profile().reset();
    const bool air = air_recorded(config);
    // In a batch the World's particles are the batch's between the half steps: they are handed
    // back (sync) before anything here reads them (the air's volume, a checkpoint, a VTK frame),
    // and for good when the stage ends or throws.
    dem::batch::BatchStepper* const batch = services.options().batch;
    struct LeaveBatch {
        dem::batch::BatchStepper* b;
        dem::World& w;
        ~LeaveBatch() {
            if (b) b->leave(w);
        }
    } leave_batch{batch, world};
    // On a device backend the device runs the steps between this loop's events by itself
    // (chunks, docs/gpu.md): the loop asks for its next sample's step, the window's forces of the
    // steps before it summed on the device as the loop sums them. Not with the air, which changes
    // dp every step from the foil's volume, nor with VTK frames, which read every step's time.
    const bool chunks = batch && batch->chunked() && !air && !(config.output.vtk_interval > 0);
    dem::batch::DeviceBatch::Probe probe;
    if (chunks) probe.particles = scene.top_ring;
    while (world.time < t_end - 0.5 * world.params.dt) {
        if (air) {
            if (batch) batch->sync(world);
            air_step(scene, state, config.process.underpressure);
        }
        if (chunks) {
            const std::size_t s = state.samples.size();
            // The step of the next sample (the first whose time reaches it), or the loop's last.
            const double dt = world.params.dt;
            const bool sampling = s < std::size_t(ncyc) * S;
            const double ts = sampling ? sample_time(s) - 0.5 * dt : 0.0;
            const dem::World::EngineSteps e = world.engine_steps();
            dem::StepClock clock = e.clock;
            double t = e.time;
            uint64_t n = e.steps;
            while (!(sampling && t >= ts)) {
                double t1 = t;
                uint64_t n1 = n;
                clock.advance(t1, n1, dt);
                if (!(t1 < t_end - 0.5 * dt)) break;  // step n is the loop's last
                t = t1;
                n = n1;
            }
            probe.sums = dem::batch::ForceProbe{};
            probe.sums.from = s <= std::size_t(ncyc) * S ? sample_time(s) - win - 0.5 * dt : 1e300;
            probe.sums.wall = kTopCap;
            probe.sums.wall_sum.z = state.window_grains;
            probe.sums.particle_sum.z = state.window_foil;
            const uint64_t before = world.steps;
            batch->compute_forces(world, n, &probe);
            state.window_grains = probe.sums.wall_sum.z;
            state.window_foil = probe.sums.particle_sum.z;
            state.window_n += long(probe.sums.count);
            done += world.steps - before;
        } else if (batch) {
            batch->compute_forces(world);
        } else {
            world.compute_forces();
        }
        const std::size_t s = state.samples.size();
        bool sampled = false;
        // The window of the sample that would open the cycle after the last is kept too (it lies
        // before the run's end; the sample is never taken): a run given more cycles when it is
        // resumed (extend_cycling) takes that sample as a run of that many cycles does.
        if (s <= std::size_t(ncyc) * S) {
            const double ts = sample_time(s);
            if (world.time > ts - win - 0.5 * world.params.dt) {
                state.window_grains += world.wall_force(kTopCap).z;
                state.window_foil += scene.top_ring_force_z();
                ++state.window_n;
            }
            if (s < std::size_t(ncyc) * S && world.time >= ts - 0.5 * world.params.dt) {
                Sample smp;
                smp.time = world.time;
                smp.displacement = state.cap_d0 - world.planes[kTopCap].motion.displacement(world.time).z;
                smp.grains = state.window_grains / double(state.window_n);
                smp.foil = state.window_foil / double(state.window_n);
                state.samples.push_back(smp);
                state.window_grains = state.window_foil = 0;
                state.window_n = 0;
                sampled = true;
                // The ledger counts from the first sample: works and dissipations are 0 there.
                if (energy && s == 0) world.reset_energy();
                if (air) {
                    if (s == 0) state.gas_work = 0.0;
                    state.air.push_back(air_sample(scene, state));
                }
                if (s == 0) {
                    if (batch) batch->sync(world);  // it reads the sample's geometry
                    record_start_of_cycling(scene, state, smp);
                }
            }
        }
        world.profile().lap(dem::Phase::kOutput);
        if (batch) batch->integrate(world);
        else world.integrate();
        // The ledger at this sample's time is complete once the step is integrated.
        if (energy && sampled) state.energy.push_back(energy_row(world.energy(), world.energy().time - state.cycle_t0));
        prog.update(++done, world.time);
        services.checkpoint(scene, state, false);
        services.cycle_frame(scene);
        world.profile().lap(dem::Phase::kOutput);
    }
    if (batch) batch->leave(world);
    if (services.options().profile && done > 0) {
        const dem::PhaseProfile& pr = world.profile();
        std::fprintf(stderr, "[cycle] time per phase over %llu steps (%d threads):\n", (unsigned long long)done, world.params.threads);
        for (int k = 0; k < int(dem::Phase::kCount); ++k) {
            const auto ph = dem::Phase(k);
            std::fprintf(stderr, "  %-18s %10.3f s %9.2f us/step %6.1f%%\n", dem::phase_name(ph), pr.seconds(ph),
                1e6 * pr.seconds(ph) / double(done), 100.0 * pr.seconds(ph) / std::max(pr.total(), 1e-300));
        }
        std::fprintf(stderr, "  %-18s %10.3f s %9.2f us/step\n", "total", pr.total(), 1e6 * pr.total() / double(done));
    }
    world.profile().enable(false);
}

int cycles_done(const DamperScene& scene, const RunState& state) {
    const int ncyc = int(scene.config.process.cycles);
    if (state.stage == Stage::Done) return ncyc;
    if (state.stage < Stage::Cycling || (state.samples.empty() && state.window_n == 0 && state.cycle_t0 == 0.0)) return 0;
    // The test that ends cycle(k), so a run stopped there counts k (and one stopped within
    // a cycle, in a checkpoint, the cycles before it).
    const double T = cycle_period(scene.config.process);
    for (int k = ncyc; k > 0; --k)
        if (!(scene.world.time < state.cycle_t0 + k * T - 0.5 * scene.world.params.dt)) return k;
    return 0;
}

}  // namespace vpp::damper_detail::stages
