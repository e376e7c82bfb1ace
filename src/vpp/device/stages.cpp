// The device run's stages (device/stages.h).
#include "vpp/device/stages.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "scene/progress.h"
#include "vpp/device/checks.h"
#include "vpp/device/pour.h"
#include "vpp/device/records.h"
#include "vpp/membrane/air.h"

namespace vpp::device_detail::stages {

using dem::Vec3;

bool step(DeviceScene& scene, DeviceState& state, StageServices& services, DeviceStage stage, double dp_set) {
    dem::World& w = scene.world;
    bool done = true;
    for (std::size_t k = 0; k < scene.tools.size(); ++k) {
        const dem::ToolState before = state.tools[k];
        done = dem::drive_tool(w, scene.tools[k], state.tools[k], int32_t(stage)) && done;
        if (state.tools[k].segment != before.segment) {
            const std::string short_of = force_segment_stopped_short(w, scene.tools[k], k, before, state.tools[k], int32_t(stage));
            if (!short_of.empty()) services.warn(state, short_of);
        }
    }
    if (state.sealed) membrane_air_step(w, scene.membrane, scene.grain_volume, dp_set, scene.def.air, state.gas);
    w.compute_forces();
    if (state.suction.on)  // sets the footprint's ext_force, which integrate() applies and the ledger books
        state.suction.last = step_seal(state.suction.seal, w.particles.pos, object_shift(scene), w.params.dt, scene.def.suction,
                                       w.particles.ext_force);
    add_tool_forces(scene, state);
    const bool sample = sample_due(scene, state);
    if (sample) record_sample(scene, state, stage);
    w.integrate();
    const double vtk_interval = scene.def.vtk_interval;
    if (vtk_interval > 0.0 && w.time >= double(state.vtk_frames + 1) * vtk_interval - 0.5 * w.params.dt) {
        ++state.vtk_frames;
        char name[32];
        std::snprintf(name, sizeof name, "frame_%06lld", (long long)state.vtk_frames);
        services.vtk_frame(scene, name);
    }
    if (sample && w.params.track_energy) record_energy(scene, state);
    return done;
}

namespace {

// The suction's seal on result.object from the membrane as it lies at the load stage's start
// (vpp/device/suction.h); a warning where the membrane does not touch the object.
void capture_suction(DeviceScene& scene, DeviceState& state, StageServices& services) {
    dem::World& w = scene.world;
    const dem::Tool& t = scene.tools[object_index(scene)];
    // The facets at their build positions: capture_seal adds the object's translation.
    const std::vector<dem::Facet> facets(w.facets.begin() + t.facet0, w.facets.begin() + t.facet1);
    state.suction.seal = capture_seal(w.pressure.fans, w.particles.pos, scene.def.membrane.foil.particle_radius, facets,
                                      object_shift(scene), scene.def.suction);
    state.suction.on = 1;
    if (w.particles.ext_force.size() != w.particles.size()) w.particles.ext_force.assign(w.particles.size(), Vec3{});
    double area = 0;
    for (double a : state.suction.seal.area) area += a;
    state.report["seal_particles"] = double(state.suction.seal.particle.size());
    state.report["seal_area"] = area;
    char msg[200];
    std::snprintf(msg, sizeof msg, "load: the membrane seals on '%s' over %zu particles (%.4g m^2)", scene.def.object.c_str(),
                  state.suction.seal.particle.size(), area);
    services.log(msg);
    if (state.suction.seal.particle.empty())
        services.warn(state, "suction: the membrane does not touch result.object '" + scene.def.object +
                                 "' at the load stage's start: no seal, no suction (press it on further: the press segment's force or travel)");
}

// Pour: the grains that missed the bag (or spilled over its rim) and fell below it would fall for
// ever and keep the pour from coming to rest: retired, counted (report "grains_spilled").
void retire_spilled(DeviceScene& scene, DeviceState& state) {
    const double z_min = scene.membrane_z_min();
    bool any = false;
    for (uint32_t i = scene.first_grain; i < scene.end_grain; ++i)
        if (scene.active_grain(i) && scene.world.particles.pos[i].z < z_min - 2.0 * scene.def.grain_radius) {
            scene.retire_grain(i);
            state.report["grains_spilled"] += 1.0;
            any = true;
        }
    if (any) scene.world.invalidate_candidates();
}

}  // namespace

void fill(DeviceScene& scene, DeviceState& state, StageServices& services) {
    const DeviceDef& def = scene.def;
    const dem::World& w = scene.world;
    const double check = 2e-3;  // [s] between the rest checks, at fixed times from the stage start
    // The grains' weight lifted by a diameter (with g = 9.81 m/s^2 where the device has no gravity).
    const double g = norm(def.gravity) > 0.0 ? norm(def.gravity) : 9.81;
    const double scale = double(scene.active_grains()) * w.particles.mass[scene.first_grain] * g * 2.0 * def.grain_radius;
    scene::Progress prog("fill", uint64_t(def.fill_time / w.params.dt), services.options().quiet);
    uint64_t n = 0;
    if (state.at.next_check == 0) state.at.next_check = state.at.t0 + check;
    for (;;) {
        if (services.pause_point(scene, state)) return;
        step(scene, state, services, DeviceStage::Fill, 0.0);
        prog.update(++n, w.time);
        if (w.time < state.at.next_check) continue;
        state.at.next_check += check;
        if (scene.pour) retire_spilled(scene, state);
        const double t = w.time - state.at.t0;
        const double ke = scene.grains_kinetic_energy();
        if (t >= def.fill_min_time && ke < 1e-4 * scale) {
            state.report["fill_settled"] = 1.0;
            break;
        }
        if (t >= def.fill_time) {
            state.report["fill_settled"] = 0.0;
            services.warn(state, fill_not_at_rest(def, ke, 1e-4 * scale));
            break;
        }
    }
    state.report["fill_time"] = w.time - state.at.t0;
    char msg[160];
    std::snprintf(msg, sizeof msg, "fill: %u grains settled in %.4g s", unsigned(scene.active_grains()), w.time - state.at.t0);
    services.log(msg);
}

void seal(DeviceScene& scene, DeviceState& state, StageServices& services) {
    const DeviceDef& def = scene.def;
    dem::World& w = scene.world;
    if (scene.pour) {
        const std::size_t n = strike_off(scene);
        state.report["grains_removed_at_seal"] = double(n);
        scene.grain_volume = scene.active_grain_volume();
        char msg[200];
        std::snprintf(msg, sizeof msg, "seal: the opening closed; %zu grains struck off (outside the membrane or overlapping "
                      "the opening), %zu in the bag", n, scene.active_grains());
        services.log(msg);
    }
    state.report["seal_max_overlap"] = scene.largest_membrane_overlap();
    if (w.materials[scene.grain_mat].friction != def.grain_friction) {  // the fill's friction ends with the fill
        w.materials[scene.grain_mat].friction = def.grain_friction;
        w.invalidate_contact_physics();
    }
    w.pressure.fans = membrane_pressure_fans(scene.membrane);
    w.pressure.dp = 0.0;
    state.sealed = 1;
    state.gas = MembraneGas{};
    state.report["volume_seal"] = scene.enclosed();
    if (def.energy) {
        w.params.track_energy = true;
        w.reset_energy();
    }
    char msg[160];
    std::snprintf(msg, sizeof msg, "seal: enclosed volume %.6g m^3 (grains %.6g m^3)", scene.enclosed(), scene.grain_volume);
    services.log(msg);
}

void tools(DeviceScene& scene, DeviceState& state, StageServices& services, DeviceStage stage) {
    const DeviceDef& def = scene.def;
    const dem::World& w = scene.world;
    const std::vector<dem::Tool>& tools = scene.tools;
    double longest = 0;
    for (const dem::Tool& t : tools)
        longest = std::max(longest, dem::program_duration(t, int32_t(stage), dem::tool_displacement(w, t, w.time)));
    scene::Progress prog(device_stage_name(stage), uint64_t(longest / w.params.dt) + 1, services.options().quiet);
    uint64_t n = 0;
    const double dp = state.sealed && stage > DeviceStage::Vacuum ? def.underpressure : 0.0;
    if (stage == DeviceStage::Load && def.suction.enabled && !state.suction.on) capture_suction(scene, state, services);
    // The load stage ends early once the object has carried no force for result.release_time
    // (it has let go: the rest of the lift would record zeros).
    const dem::Tool* obj = nullptr;
    for (const dem::Tool& t : tools)
        if (t.name == def.object && stage == DeviceStage::Load && def.release_time > 0) obj = &t;
    // The cycle tool's first load-stage cycle segment: where and when it starts is the cycle
    // analysis's origin (recorded once it has started; kept over a resume).
    std::size_t ck = tools.size();
    int32_t cseg = -1;
    for (std::size_t k = 0; k < tools.size(); ++k)
        if (stage == DeviceStage::Load && tools[k].name == def.cycle_tool)
            for (std::size_t s = 0; s < tools[k].program.size() && cseg < 0; ++s)
                if (tools[k].program[s].stage == int32_t(stage) && tools[k].program[s].kind == dem::SegmentKind::Cycle) {
                    ck = k;
                    cseg = int32_t(s);
                }
    auto note_cycle = [&] {
        if (ck == tools.size() || state.report.count("cycle_t0")) return;
        const dem::ToolState& ts = state.tools[ck];
        if (ts.segment != cseg || !ts.started) return;
        state.report["cycle_t0"] = ts.t0;
        state.report["cycle_d0"] = ts.d0;
    };
    for (;;) {
        if (services.pause_point(scene, state)) return;
        const bool done = step(scene, state, services, stage, dp);
        note_cycle();
        if (done) break;
        prog.update(++n, w.time);
        if (!obj) continue;
        const Vec3 held = dem::tool_force(w, *obj) + (state.suction.on ? state.suction.last.object_force : Vec3{});
        state.at.free_steps = held == Vec3{} ? state.at.free_steps + 1 : 0;
        if (double(state.at.free_steps) * w.params.dt >= def.release_time) {
            char msg[160];
            std::snprintf(msg, sizeof msg, "load: the object '%s' let go; the load stage ends at t = %.6g s", def.object.c_str(), w.time);
            services.log(msg);
            state.report["released"] = 1.0;
            break;
        }
    }
}

void vacuum(DeviceScene& scene, DeviceState& state, StageServices& services) {
    const DeviceDef& def = scene.def;
    const dem::World& w = scene.world;
    const double t_end = def.ramp_time + def.vacuum_hold;
    if (!state.report.count("volume_press")) state.report["volume_press"] = scene.enclosed();  // the vacuum's start
    // The stage lasts the ramp and the hold, or the tools' vacuum segments where they take longer.
    double longest = t_end - (w.time - state.at.t0);
    for (const dem::Tool& t : scene.tools)
        longest = std::max(longest, dem::program_duration(t, int32_t(DeviceStage::Vacuum), dem::tool_displacement(w, t, w.time)));
    scene::Progress prog("vacuum", uint64_t(std::max(longest, 0.0) / w.params.dt) + 1, services.options().quiet);
    uint64_t n = 0;
    for (;;) {
        const double t = w.time - state.at.t0;
        if (t >= t_end - 0.5 * w.params.dt && state.at.tools_done) break;
        if (services.pause_point(scene, state)) return;
        state.at.tools_done = step(scene, state, services, DeviceStage::Vacuum, def.underpressure * std::min(1.0, t / def.ramp_time));
        prog.update(++n, w.time);
    }
    state.report["volume_vacuum"] = scene.enclosed();
    const double z_min = scene.membrane_z_min();
    state.report["membrane_z_min"] = z_min;
    char msg[160];
    std::snprintf(msg, sizeof msg, "vacuum: dp %.6g Pa, enclosed volume %.6g m^3, the membrane's lowest point at z = %.6g m",
                  w.pressure.dp, scene.enclosed(), z_min);
    services.log(msg);
}

void next_stage(DeviceScene& scene, DeviceState& state, StageServices& services) {
    if (scene.def.vtk) services.vtk_frame(scene, "stage_" + std::to_string(state.at.stage) + "_" + device_stage_name(DeviceStage(state.at.stage)));
    ++state.at.stage;
    state.at.t0 = scene.world.time;
    state.at.next_check = 0;
    state.at.free_steps = 0;
    state.at.tools_done = 0;
    services.checkpoint(scene, state);
    services.write_records(scene, state);
}

}  // namespace vpp::device_detail::stages
