// The rows of the device's records (device/records.h).
#include "vpp/device/records.h"

#include <algorithm>

#include "dem/world/tool.h"

namespace vpp::device_detail {

std::size_t object_index(const DeviceScene& scene) {
    for (std::size_t k = 0; k < scene.tools.size(); ++k)
        if (scene.tools[k].name == scene.def.object) return k;
    return scene.tools.size();
}

dem::Vec3 object_shift(const DeviceScene& scene) {
    const std::size_t k = object_index(scene);
    return k < scene.tools.size() ? dem::Vec3{0, 0, dem::tool_displacement(scene.world, scene.tools[k], scene.world.time)} : dem::Vec3{};
}

void add_tool_forces(const DeviceScene& scene, DeviceState& state) {
    const std::size_t obj = state.suction.on ? object_index(scene) : scene.tools.size();
    for (std::size_t k = 0; k < scene.tools.size(); ++k) {
        dem::Vec3 f = dem::tool_force(scene.world, scene.tools[k]);
        if (k == obj) f += state.suction.last.object_force;  // the surroundings' push through the seal
        state.window.sums[3 * k] += f.x;
        state.window.sums[3 * k + 1] += f.y;
        state.window.sums[3 * k + 2] += f.z;
    }
    ++state.window.steps;
}

bool sample_due(const DeviceScene& scene, const DeviceState& state) {
    const std::size_t taken = state.records.tools.size() / tool_row_size(scene.tools.size());
    return scene.world.time >= double(taken + 1) * scene.def.sample_interval - 0.5 * scene.world.params.dt;
}

void record_sample(const DeviceScene& scene, DeviceState& state, DeviceStage stage) {
    const dem::World& w = scene.world;
    std::vector<double>& rows = state.records.tools;
    rows.push_back(w.time);
    rows.push_back(double(int(stage)));
    for (std::size_t k = 0; k < scene.tools.size(); ++k) {
        rows.push_back(dem::tool_displacement(w, scene.tools[k], w.time));
        for (std::size_t c = 0; c < 3; ++c) rows.push_back(state.window.sums[3 * k + c] / double(state.window.steps));
    }
    std::fill(state.window.sums.begin(), state.window.sums.end(), 0.0);
    state.window.steps = 0;
    const double v = scene.enclosed();
    state.records.air.insert(state.records.air.end(), {w.time, double(int(stage)), v, v - scene.grain_volume, w.pressure.dp});
    if (state.suction.on) {
        const SuctionStep& s = state.suction.last;
        state.suction.rows.insert(state.suction.rows.end(), {w.time, double(s.open), double(s.sealed), double(s.leaked),
                                                             s.pressure_min, s.sealed_area, s.sealed_volume, s.object_force.z});
    }
}

void record_energy(const DeviceScene& scene, DeviceState& state) {
    double row[kEnergyRowSize];
    dem::energy_csv_row(scene.world.energy(), scene.world.energy().time, row);
    state.records.energy.insert(state.records.energy.end(), row, row + kEnergyRowSize);
}

}  // namespace vpp::device_detail
