// The device run's result and summary.json (device/result.h).
#include "vpp/device/result.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "dem/io/json.h"
#include "vpp/device/records.h"

namespace vpp::device_detail {

namespace {

double reported(const DeviceState& state, const char* key) {
    const auto it = state.report.find(key);
    return it == state.report.end() ? 0.0 : it->second;
}

// The cycle tool's loops into r: P = -sign(a) F_z, the load it puts on the sample along the
// cycle's first leg, against u = sign(a) (z - z0), the displacement along it. Rows are assigned
// to cycles by time (period 2 |a| / speed from the cycle's start); each cycle's loop is closed by
// the row before it (or u = 0, P = its first row's at the start).
void add_cycles(const DeviceScene& scene, const DeviceState& state, DeviceResult& r) {
    const std::size_t cols = tool_row_size(scene.tools.size());
    for (std::size_t k = 0; k < scene.tools.size(); ++k) {
        if (scene.tools[k].name != scene.def.cycle_tool || !state.report.count("cycle_t0")) continue;
        const dem::ToolSegment* seg = nullptr;
        for (const dem::ToolSegment& s : scene.tools[k].program)
            if (!seg && s.stage == int32_t(DeviceStage::Load) && s.kind == dem::SegmentKind::Cycle) seg = &s;
        if (!seg) break;
        const double sg = seg->amplitude < 0 ? -1.0 : 1.0, amp = std::abs(seg->amplitude);
        const double period = 2.0 * amp / seg->speed, t0 = reported(state, "cycle_t0"), z0 = reported(state, "cycle_d0");
        std::vector<std::vector<std::pair<double, double>>> loops(std::size_t(seg->cycles));
        std::pair<double, double> prev{0.0, 0.0};
        bool have_prev = false;
        for (std::size_t s = 0; s < r.samples; ++s) {
            const double* row = &state.records.tools[s * cols];
            if (int(row[1]) != int(DeviceStage::Load)) continue;
            const double t = row[0] - t0;
            const long c = t <= 0.0 ? -1 : long(std::floor((t - 1e-12) / period));
            const std::pair<double, double> up{sg * (row[2 + kToolColumns * k] - z0), -sg * row[2 + kToolColumns * k + 3]};
            if (c >= 0 && c < long(loops.size())) {
                auto& L = loops[std::size_t(c)];
                if (L.empty()) L.push_back(have_prev ? prev : std::pair<double, double>{0.0, up.second});
                L.push_back(up);
            }
            prev = up;
            have_prev = true;
        }
        for (const auto& L : loops) {
            if (L.size() < 4) continue;
            double w = 0, peak = 0;
            double su = 0, sp = 0, suu = 0, sup = 0;
            int n = 0;
            for (std::size_t i = 1; i < L.size(); ++i) {
                w += 0.5 * (L[i].second + L[i - 1].second) * (L[i].first - L[i - 1].first);
                peak = std::max(peak, L[i].second);
            }
            // The loading branch: the first leg (u rising to its largest).
            std::size_t top = 0;
            for (std::size_t i = 0; i < L.size(); ++i)
                if (L[i].first > L[top].first) top = i;
            for (std::size_t i = 0; i <= top; ++i) {
                su += L[i].first;
                sp += L[i].second;
                suu += L[i].first * L[i].first;
                sup += L[i].first * L[i].second;
                ++n;
            }
            const double den = double(n) * suu - su * su;
            r.cycle_stiffness.push_back(n >= 2 && den > 0 ? (double(n) * sup - su * sp) / den : 0.0);
            r.cycle_work.push_back(w);
            r.cycle_peak_force.push_back(peak);
        }
    }
}

// The largest pull on result.object in the load stage (and when), the largest push before it.
void add_object_forces(const DeviceScene& scene, const DeviceState& state, DeviceResult& r) {
    const std::size_t cols = tool_row_size(scene.tools.size());
    std::size_t obj = scene.tools.size();
    for (std::size_t k = 0; k < scene.tools.size(); ++k)
        if (scene.tools[k].name == scene.def.object) obj = k;
    if (obj == scene.tools.size()) return;
    for (std::size_t s = 0; s < r.samples; ++s) {
        const double* row = &state.records.tools[s * cols];
        const double fz = row[2 + kToolColumns * obj + 3];
        if (int(row[1]) == int(DeviceStage::Load) && fz > r.holding_force) {
            r.holding_force = fz;
            r.holding_time = row[0];
        }
        if (int(row[1]) < int(DeviceStage::Load)) r.press_force = std::max(r.press_force, -fz);
    }
}

// A JSON array of numbers on one line.
std::string number_array(const std::vector<double>& v) {
    std::string out = "[";
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + dem::json_double(v[k]);
    return out + "]";
}

}  // namespace

DeviceResult device_result(const DeviceScene& scene, const DeviceState& state) {
    DeviceResult r;
    r.stage = device_stage_name(DeviceStage(state.at.stage));
    r.grains = scene.active_grains();
    r.grains_placed = scene.end_grain - scene.first_grain;
    r.grains_spilled = std::size_t(reported(state, "grains_spilled"));
    r.grains_removed_at_seal = std::size_t(reported(state, "grains_removed_at_seal"));
    r.seal_max_overlap = reported(state, "seal_max_overlap");
    r.membrane_particles = scene.membrane.particles.size();
    r.bonds = scene.membrane.bonds.size();
    r.dt = scene.world.params.dt;
    r.samples = state.records.tools.size() / tool_row_size(scene.tools.size());
    add_object_forces(scene, state, r);
    // The object's cross-section normal to the pull: its closed surface projected on the xy plane,
    // half the sum of |A_z| over its facets.
    const std::size_t obj = object_index(scene);
    if (obj < scene.tools.size())
        for (uint32_t k = scene.tools[obj].facet0; k < scene.tools[obj].facet1; ++k) {
            const auto& v = scene.world.facets[k].vertices;
            r.object_area += 0.25 * std::abs(cross(v[1] - v[0], v[2] - v[0]).z);
        }
    if (scene.def.underpressure > 0 && r.object_area > 0) r.holding_ratio = r.holding_force / (scene.def.underpressure * r.object_area);
    const std::vector<double>& suction = state.suction.rows;
    for (std::size_t s = 0; s + kSuctionColumns <= suction.size(); s += kSuctionColumns)
        r.suction_force_max = std::max(r.suction_force_max, suction[s + kSuctionColumns - 1]);
    r.seal_area = reported(state, "seal_area");
    add_cycles(scene, state, r);
    r.volume_seal = reported(state, "volume_seal");
    r.volume_vacuum = reported(state, "volume_vacuum");
    r.volume_press = reported(state, "volume_press");
    if (r.volume_seal > 0 && r.volume_vacuum > 0) r.volume_change = (r.volume_vacuum - r.volume_seal) / r.volume_seal;
    if (r.volume_press > 0 && r.volume_vacuum > 0) r.volume_change_vacuum = (r.volume_vacuum - r.volume_press) / r.volume_press;
    r.fill_settled = reported(state, "fill_settled") != 0.0;
    r.packing_seal = r.volume_seal > 0 ? scene.grain_volume / r.volume_seal : 0.0;
    // The scale: the largest term of any row (every column but the time and the residual).
    const std::vector<double>& energy = state.records.energy;
    const std::size_t first = dem::energy_column("boundary_work"), res = dem::energy_column("residual");
    for (std::size_t s = 0; s + kEnergyRowSize <= energy.size(); s += kEnergyRowSize)
        for (std::size_t c = first; c < kEnergyRowSize; ++c)
            if (c != res) r.energy_scale = std::max(r.energy_scale, std::abs(energy[s + c]));
    if (!energy.empty()) r.energy_residual = energy.back();
    r.warnings = state.warnings;
    return r;
}

std::string summary_json(const DeviceScene& scene, const DeviceState& state, const DeviceResult& r) {
    const DeviceDef& def = scene.def;
    dem::JsonObject inputs;
    for (const auto& [k, v] : device_inputs(def)) inputs.raw(k, v);
    std::vector<std::string> names;
    for (const dem::Tool& t : scene.tools) names.push_back(t.name);
    dem::JsonObject j;
    j.str("stage", r.stage)
        .str("object", def.object)
        .num("holding_force", r.holding_force)
        .num("holding_time", r.holding_time)
        .num("press_force", r.press_force)
        .num("object_area", r.object_area)
        .num("holding_ratio", r.holding_ratio)
        .num("underpressure", def.underpressure)
        .num("volume_seal", r.volume_seal)
        .num("volume_vacuum", r.volume_vacuum)
        .num("volume_change", r.volume_change)
        .num("volume_press", r.volume_press)
        .num("volume_change_vacuum", r.volume_change_vacuum)
        .boolean("fill_settled", r.fill_settled)
        .boolean("released", state.report.count("released") > 0)
        .num("membrane_z_min", reported(state, "membrane_z_min"))
        .num("fill_time", reported(state, "fill_time"))
        .num("grains", double(r.grains))
        .str("fill_mode", def.fill_mode)
        .num("grains_placed", double(scene.end_grain - scene.first_grain))
        .num("grains_spilled", reported(state, "grains_spilled"))
        .num("grains_removed_at_seal", reported(state, "grains_removed_at_seal"))
        .num("seal_max_overlap", reported(state, "seal_max_overlap"))
        .num("grain_volume", scene.grain_volume)
        .num("membrane_particles", double(r.membrane_particles))
        .num("bonds", double(r.bonds))
        .raw("tools", dem::json_string_array(names))
        .num("dt", r.dt)
        .num("steps", double(scene.world.steps))
        .num("time", scene.world.time)
        .num("samples", double(r.samples))
        .str("cycle_tool", def.cycle_tool)
        .num("stiffness", r.cycle_stiffness.empty() ? 0.0 : r.cycle_stiffness.back())
        .num("work_per_cycle", r.cycle_work.empty() ? 0.0 : r.cycle_work.back())
        .num("peak_force", r.cycle_peak_force.empty() ? 0.0 : r.cycle_peak_force.back())
        .raw("cycle_stiffness", number_array(r.cycle_stiffness))
        .raw("cycle_work", number_array(r.cycle_work))
        .raw("cycle_peak_force", number_array(r.cycle_peak_force))
        .num("packing_seal", r.volume_seal > 0 ? scene.grain_volume / r.volume_seal : 0.0)
        .num("packing_vacuum", r.volume_vacuum > 0 ? scene.grain_volume / r.volume_vacuum : 0.0)
        .num("energy_residual", r.energy_residual)
        .num("energy_scale", r.energy_scale)
        .raw("warnings", dem::json_string_array(r.warnings));
    if (def.suction.enabled)
        j.num("suction_force_max", r.suction_force_max)
            .num("seal_area", r.seal_area)
            .num("seal_particles", reported(state, "seal_particles"));
    j.raw("inputs", inputs.value());
    return j.text();
}

}  // namespace vpp::device_detail
