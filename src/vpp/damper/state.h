// The damper run's state besides its World: the stage it stands at, the samples and the ledger
// recorded so far, the air, the geometry and settings the run is bound to, the report and the
// warnings; stored as a checkpoint's app blob (RunState::save, RunState::load), and the tables
// forces.csv and energy.csv read from it. Internal to vpp/damper_*.cpp (and its tests).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "dem/io/energy_columns.h"
#include "vpp/damper/damper.h"

namespace vpp::damper_detail {

enum class Stage : int { Fill = 0, Compress = 1, Prepared = 2, Vacuum = 3, Cycling = 4, Done = 5 };
inline const char* stage_name(Stage s) {
    static const char* n[] = {"fill", "compress", "prepared", "vacuum", "cycle", "done"};
    return n[int(s)];
}

using Sample = DamperSample;
using AirSample = DamperAirSample;

// One row of energy.csv (the ledger at a forces.csv sample; its columns dem::kEnergyColumns,
// dem/io/energy_columns.h; docs/energy.md). Kept in the checkpoint's run state as 11 doubles.
constexpr std::size_t kEnergyRowSize = dem::kEnergyColumns.size();
static_assert(kEnergyRowSize == 11, "a new energy.csv column changes the damper's run state in its checkpoint");
struct EnergyRow {
    double v[kEnergyRowSize];
};


EnergyRow energy_row(const dem::EnergyLedger& L, double time);

// Everything besides the World that a resumed run needs; stored as the checkpoint's app blob.
struct RunState {
    Stage stage = Stage::Fill;
    double stage_t0 = 0;        // [s] simulated time the stage began
    double cap_d0 = 0;          // [m] top-cap z displacement at the start of the stage
    double cycle_t0 = 0;        // [s] start of cycling
    double window_grains = 0, window_foil = 0;  // force sums over the current sample window
    long window_n = 0;
    std::vector<Sample> samples;
    std::vector<EnergyRow> energy;  // the ledger at each sample (rows of energy.csv)
    // The air inside (recorded with the pump model or output.air; vpp/membrane/gas.h): the gas amount
    // p V [Pa m^3] (pump model; 0 until the vacuum stage seals the foil at atmospheric
    // pressure), the gas volume of the step before [m^3] (0: none yet), the gas's work since
    // the first sample [J], and the air at each sample.
    double gas_amount = 0;
    double gas_volume = 0;
    double gas_work = 0;
    std::vector<AirSample> air;
    // Geometry the prepared sample was made with: a --from run must match it.
    std::map<std::string, double> geometry;
    // Contact, process and simulation settings the run started with (kRunKeys), recorded when
    // they are applied to the prepared sample; empty before that (prepared.ckpt). A resumed run
    // continues with these.
    std::map<std::string, double> settings;
    // Grains in the sample (the pour and its re-fills); 0 in a checkpoint of an older vppdem,
    // whose sample holds grain_count(config) grains.
    std::size_t grains = 0;
    // What the preparation and the start of cycling measured (the "preparation" and
    // "start_of_cycling" objects of summary.json), e.g. "prepare.cap_force".
    std::map<std::string, double> report;
    // Every warning of the run so far, the preparation's included: a branch from prepared.ckpt
    // and a resumed run report them too (summary.json "warnings").
    std::vector<std::string> warnings;

    // The checkpoint's app blob: the run-state archive of the World's sections
    // (dem/io/archive.h), bit for bit what load() reads back.
    std::string save() const;
    // The blob of the state as a prepared sample: save() without the run settings, so that a run
    // from it takes the settings it is given (prepared.ckpt, and a Damper saved at that stage).
    std::string save_as_sample() const;
    // Reads save()'s blob, or the key/value text of checkpoints written before vppdem kept all
    // run state in one format (load_text). Throws std::runtime_error naming the checkpoint's
    // path on damaged data, an unknown entry, a value that is not a number, or a stage outside
    // Stage.
    static RunState load(const std::string& blob, const std::string& path);
    static RunState load_text(const std::string& text, const std::string& path);

private:
    template <class A, class S> static void fields(A& a, S& r);
};

// The air's records are written when every sample has one (pump model or output.air; a run
// that turned output.air on when resumed has none for its first samples and writes none).
bool air_complete(const RunState& state);

// forces.csv's table from the state's samples (and the air's columns when every sample has its
// air), cycles counted by samples_per_cycle [-].
ForcesTable forces_table(const RunState& state, int samples_per_cycle);
// energy.csv's table from the state's ledger rows (no rows before cycling), with the gas's work
// when every sample has its air.
ForcesTable energy_table(const RunState& state);

}  // namespace vpp::damper_detail
