// The rows of the device's records, taken into the run state as the run steps (docs/devices.md,
// "Records"): every output.sample_interval of simulated time a row of tools.csv (each tool's z
// displacement and the particles' force on it averaged over the steps since the row before), one
// of air.csv (enclosed volume, gas volume, dp) and, with the energy ledger on, one of energy.csv.
// The recorder (device/recorder.h) writes them out. Internal to vpp/device/*.cpp.
#pragma once

#include "vpp/device/definition.h"
#include "vpp/device/scene.h"
#include "vpp/device/state.h"

namespace vpp::device_detail {

// After the step's forces: each tool's reaction added to the sample window (result.object's with
// the suction's pull through the seal, state.suction.last).
void add_tool_forces(const DeviceScene& scene, DeviceState& state);
// Whether the step at the World's time takes a row: the first at or past the next multiple of
// output.sample_interval (half a step's tolerance).
bool sample_due(const DeviceScene& scene, const DeviceState& state);
// The rows of tools.csv (the window's mean force, then the window restarted) and air.csv at the
// World's time, in stage `stage`.
void record_sample(const DeviceScene& scene, DeviceState& state, DeviceStage stage);
// result.object's index in the scene's tools (scene.tools.size(): none).
std::size_t object_index(const DeviceScene& scene);
// The object's translation now [m] (tools move along z; 0 without an object).
dem::Vec3 object_shift(const DeviceScene& scene);
// The row of energy.csv: the ledger as it stands (after the step's integration).
void record_energy(const DeviceScene& scene, DeviceState& state);

}  // namespace vpp::device_detail
