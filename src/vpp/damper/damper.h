// `vppdem damper`: the VPP damper end to end (paper section 4; spec sections 5-7).
//   prepare: foil cylinder, grains generated in the foil and a funnel above it, frictionless
//            fall, upper cap down to the damper height, funnel removed  -> prepared.ckpt
//   vacuum:  grain friction restored, dp ramped up, sample brought to rest
//   cycle:   upper cap and top foil ring moved together, triangular displacement
//   record:  forces.csv (grains on the cap, foil on the top ring), cycles.csv, summary.json
// vpp::Damper runs these stages one call at a time (the Python module drives it); run_damper()
// runs them all and writes the outputs. The code lives in damper/scene.cpp (the damper's world
// and its parts), damper/stages.cpp (the stages), damper/run.cpp (the run that composes them),
// damper/recorder.cpp (every file of the output folder) and damper/record.cpp (result, summary,
// report); damper/run.h lists them all.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dem/world/world.h"

namespace dem::batch {
class BatchStepper;
}
#include "vpp/analysis/analysis.h"
#include "vpp/settings/config.h"
#include "vpp/analysis/settle.h"

namespace vpp {

struct DamperOptions {
    std::string out_dir;
    std::string from;        // checkpoint to start from (prepared.ckpt or run.ckpt); empty: prepare
    bool quiet = false;
    bool plot = true;
    bool overwrite = false;  // replace files in a non-empty out_dir (resuming from it needs none)
    double checkpoint_every = 60.0;  // [s] wall clock between run.ckpt writes
    bool profile = false;    // print the time per phase of the cycling (dem/core/profile.h)
    double progress_every = 0;  // [s] between progress lines; 0: 2 s on a terminal, 30 s in a log
    // Called every 256 steps of each stage with the stage's name, its steps done (never less
    // than at the call before within one stage name) and expected (the most it can take for the
    // stages that end when the sample is at rest: "prepare: fill", each "prepare: re-fill N",
    // "vacuum") and the simulated time [s]. It may throw to stop the run (the Python module does on Ctrl-C); the exception
    // leaves the stage where it stood. Empty: none (the results do not depend on it).
    std::function<void(const char* stage, uint64_t done, uint64_t total, double time)> progress;
    // The cycling stage's steps go to this batch, in lockstep with the other runs it holds (sweep
    // --backend batch, docs/gpu.md); nullptr: the run steps its World itself. The results are the
    // same bits.
    dem::batch::BatchStepper* batch = nullptr;
    // From a prepared.ckpt: refuse it when a key that acts during the preparation
    // (preparation_settings(): stiffnesses, foil, damping, time step) differs from the config's.
    // A study's branches set it: a case must not branch from a sample its settings did not
    // prepare (an earlier sweep into the same folder). By hand (--from) a sample may be cycled
    // with other settings on purpose (the time-step study), so it is off there.
    bool check_preparation = false;
};

// The air over one cycle (pump model or output.air; summary.json "air"): what the testing
// machine sees, grains + foil + the lid's -dp A (forces.csv force_machine_zeroed), and the
// underpressure's excursion. With a constant dp the lid adds a constant and W_machine is W.
struct AirCycle {
    int cycle = 0;
    double W_machine = 0;           // [J/m^2] loop area of force_machine_zeroed / (pi radius^2)
    double peak_force_machine = 0;  // [N] largest force_machine_zeroed in the cycle
    double min_force_machine = 0;   // [N] smallest force_machine_zeroed in the cycle
    double underpressure_min = 0;   // [Pa] smallest dp at a sample of the cycle
    double underpressure_max = 0;   // [Pa] largest dp at a sample of the cycle
    double underpressure_mean = 0;  // [Pa] mean dp over the cycle's samples: the dp the cycle had
    double gas_volume_min = 0;      // [m^3]
    double gas_volume_max = 0;      // [m^3]
};

// forces.csv as a table: its column names (vpp/analysis/records.h, sample_columns(); the air's with the
// air record) and one row per sample, the same numbers the file holds.
struct ForcesTable {
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
};

struct DamperResult {
    std::size_t grains = 0, foil_particles = 0, bonds = 0;
    int foil_columns = 0, foil_rows = 0;  // the lattice's (0 for the mesh foil)
    double foil_radius = 0, height = 0, dt = 0;
    // The mesh foil (foil.builder = "mesh"): its vacancies and its bonds' mean kn [N/m].
    std::size_t foil_vacancies = 0;
    double foil_bond_kn_mean = 0;
    // The lattice foil: the distance between neighbouring columns' sites [m] (its row bonds' rest
    // length: 2 r_f, or the chord at foil.exact_radius) and the kn [N/m] of its row (hoop) and
    // column (axial) bonds.
    double foil_column_pitch = 0, foil_bond_kn_hoop = 0, foil_bond_kn_axial = 0;
    double inertial_number = 0;
    std::vector<CycleResult> cycles;  // with the stationarity flag (settled) of each
    std::vector<AirCycle> air;        // per cycle, when the run recorded the air (else empty)
    double underpressure_held = 0;    // [Pa] mean dp over every cycle's samples (air recorded; else 0)
    Settling settling;                // analysis.settle_tolerance applied to the cycles' W
    // The preparation and the start of cycling as measured ("prepare.cap_force",
    // "cycle.packing_fraction", ...; summary.json "preparation", "start_of_cycling").
    std::map<std::string, double> report;
    // Every warning of the run, the preparation's included (summary.json "warnings").
    std::vector<std::string> warnings;
    // The run stepped through every cycle asked but recorded fewer complete ones (samples fell
    // behind the time step, a period shorter than a few steps): warned in summary.json, and
    // `vppdem damper` exits 1, a study's case fails (summary.json "cycles" holds what ran).
    bool incomplete = false;
    double run_seconds = 0;
    // The settings the run used: a run from a checkpoint takes some of its values. (Set by the
    // run; unread until then, as reading the defaults samples the machine's cores: Config::unread.)
    Config config = Config::unread();
};

// What a checkpoint records of the sample in it, read once (a study matches one file against
// many cases): whether it is a prepared sample (stage "prepared") and the numbers of the keys
// that shaped it, the geometry (an older vppdem's missing keys at their legacy values) and the
// keys acting during the preparation (those an older vppdem did not record are absent). Throws
// std::runtime_error when the file cannot be read.
struct SampleRecord {
    bool prepared = false;
    std::map<std::string, double> keys;
};
SampleRecord read_sample_record(const std::string& checkpoint);

// Whether the sample is one `c` would have prepared: "" when it fits, else why not (not a
// prepared sample, a geometry key, or with `preparation_keys` a key that acts during the
// preparation, each with both values). A study takes its samples from another study's folder by
// it (Study::samples_from).
std::string sample_misfit(const Config& c, const SampleRecord& sample, bool preparation_keys);

// With opt.from: the checkpoint's geometry replaces the config's (a geometry key the config
// gives with another value is an error), and a checkpoint of a run that started (run.ckpt past
// the preparation) also gives its contact, process and simulation settings (kRunKeys in
// damper/stored_settings.cpp; a key given with another value is an error naming both values).
DamperResult run_damper(const Config& c, const DamperOptions& opt);

// One recorded sample of the cycling: the forces averaged over process.sample_window before it.
struct DamperSample {
    double time;          // [s] simulated time of the sample
    double displacement;  // [m] cap travel from the cycling start position, compression positive
    double grains;        // [N] grains on the upper cap, compression positive
    double foil;          // [N] foil on the top ring
};

// The air inside at a sample (recorded with process.pressure_model = "pump" or output.air; the
// columns of forces.csv after `cycle`): the state of the step the sample is taken at.
struct DamperAirSample {
    double enclosed;    // [m^3] volume bounded by the foil (through its particles' centres) and the caps
    double gas;         // [m^3] enclosed minus the grains' volume
    double p_inside;    // [Pa] absolute pressure of the gas
    double dp;          // [Pa] underpressure, atmospheric minus p_inside
    double lid_area;    // [m^2] area inside the top ring, on which dp pushes the lid
    double gas_work;    // [J] work done by the gas on its enclosure since the first sample
};

namespace damper_detail {
class DamperRun;
}

// The damper run as an object: its stages one call at a time. run_damper() is
//   Damper d(c, opt); d.prepare(); d.vacuum(); d.cycle(); write_damper_outputs(d, opt) ...
// so a caller that runs the same stages gets the same records bit for bit. With an empty
// opt.out_dir it writes no file (no checkpoint, no VTK frame) unless asked (save()).
class Damper {
public:
    // Builds the damper's world from the config, or loads opt.from (prepared.ckpt, run.ckpt, or
    // a save()) as run_damper() does: the checkpoint's geometry and, for a run that started,
    // its settings replace the config's.
    Damper(const Config& c, const DamperOptions& opt);
    ~Damper();
    Damper(Damper&&) noexcept;
    Damper& operator=(Damper&&) noexcept;

    // The stages; each runs what comes before it when that has not run yet, and does nothing
    // when the run is past it.
    void prepare();       // fill and compress: the prepared sample (prepared.ckpt in out_dir)
    void vacuum();        // dp ramped up, sample brought to rest
    // Runs n more cycles (n < 0: all of process.cycles that remain); the cycle's motion is laid
    // out for process.cycles at the start of cycling, so n may not exceed what remains (throws
    // std::runtime_error saying so). Returns the cycles done so far.
    int cycle(int n = -1);

    // Replaces DamperOptions::progress for the stages to come.
    void set_progress(std::function<void(const char*, uint64_t, uint64_t, double)> hook);

    void save(const std::string& path) const;  // a checkpoint Damper(c, {.from = path}) continues
    std::string stage() const;                 // "fill", "compress", "prepared", "vacuum", "cycle", "done"
    int cycles_done() const;
    int cycles_total() const;                  // process.cycles
    const std::vector<DamperSample>& samples() const;
    // The air at each sample when it is recorded (pump model or output.air), else empty.
    const std::vector<DamperAirSample>& air() const;
    // forces.csv's columns and rows as the run has them so far (the Python module's arrays).
    ForcesTable forces() const;
    // The energy ledger at each sample (rows of energy.csv, columns energy_columns(); [s] then
    // [J]); empty with output.energy = false.
    std::vector<std::vector<double>> energy() const;
    static std::vector<std::string> energy_columns();
    // The records analysed: cycles (W, dissipation split), settling, the preparation's report,
    // and the warnings of summary.json (not quasi-static, W not stationary).
    DamperResult result() const;
    void write_records(const std::string& dir) const;  // forces.csv and energy.csv into dir
    const dem::World& world() const;
    const Config& config() const;  // the settings in use (a checkpoint's replace the given ones)

private:
    std::unique_ptr<damper_detail::DamperRun> run_;
};

// Writes forces.csv, energy.csv, cycles.csv and summary.json of the damper into opt.out_dir
// (the one the damper was made with) and returns its result().
DamperResult write_damper_outputs(const Damper& d, const DamperOptions& opt);

// summary.json's text for this result (of write_damper_outputs); `from` is opt.from.
std::string damper_summary_json(const DamperResult& r, const std::string& from);

// Number of grains for the volume fraction: round(phi * pi r_p^2 H_p / (4/3 pi r_k^3)).
std::size_t grain_count(const Config& c);

// Inertial number I = gamma_dot d sqrt(rho / p) of the cycling: gamma_dot = v_z / H,
// d = 2 r_k, p = dp.
double inertial_number(const Config& c, double height);

// [-] Below this inertial number a run counts as quasi-static (summary.json "quasi_static"; a
// warning above it). Calibrated on the paired velocity-convergence runs (docs/studies.md,
// "Velocity convergence: results"): in the first cycle, wherever I < 5e-4, W lay within the
// paired 95% interval of the slowest velocity run and within 8% of it; above it W was 12-45%
// higher wherever the difference was resolved (local damping of the grains' and the foil's
// motion grows with the loading rate). Later cycles drift more: no difference below the mark
// was resolved with 2-3 seeds, but the paper's damper at 0.06 MPa lost 11-12% of W in cycle 2
// from 0.02 to 0.01 m/s in both seeds (and nothing from 0.01 to 0.005 m/s). The former mark,
// 1e-3, let runs with W 12-16% too high in the first cycle pass as quasi-static.
inline constexpr double kQuasiStaticInertialNumber = 5e-4;

// [-] The pump model warns when a cycle's mean dp falls more than this fraction below
// process.underpressure: W grows with dp (docs/paper_comparison.md, C1), so a run 5% short is
// not a run at the set value.
inline constexpr double kUnderpressureShortfall = 0.05;

}  // namespace vpp
