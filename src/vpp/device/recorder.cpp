// The device run's recorder (device/recorder.h): the output folder, its lock, the checkpoint, the
// records and the VTK frames. Each file's name, content and atomic write (PATH.part renamed to
// PATH) are contracts: tests compare them byte for byte and resumed runs load the checkpoint bit
// for bit.
#include "vpp/device/recorder.h"

#include <vector>

#include "dem/io/csv.h"
#include "dem/io/vtk.h"
#include "scene/build_info.h"
#include "scene/config.h"
#include "scene/scene_runner.h"
#include "vpp/device/result.h"
#include "vpp/membrane/membrane.h"

namespace vpp::device_detail {

namespace fs = std::filesystem;

namespace {

// A VTK frame of the device run (DeviceRecorder::vtk_frame, stages::step), or one left partly
// written (its .part).
bool device_frame(const std::string& name) {
    return (name.starts_with("frame_") || name.starts_with("stage_")) && (name.ends_with(".vtk") || name.ends_with(".vtk.part"));
}

}  // namespace

bool holds_only_a_killed_run(const fs::path& dir, std::vector<fs::path>& stale, fs::path& other) {
    if (!fs::is_directory(dir)) return true;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n == dem::FolderLock::kFileName || n == "build.json") continue;  // rewritten by the new run
        if (n == "run.ckpt.part" && e.is_regular_file()) {
            stale.push_back(e.path());
            continue;
        }
        if (n == "vtk" && e.is_directory()) {
            for (const auto& f : fs::directory_iterator(e.path())) {
                if (!f.is_regular_file() || !device_frame(f.path().filename().string())) {
                    other = f.path();
                    return false;
                }
                stale.push_back(f.path());
            }
            continue;
        }
        other = e.path();
        return false;
    }
    return true;
}

void DeviceRecorder::open(const std::string& resumed_from, bool overwrite, const std::function<void(const std::string&)>& log) {
    const bool own = !resumed_from.empty() && fs::exists(run_checkpoint()) &&
                     fs::equivalent(fs::path(resumed_from), run_checkpoint());
    if (own) {
        lock_ = scene::lock_output_dir(out_.string());
        scene::record_build(out_.string(), false);  // another build resuming the run is listed
        return;
    }
    if (overwrite) {
        lock_ = scene::prepare_output_dir(out_.string(), true);
        return;
    }
    // The lock first: a run in progress before its first checkpoint leaves the same files, and
    // holds the lock (refused: FolderLocked).
    lock_ = scene::lock_output_dir(out_.string());
    std::vector<fs::path> stale;
    fs::path other;
    if (!holds_only_a_killed_run(out_, stale, other))
        throw cfg::ConfigError("--out '" + out_.string() + "' exists and is not empty (it holds '" +
                               other.lexically_relative(out_).string() + "'); pass --overwrite to replace its files");
    // A run killed before its first checkpoint has nothing to resume: started afresh, as the
    // same command into an empty folder would be.
    if (fs::exists(out_ / "build.json") || !stale.empty())
        log("--out '" + out_.string() + "' holds what a run killed before its first checkpoint leaves (no run.ckpt): "
            "starting the run afresh" + (stale.empty() ? "" : ", its " + std::to_string(stale.size()) + " stale file(s) removed"));
    for (const fs::path& f : stale) fs::remove(f);
    scene::record_build(out_.string(), true);  // a new run: this build made it
}

bool DeviceRecorder::checkpoint_due(double every) {
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_ckpt_).count() < every) return false;
    last_ckpt_ = now;
    return true;
}

void DeviceRecorder::save_checkpoint(dem::World& world, const DeviceState& state) const {
    save_checkpoint_without_fans(run_checkpoint().string(), world, state.save());
}

void DeviceRecorder::vtk_frame(const DeviceScene& scene, const std::string& name) const {
    fs::create_directories(out_ / "vtk");
    // The retired grains (a pour's struck off) are left out; without any, every particle.
    std::vector<uint32_t> shown;
    if (scene.pour)
        for (uint32_t i = 0; i < uint32_t(scene.world.particles.size()); ++i)
            if (i < scene.first_grain || i >= scene.end_grain || scene.active_grain(i)) shown.push_back(i);
    dem::write_particles_vtk((out_ / "vtk" / (name + ".vtk")).string(), scene.world, true, scene.pour ? &shown : nullptr);
    if (!scene.world.facets.empty()) dem::write_walls_vtk((out_ / "vtk" / (name + "_tools.vtk")).string(), scene.world, 0.0);
}

namespace {

// `rows` (row after row, `cols` columns each) as CSV at `path` under `header`.
void write_table(const fs::path& path, const std::string& header, const std::vector<double>& rows, std::size_t cols) {
    dem::CsvWriter csv(path.string(), header);
    for (std::size_t s = 0; s + cols <= rows.size(); s += cols)
        csv.row(std::vector<double>(rows.begin() + long(s), rows.begin() + long(s + cols)));
    csv.close();
}

}  // namespace

void DeviceRecorder::write_records(const DeviceScene& scene, const DeviceState& state) const {
    std::string header = "time,stage";
    for (const dem::Tool& t : scene.tools) header += "," + t.name + "_z," + t.name + "_fx," + t.name + "_fy," + t.name + "_fz";
    write_table(out_ / "tools.csv", header, state.records.tools, tool_row_size(scene.tools.size()));
    write_table(out_ / "air.csv", "time,stage,enclosed_volume,gas_volume,dp", state.records.air, kAirColumns);
    if (scene.def.energy) write_table(out_ / "energy.csv", dem::energy_csv_header(), state.records.energy, kEnergyRowSize);
    if (state.suction.on)
        write_table(out_ / "suction.csv", "time,open,sealed,leaked,pressure_min,sealed_area,sealed_volume,force_z", state.suction.rows,
                    kSuctionColumns);
    dem::write_text_atomic((out_ / "summary.json").string(), summary_json(scene, state, device_result(scene, state)));
}

}  // namespace vpp::device_detail
