// The device run (vpp/device/run.h): its scene built from the device file, its state fresh or
// from a checkpoint, its folder opened, and its stages in order. The code's layout, as the
// damper's run (vpp/damper/run.h):
//   device/scene.h/.cpp           the scene: the World, the membrane, the tools, the grains
//   device/fill_sites.h/.cpp      where the grains start: the fill lattice's sites
//   device/pour.h/.cpp            the pour's opening, its column and the seal's strike-off
//   device/fill_geometry.h/.cpp   inside a closed surface, the distance to one, the jitter
//   device/state.h/.cpp           the run state the checkpoint carries (DeviceState)
//   device/stages.h/.cpp          the stages: fill, seal, press and load, vacuum
//   device/stage_services.h/.cpp  what a stage asks of the run: pause points, checkpoints, warnings
//   device/records.h/.cpp         the rows of tools.csv, air.csv and energy.csv as the run steps
//   device/recorder.h/.cpp        the output folder and every file written into it
//   device/result.h/.cpp          DeviceResult and summary.json from the scene and the state
//   device/checks.h/.cpp          what the run was asked against what it did: warnings
//   device/run.cpp                run_device (this file)
#include "vpp/device/run.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "dem/io/checkpoint.h"
#include "scene/scene_runner.h"
#include "vpp/device/recorder.h"
#include "vpp/device/result.h"
#include "vpp/device/scene.h"
#include "vpp/device/stage_services.h"
#include "vpp/device/stages.h"
#include "vpp/device/state.h"

namespace vpp {

namespace device_detail {

namespace {

// The state of the run in `from` (a checkpoint), loaded with its World into the scene: refused
// (std::runtime_error) when made with another device file.
DeviceState resumed_state(DeviceScene& scene, const std::string& from, const StageServices& services) {
    const std::string blob = dem::load_checkpoint(from, scene.world);
    DeviceState state = DeviceState::load(blob, from);
    if (state.inputs != inputs_text(scene.def))
        throw std::runtime_error("checkpoint '" + from + "' was made with another device file (its inputs differ from '" +
                                 scene.def.path + "'): run into a new --out, or give the device file it was made with");
    if (state.sealed) scene.world.pressure.fans = membrane_pressure_fans(scene.membrane);
    if (scene.pour) scene.grain_volume = scene.active_grain_volume();  // the struck-off grains are in the World's masks
    scene.world.params.threads = scene.def.threads;  // this machine's, not the checkpoint's (the results do not depend on it)
    char at[64];
    std::snprintf(at, sizeof at, "t = %.6g s", scene.world.time);
    services.log("resuming from " + from + " at " + at + " in the stage '" + device_stage_name(DeviceStage(state.at.stage)) + "'");
    return state;
}

// The stages from the state's on, each ended by next_stage (a checkpoint and the records), up to
// the options' stop_after or a pause point's stop.
void run_stages(DeviceScene& scene, DeviceState& state, StageServices& services) {
    while (state.at.stage < int32_t(DeviceStage::Done)) {
        const DeviceStage s = DeviceStage(state.at.stage);
        if (int32_t(s) > int32_t(services.options().stop_after)) break;
        switch (s) {
        case DeviceStage::Fill: stages::fill(scene, state, services); break;
        case DeviceStage::Seal: stages::seal(scene, state, services); break;
        case DeviceStage::Press: stages::tools(scene, state, services, s); break;
        case DeviceStage::Vacuum: stages::vacuum(scene, state, services); break;
        case DeviceStage::Load: stages::tools(scene, state, services, s); break;
        case DeviceStage::Done: break;
        }
        if (services.stopped()) return;
        stages::next_stage(scene, state, services);
    }
}

}  // namespace

}  // namespace device_detail

DeviceResult run_device(const DeviceDef& d, const DeviceOptions& o) {
    using namespace device_detail;
    const auto start = std::chrono::steady_clock::now();
    // A device run always writes its folder: an empty one would run to the end and keep
    // nothing (or be the current folder); both front doors refuse it too.
    scene::require_output_path(o.out_dir, "--out");
    DeviceScene scene(d);  // a device file at fault is refused here, before anything is written
    DeviceRecorder recorder(o.out_dir);
    StageServices services(o, recorder);
    const std::string from = scene::resume_checkpoint(o.out_dir, o.from, o.overwrite);
    DeviceState state = from.empty() ? fresh_state(d, scene.tools.size()) : resumed_state(scene, from, services);
    recorder.open(from, o.overwrite, [&](const std::string& what) { services.log(what); });
    run_stages(scene, state, services);
    recorder.write_records(scene, state);
    DeviceResult r = device_result(scene, state);
    r.run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!o.quiet)
        std::fprintf(stderr, "[device] %s: holding force %.6g N, volume change %.4g%% from the seal, %.4g%% in the vacuum stage, %.1f s\n",
                     r.stage.c_str(), r.holding_force, 100.0 * r.volume_change, 100.0 * r.volume_change_vacuum, r.run_seconds);
    return r;
}

}  // namespace vpp
