// The device run's result from its scene and state (docs/devices.md, "Records"): the holding
// and press forces on result.object, the volumes and their changes, the pour's counts, the
// cycle tool's loops (per cycle the loading branch's slope, the loop's area, the peak load) and
// the ledger's residual; and summary.json's text. Internal to vpp/device/*.cpp.
#pragma once

#include <string>

#include "vpp/device/run.h"
#include "vpp/device/scene.h"
#include "vpp/device/state.h"

namespace vpp::device_detail {

// The result as the records stand (run_seconds left 0: the caller's clock).
DeviceResult device_result(const DeviceScene& scene, const DeviceState& state);

// summary.json: the result `r`, what the stages measured, the inputs.
std::string summary_json(const DeviceScene& scene, const DeviceState& state, const DeviceResult& r);

}  // namespace vpp::device_detail
