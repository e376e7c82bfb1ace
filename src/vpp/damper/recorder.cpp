// The damper run's recorder (damper/recorder.h): the output folder, its lock and clearing, the
// checkpoints, forces.csv, energy.csv, cycles.csv, summary.json and the VTK frames. Each file's name, content and atomic
// write (PATH.part renamed to PATH) are contracts: tests compare them byte for byte and resumed
// runs load the checkpoints bit for bit.
#include "vpp/damper/recorder.h"

#include <cstdio>
#include <system_error>
#include <vector>

#include "scene/build_info.h"
#include "scene/scene_runner.h"
#include "dem/io/checkpoint.h"
#include "dem/io/csv.h"
#include "dem/io/vtk.h"
#include "vpp/membrane/membrane.h"
#include "vpp/analysis/records.h"

namespace vpp::damper_detail {

namespace fs = std::filesystem;

namespace {

// Everything a damper run writes into its folder (docs/damper.md, "Outputs"). --overwrite
// removes all of it before a new run starts, so nothing of the previous run (an energy.csv the
// new run does not write, a prepared.ckpt of another sample) is left beside the new results.
// Other files in the folder (notes, a sweep's case.toml) are left alone.
const char* const kDamperFiles[] = {"forces.csv",   "cycles.csv", "energy.csv",      "summary.json",
                                    "prepared.ckpt", "run.ckpt",  "loops.png",       "loops_total.png",
                                    "loops_foil.png", "loops_grains.png", "energy_split.png"};

void remove_previous_outputs(const fs::path& dir, const std::string& spare) {
    std::error_code ec;
    auto remove = [&](const fs::path& p) {
        if (!fs::exists(p)) return;
        if (!spare.empty() && fs::equivalent(p, spare, ec)) return;  // the checkpoint this run starts from
        fs::remove(p);
    };
    for (const char* f : kDamperFiles) {
        remove(dir / f);
        remove(dir / (std::string(f) + ".part"));
    }
    if (!fs::is_directory(dir / "vtk")) return;
    std::vector<fs::path> frames;
    for (const auto& e : fs::directory_iterator(dir / "vtk")) {
        const std::string n = e.path().filename().string();
        if (e.is_regular_file() && n.starts_with("damper_") && (n.ends_with(".vtk") || n.ends_with(".vtk.part")))
            frames.push_back(e.path());
    }
    for (const fs::path& f : frames) fs::remove(f);
}

// A table as CSV at `path`: its column names joined by commas as the header, a row per line.
void write_table(const fs::path& path, const ForcesTable& t) {
    std::string header;
    for (const std::string& c : t.columns) header += (header.empty() ? "" : ",") + c;
    dem::CsvWriter csv(path.string(), header);
    for (const std::vector<double>& row : t.rows) csv.row(row);
    csv.close();
}

}  // namespace

void DamperRecorder::open(bool resuming, bool overwrite, const std::string& from) {
    if (!files_) return;
    // The folder's lock first, for the life of the run (docs/damper.md, "One run per folder"):
    // a second run into a folder in use is refused before --overwrite removes the first one's
    // files.
    if (resuming) {
        lock_ = scene::lock_output_dir(out_.string());
        scene::record_build(out_.string(), false);  // another build resuming the run is listed
        return;
    }
    lock_ = scene::prepare_output_dir(out_.string(), overwrite);
    if (overwrite) remove_previous_outputs(out_, from);
}

bool DamperRecorder::checkpoint_due(bool force, double every) {
    if (!files_) return false;
    const auto now = std::chrono::steady_clock::now();
    if (!force && std::chrono::duration<double>(now - last_ckpt_).count() < every) return false;
    last_ckpt_ = now;
    return true;
}

void DamperRecorder::save_run(const dem::World& world, const std::string& blob) const {
    save_world((out_ / "run.ckpt").string(), world, blob);
}

void DamperRecorder::save_prepared(const dem::World& world, const std::string& blob) const {
    save_world((out_ / "prepared.ckpt").string(), world, blob);
}

void DamperRecorder::save_world(const std::string& path, const dem::World& world, const std::string& blob) {
    if (world.pressure.fans.empty()) {
        dem::save_checkpoint(path, world, blob);
        return;
    }
    // The fans follow from the foil, which the config rebuilds (bit for bit): saved without them.
    save_checkpoint_without_fans(path, const_cast<dem::World&>(world), blob);
}

void DamperRecorder::vtk_frame(const dem::World& world, const char* tag) {
    if (!files_) return;
    fs::create_directories(out_ / "vtk");
    char name[96];
    std::snprintf(name, sizeof name, "damper_%04d_%s.vtk", vtk_count_++, tag);
    dem::write_particles_vtk((out_ / "vtk" / name).string(), world, true);
}

void DamperRecorder::write_forces(const fs::path& dir, const ForcesTable& forces) {
    write_table(dir / "forces.csv", forces);
}

void DamperRecorder::write_energy(const fs::path& dir, const ForcesTable& energy) {
    if (energy.rows.empty()) return;  // no ledger recorded (before cycling): no energy.csv
    write_table(dir / "energy.csv", energy);
}

void DamperRecorder::write_records(const ForcesTable& forces, const ForcesTable& energy) const {
    write_forces(out_, forces);
    write_energy(out_, energy);
}

void DamperRecorder::write_cycles(const fs::path& dir, const std::vector<CycleResult>& cycles) {
    write_cycles_csv((dir / "cycles.csv").string(), cycles);
}

void DamperRecorder::write_summary(const fs::path& dir, const std::string& summary_json) {
    dem::write_text_atomic((dir / "summary.json").string(), summary_json);
}

}  // namespace vpp::damper_detail
