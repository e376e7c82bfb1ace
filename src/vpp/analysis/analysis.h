// Hysteresis-loop analysis of force-displacement records (model.md section 5 step 6): the energy
// dissipated per cycle and the damper efficiency W = energy / (pi r_p^2), for the damper's own
// DIR/forces.csv or for a measured loop read from any CSV with a header.
//
// Conventions: displacement positive in compression (downward travel of the upper cap), force
// positive in compression. A cycle goes from the start position down by the amplitude and back up.
#pragma once

#include <string>
#include <vector>

namespace vpp {

// One record; all vectors have the same length. cycle[i] is the 1-based cycle index of sample i;
// 0 (or less) means the sample belongs to no cycle (leading or trailing partial cycles found by
// the automatic split) and is ignored by analyze_cycles.
struct LoopSeries {
    std::vector<double> time, displacement, force;
    std::vector<int> cycle;
    bool cycles_from_column = false;  // cycle was read from the file, not split from the displacement
};

struct CycleResult {
    int cycle = 0;
    double dissipated_energy = 0;  // [J]  loop area, positive for a dissipative loop
    double W = 0;                  // [J/m^2] dissipated_energy / (pi radius^2)
    double peak_force = 0;         // [N]  largest force in the cycle
    double min_force = 0;          // [N]  smallest force in the cycle
    int samples = 0;               // samples of the cycle
    // The cycle ends where it started (see analyze_cycles). A record cut short (a killed run's
    // forces.csv, a measurement stopped early) has a partial last cycle: its area is not the
    // loop's (W 140 J/m^2 instead of 163 on the tests' damper).
    bool complete = true;
    // Energy budget of the cycle from the simulation's ledger (docs/energy.md); only a damper
    // run fills these (has_energy), not a loop read from a CSV file.
    bool has_energy = false;
    double friction_dissipation = 0;  // [J] Coulomb slip + loaded shear springs lost on opening
    double damping_dissipation = 0;   // [J] local damping
    double viscous_dissipation = 0;   // [J] normal dashpots
    double boundary_work = 0;         // [J] work of the cap and the top ring on the sample
    double energy_residual = 0;       // [J] input - stored change - dissipated over the cycle
    // The dissipation in rearrangement events (vpp/analysis/events.h): a damper run with the energy
    // ledger and analysis.event_threshold > 0 fills these (has_events).
    bool has_events = false;
    int events = 0;                   // bursts of kinetic energy in the cycle
    double event_fraction = 0;        // [-] share of the cycle's record intervals inside events
    double friction_in_events = 0;    // [J] of friction_dissipation, inside events
    double damping_in_events = 0;     // [J] of damping_dissipation, inside events
    double viscous_in_events = 0;     // [J] of viscous_dissipation, inside events
    // Stationarity of the loop (vpp/analysis/settle.h); only a damper run fills these (has_settled).
    bool has_settled = false;
    bool settled = false;             // W has settled by this cycle (the criterion in settle.h)
};

// Per cycle (samples grouped by their cycle index, results in increasing cycle order):
//   dissipated_energy = closed line integral of F d(displacement) over the cycle's samples, by the
//   trapezoid rule over the closed polygon (the last sample is joined back to the first):
//       E = sum_i (F_i + F_{i+1})/2 * (d_{i+1} - d_i),   i = 0..n-1, index n meaning 0.
//   E > 0 for a dissipative loop: the compression branch (d increasing) carries a larger force
//   than the release branch, i.e. the loop runs clockwise in the (displacement, force) plane.
//   Over a closed polygon this equals E = -1/2 sum_i (d_i F_{i+1} - d_{i+1} F_i), so
//   W = E / (pi radius^2) is the paper's W = 1/(2 s) * sum (dz_i F_{i+1} - dz_{i+1} F_i)
//   (s = pi r_p^2) up to the orientation sign: the paper's shoelace sum is the counter-clockwise
//   area, positive for its axis orientation (dz measured along z, i.e. compression negative) and
//   negative with ours, hence the minus sign. The result does not depend on where the loop
//   starts, nor on constant offsets of force or displacement (e.g. a zeroed force).
//   peak_force / min_force: max / min of F over the cycle's samples.
//   complete: |d_last - d_first| <= max(0.1 (d_max - d_min), 1.5 max |d_{i+1} - d_i|) over the
//   cycle's samples: it comes back to its start, to 10% of its own stroke (so cycles of any
//   amplitude qualify) or to within the last step between samples (a recorded cycle ends one
//   sample before it closes, which is a large share of the stroke with few samples per cycle).
//   A cycle cut off before about 95% of its period fails (a triangular stroke; a sinusoidal one
//   is back within 10% of its stroke from 90% of its period on).
// Cycles with fewer than 3 samples are skipped; samples with cycle <= 0 are ignored.
// Throws std::invalid_argument on vectors of different lengths or radius <= 0.
std::vector<CycleResult> analyze_cycles(const LoopSeries& s, double radius);

// Reads a CSV file whose first line (blank lines and lines starting with '#' skipped) is a
// header of column names; the named columns are picked in any order, other columns are ignored.
// Every data row must hold a number in each picked column; a file without data rows (a header
// only) throws. A missing time_col, disp_col or
// force_col throws std::runtime_error naming the missing column and listing those available;
// an empty time_col fills time with the sample index.
// The cycle index is read from cycle_col (values rounded to integers). When cycle_col is empty
// or not in the file, cycles are found by split_cycles (below).
LoopSeries read_loop_csv(const std::string& path, const std::string& time_col,
                         const std::string& disp_col, const std::string& force_col,
                         const std::string& cycle_col);

// Automatic cycle split of a displacement record, a cycle being a travel from the start position
// (the displacement minimum) to the far end (maximum) and back. With lo = min + 0.1 range and
// hi = min + 0.9 range over the whole record (so units do not matter, and noise well below 10%
// of the stroke neither splits nor merges cycles):
//  - a "return" is a stretch that starts at a sample with d <= lo reached after the record has
//    been at d >= hi (since the previous return), and lasts until the next sample with d >= hi
//    (or the end of the record);
//  - cycle boundaries are the first sample (when d[0] <= lo) and, in each return, the sample of
//    smallest displacement (its first occurrence);
//  - with boundaries b_1 < ... < b_m, cycle k (k = 1..m-1) holds the samples b_k up to, not
//    including, b_{k+1}; the last cycle also keeps its closing sample b_m (so a record that ends
//    at the bottom of its last return loses nothing). Samples before b_1 and after b_m (a cycle
//    the record does not finish, or a tail held at the start position) get index 0.
// Returns one index per sample; all 0 when the range is zero.
std::vector<int> split_cycles(const std::vector<double>& displacement);

// cycles.csv is written and read by vpp/analysis/records.h, from the one description of its columns.

}  // namespace vpp
