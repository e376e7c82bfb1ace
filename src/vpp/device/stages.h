// The device run's stages, a stage at a time (docs/devices.md, "Stages"): fill, seal, the tools'
// stages (press, load), vacuum. Each is a function of the scene (device/scene.h), the run state
// (device/state.h) and what it asks of the run around it (device/stage_services.h: the pause
// points, checkpoints, records, warnings); run_device calls them in order. A stage resumed from
// a checkpoint takes its decisions at the same steps as an uninterrupted one: the records are
// bitwise the same however the run is split. A stage stopped at a pause point returns at once
// (services.stopped()). Internal to vpp/device/*.cpp.
#pragma once

#include "vpp/device/definition.h"
#include "vpp/device/scene.h"
#include "vpp/device/stage_services.h"
#include "vpp/device/state.h"

namespace vpp::device_detail::stages {

// One step of `stage` with the regulator at dp_set [Pa]: the tools driven, the air, the forces,
// a row of the records when one is due, the integration, a VTK frame when one is due. True when
// the tools' segments of the stage are done.
bool step(DeviceScene& scene, DeviceState& state, StageServices& services, DeviceStage stage, double dp_set);
// The grains settle (a pour: fall through the opening; the ones that miss the bag retired) until
// at rest after stages.fill_min_time, or stages.fill_time (warned).
void fill(DeviceScene& scene, DeviceState& state, StageServices& services);
// The pour struck off and its opening closed; the grains' friction, the pressure fans, the air
// and the energy ledger on; the enclosed volume recorded. No steps.
void seal(DeviceScene& scene, DeviceState& state, StageServices& services);
// The tools' segments of `stage` (press, load) until they are done; the load stage ends early
// once result.object has been free for result.release_time.
void tools(DeviceScene& scene, DeviceState& state, StageServices& services, DeviceStage stage);
// dp ramped to stages.underpressure and held, and the tools' vacuum segments, until both are over.
void vacuum(DeviceScene& scene, DeviceState& state, StageServices& services);
// The stage ended: its VTK frame (output.vtk), the next stage's clocks, a checkpoint and the records.
void next_stage(DeviceScene& scene, DeviceState& state, StageServices& services);

}  // namespace vpp::device_detail::stages
