// The damper run's parts shared by its files; internal to vpp/damper_*.cpp:
//   damper_world.cpp   the damper's world: foil, grains, caps, funnel; the input's checks; a
//                      checkpoint's geometry and settings; the settings applied to a sample
//   damper_stages.cpp  the protocol: fill, compress, vacuum, cycle; vpp::Damper
//   damper_record.cpp  the record: checkpoint state, forces.csv's and energy.csv's tables, summary.json, report
//   damper_recorder.h  the recorder: the output folder and every file written into it (DamperRecorder)
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "scene/progress.h"
#include "dem/io/energy_columns.h"
#include "dem/world/world.h"
#include "vpp/damper.h"
#include "vpp/damper_recorder.h"
#include "vpp/damper_state.h"
#include "vpp/foil.h"
#include "vpp/gas.h"
#include "vpp/membrane.h"

namespace vpp::damper_detail {

namespace fs = std::filesystem;
using dem::Vec3;

// Material indices in the damper world (the foil is built first, so its material is 0).
constexpr uint32_t kFoilMat = 0, kGrainMat = 1, kCapMat = 2, kFunnelMat = 3;
constexpr uint32_t kBottomCap = 0, kTopCap = 1;  // plane indices

// The terminal's progress line and the caller's hook (DamperOptions::progress).
class StageProgress {
public:
    StageProgress(const char* stage, uint64_t total, const DamperOptions& o)
        : prog_(stage, total, o.quiet), stage_(stage), total_(total), hook_(o.progress) {}
    void update(uint64_t done, double sim_time) {
        prog_.update(done, sim_time);
        // Every 256 steps, as often as the progress line looks at the clock: the hook may take
        // a lock (the Python interpreter's) and must not slow the steps down.
        if (hook_ && !(done & 255u)) hook_(stage_, done, total_, sim_time);
    }

private:
    scene::Progress prog_;
    const char* stage_;
    uint64_t total_;
    const std::function<void(const char*, uint64_t, uint64_t, double)>& hook_;
};

class DamperRun {
public:
    // Builds the world, or loads o.from (damper_world.cpp).
    DamperRun(const Config& c, const DamperOptions& o);
    // The stages (damper_stages.cpp): see vpp::Damper.
    void prepare();
    void vacuum();
    int cycle(int n);
    int cycles_done() const;
    // The record (damper_record.cpp).
    void save(const std::string& path) const;
    DamperResult result() const;
    void write_records(const std::string& dir) const;
    const dem::World& world() const { return world_; }
    const Config& config() const { return config_; }
    const DamperOptions& options() const { return options_; }
    void set_progress(std::function<void(const char*, uint64_t, uint64_t, double)> hook) { options_.progress = std::move(hook); }

private:
    void setup();
    void adopt_checkpoint_settings();
    void check_grains_fit(std::size_t n);
    // The process against the built foil (its height z_top_): refuses a stroke the sample cannot
    // take and a pump-down that would not end; returns the warnings of values that are accepted
    // but do not do what they seem to (docs/config.md, "Limits from the physics").
    std::vector<std::string> check_process() const;
    // The sampling against the time step (known once the world is built): warnings; with
    // `refuse`, sampling faster than the time step is refused (a fresh run, before writing).
    std::vector<std::string> check_sampling(bool refuse) const;
    // The time step against the contacts and the process (known once the world is built): a step
    // that is no number, a fixed step beyond the stable one, a run of more steps than any machine
    // finishes are refused (a new run or a branch, before writing).
    void check_steps() const;
    // Warns what is not yet among the run's warnings (a resumed run has its first start's).
    void warn_once(const std::vector<std::string>& what);
    // n radii from the size distribution's stream `stream` (0: the pour, k: re-fill k).
    std::vector<double> draw_radii(std::size_t n, uint64_t stream) const;
    // The drawn radii's statistics into the preparation's report (size distributions only).
    void report_grain_sizes();
    // Grains at these centres with these (volume-equivalent) radii: spheres, or clumps of
    // grains.shape in random orientations from stream `stream` (0: the pour, k: re-fill k).
    void add_grains(const std::vector<Vec3>& pos, const std::vector<double>& radii, uint64_t stream);
    // Grains in the world: clumps, or the spheres first_grain_ .. end_grain_.
    std::size_t grain_count_now() const { return clumps() ? world_.clumps().size() : std::size_t(end_grain_ - first_grain_); }
    bool clumps() const { return config_.grains.shape != 0; }
    // The reach of a grain of volume-equivalent radius r from its centre [m] (r for spheres).
    double grain_reach(double r) const { return clumps() ? r * shape_.bounding_radius : r; }
    // Per grain: its volume-equivalent radius [m], its top (highest point) [m]; the grains'
    // volume [m^3] and mass [kg].
    std::vector<double> grain_radii() const;
    std::vector<double> grain_tops() const;
    double grains_volume_now() const;
    double grains_mass() const;
    void build();
    void apply_config_to_prepared();
    void stage_fill();
    void stage_compress();
    void stage_vacuum();
    // Cycles until the end of cycle `upto` (of process.cycles; the run is bitwise the same
    // however the cycles are split into calls).
    void stage_cycle(int upto);
    // The cap's and the top ring's knots of cycles k0 .. k1 - 1 and the end of cycle k1, from the
    // start positions cap0, ring0 [m] (the knot at the start of cycle k0 too when first_knot).
    void lay_out_cycles(dem::Motion& cap, dem::Motion& ring, double cap0, double ring0, int k0, int k1,
                        bool first_knot) const;
    // A resumed run given more cycles (process.cycles) than the `from` it started with: the
    // further cycles' knots, and a finished run cycling again.
    void extend_cycling(int from);
    // run.ckpt when the recorder's clock says one is due (or `force`), and while cycling
    // forces.csv and energy.csv with it.
    void checkpoint(bool force);
    // The run settings (kRunKeys) of this run's config: what it applies, or has applied, to
    // its prepared sample.
    std::map<std::string, double> run_settings() const;
    void save_prepared();
    // The next VTK frame of the world as it stands (the batch stepper's state synced first).
    void vtk_frame(const char* tag);
    double top_ring_force_z() const;
    // The foil's builder (foil.builder): the lattice (lattice_, the paper's) or the mesh membrane (membrane_).
    bool mesh_foil() const { return config_.damper.foil_builder == 1; }
    // The mesh foil's definition from the config: the paper's rules carried to the membrane
    // (docs/membrane.md, "A cylinder given as a mesh").
    MembraneDef membrane_def() const;
    // The pressure's nodes (lattice) or fans (mesh) on the foil, from the vacuum on.
    void set_foil_pressure();
    // Volume enclosed by the foil closed by flat caps through its end rings [m^3].
    double foil_volume() const;
    void next_stage(Stage s);
    // Re-fill (damper.refill): adds grains above the settled ones when their level is below the
    // damper height; returns false when the level is reached (or re-filling is off or exhausted).
    bool refill();
    double fill_level() const;
    double highest_grain_top() const;
    double packing_fraction(double inner_radius, double height) const;
    void record_start_of_cycling(const Sample& first);
    // The air (docs/damper.md, "The air inside"). air_recorded(): the pump model, or output.air.
    bool air_recorded() const { return config_.process.pressure_model != 0 || config_.output.air; }
    // Before each step of the vacuum and the cycling: the gas volume from the foil's shape as it
    // stands, the gas's work over the last step, and with the pump model the gas advanced by
    // the step and the step's dp (the regulator set to the underpressure dp_set [Pa]).
    void air_step(double dp_set);
    AirSample air_sample() const;
    double lid_area() const;
    double grain_volume() const;
    // Logs a warning and keeps it for summary.json (and the checkpoints, so branches and
    // resumed runs report it too).
    void warn(const std::string& what);
    // Settling checks fall at fixed times after the stage start (every `check` seconds), so a
    // resumed run takes its decisions at the same steps as an uninterrupted one.
    double next_check_after(double t, double check) const {
        return state_.stage_t0 + check * (std::floor((t - state_.stage_t0) / check) + 1.0);
    }
    // Energy scale of the rest criteria [J]: every grain lifted by one diameter, N m g 2 r_k.
    // With a size distribution: the grains' total mass, the mean diameter.
    double settle_energy_scale() const {
        if (sizes_.kind == scene::SizeDistribution::Kind::Single)
            return double(grain_count_now()) * world_.particles.mass[first_grain_] * 9.81 * 2.0 * config_.grains.radius;
        return grains_mass() * 9.81 * 2.0 * config_.grains.radius;
    }
    void log(const char* fmt, ...) const;

    Config config_;
    scene::SizeDistribution sizes_;  // what the fill and re-fills draw the radii from (setup())
    dem::ClumpShape shape_;          // grains.shape > 0: the clump at a volume-equivalent radius of 1 m
    DamperOptions options_;
    DamperRecorder recorder_;  // the output folder (out_dir) and every file written into it
    dem::World world_;
    // The lattice foil; with the mesh foil only its radius, spacing, material and particles are
    // set (rows and cols 0), which the grains, funnel and checks read alike.
    FoilLattice lattice_;
    Membrane membrane_;                        // the mesh foil (foil.builder = "mesh"); empty otherwise
    std::vector<uint32_t> bottom_ring_; // the foil's end ring on the base (fixed)
    std::vector<uint32_t> free_foil_;   // the foil's particles off both end rings
    RunState state_;
    uint32_t first_grain_ = 0, end_grain_ = 0;  // the grains' particle range (clumps: their members)
    double z_top_ = 0;          // [m] top ring / cap height after preparation
    std::vector<uint32_t> top_ring_;
    mutable double grain_volume_ = 0;  // [m^3] grain_volume()'s sum, once the grains are final
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::vector<std::string> pending_warnings_;  // found before the checkpoint's state is loaded
    // The process's and the sampling's warnings (check_process, check_sampling): given from the
    // vacuum on, so that prepared.ckpt, which cases of other process settings share, holds none.
    std::vector<std::string> process_warnings_;
    std::size_t ckpt_grains_ = 0;               // grains stored in the --from checkpoint (0: unknown)
    int ckpt_cycles_ = 0;  // a resumed run's process.cycles when the command line raises it (0: not raised)

public:
    const RunState& state() const { return state_; }
    ForcesTable forces() const { return forces_table(state_, int(config_.process.samples_per_cycle)); }  // forces.csv's
    ForcesTable energy() const { return energy_table(state_); }  // energy.csv's (no rows before cycling)
};

}  // namespace vpp::damper_detail
