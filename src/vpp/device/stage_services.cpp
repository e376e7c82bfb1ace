// What a stage asks of the device run (device/stage_services.h).
#include "vpp/device/stage_services.h"

#include <cstdio>

namespace vpp::device_detail {

bool StageServices::pause_point(DeviceScene& scene, const DeviceState& state) {
    if ((options_.stop_at_time >= 0.0 && scene.world.time >= options_.stop_at_time) || (options_.stop && options_.stop())) {
        checkpoint(scene, state);
        write_records(scene, state);
        stopped_ = true;
        return true;
    }
    if (recorder_.checkpoint_due(options_.checkpoint_every)) checkpoint(scene, state);
    return false;
}

void StageServices::checkpoint(DeviceScene& scene, const DeviceState& state) const {
    recorder_.save_checkpoint(scene.world, state);
}

void StageServices::warn(DeviceState& state, const std::string& what) const {
    state.warnings.push_back(what);
    if (!options_.quiet) std::fprintf(stderr, "[device] warning: %s\n", what.c_str());
}

void StageServices::log(const std::string& what) const {
    if (!options_.quiet) std::fprintf(stderr, "[device] %s\n", what.c_str());
}

}  // namespace vpp::device_detail
