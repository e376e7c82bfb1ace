// The device run's state besides its World: the stage it stands at and where within it, the
// tools' programs, the air, the records so far (the rows of tools.csv, air.csv and energy.csv),
// the report and the warnings. The checkpoint (DIR/run.ckpt) carries it as its app blob
// (DeviceState::save, DeviceState::load), beside the World; its format is a contract: a
// checkpoint of an earlier vppdem resumes. Internal to vpp/device/*.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "dem/io/energy_columns.h"
#include "dem/world/tool.h"
#include "vpp/device/definition.h"
#include "vpp/membrane/air.h"

namespace vpp::device_detail {

constexpr std::size_t kToolColumns = 4;  // tools.csv per tool: z, fx, fy, fz (after time, stage)
constexpr std::size_t kAirColumns = 5;   // air.csv: time, stage, enclosed, gas, dp
constexpr std::size_t kEnergyRowSize = dem::kEnergyColumns.size();  // energy.csv (dem/io/energy_columns.h)
// suction.csv: time, open, sealed, leaked, pressure_min, sealed_area, sealed_volume, force_z
constexpr std::size_t kSuctionColumns = 8;

// [-] the columns of a tools.csv row for `tools` tools
inline std::size_t tool_row_size(std::size_t tools) { return 2 + kToolColumns * tools; }

// The stage to run and where it stands; a checkpoint within a stage resumes from it. All but
// the stage and its start are reset by the next stage (stages::next_stage).
struct StagePosition {
    int32_t stage = 0;        // DeviceStage: the stage to run next
    double t0 = 0;            // [s] its start
    double next_check = 0;    // [s] the fill's next rest check (0: not set)
    int64_t free_steps = 0;   // [-] load: steps the object has been free
    int32_t tools_done = 0;   // vacuum: the tools' segments were done at the last step
};

// The forces on the tools summed over the steps since the last row (tools.csv averages them).
struct SampleWindow {
    std::vector<double> sums;  // [N] per tool fx, fy, fz
    int64_t steps = 0;         // [-] steps in the window
};

// The records so far, row after row.
struct Records {
    std::vector<double> tools;   // tools.csv (tool_row_size columns)
    std::vector<double> air;     // air.csv (kAirColumns)
    std::vector<double> energy;  // energy.csv (kEnergyRowSize)
};

// The suction (suction.enabled, vpp/device/suction.h): the seal on result.object, captured at the
// load stage's start, and the rows of suction.csv; `last` is the seal's latest step (not in the
// checkpoint: every step recomputes it before it is read).
struct SuctionState {
    int32_t on = 0;                // the seal is captured and stepped
    SuctionSeal seal;
    std::vector<double> rows;      // suction.csv (kSuctionColumns)
    SuctionStep last;
};

struct DeviceState {
    StagePosition at;
    int32_t sealed = 0;                    // pressure fans and air on
    MembraneGas gas;                       // the air inside (from the seal on)
    std::vector<dem::ToolState> tools;     // where each tool's program stands
    SampleWindow window;
    Records records;
    // What the stages measured for summary.json: "volume_seal", "volume_press", "volume_vacuum",
    // "fill_settled", "fill_time", "membrane_z_min", "released", "cycle_t0", "cycle_d0", the pour's
    // "grains_spilled", "grains_removed_at_seal", "seal_max_overlap".
    std::map<std::string, double> report;
    std::vector<std::string> warnings;     // every warning of the run so far (a resumed run's too)
    std::string inputs;                    // the device's inputs (inputs_text) the run was started with
    int64_t vtk_frames = 0;                // [-] frames written at output.vtk_interval
    SuctionState suction;                  // in a section of its own that only such runs' checkpoints have

    // The checkpoint's app blob, bit for bit what load() reads back.
    std::string save() const;
    // Reads save()'s blob; throws std::runtime_error naming the checkpoint's `path` on damaged
    // data or a stage out of range.
    static DeviceState load(const std::string& blob, const std::string& path);

private:
    template <class A, class S> static void fields(A& a, S& r);
};

// A new run's state for device `d` with `tools` tools [-].
DeviceState fresh_state(const DeviceDef& d, std::size_t tools);

// The device's inputs (device_inputs) as text, its file's path left out: the same device from
// another folder resumes; a checkpoint of other inputs is refused.
std::string inputs_text(const DeviceDef& d);

}  // namespace vpp::device_detail
