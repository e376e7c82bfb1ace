// `vppdem calibrate`: grid search of a study against a measured force-displacement loop
// (docs/studies.md, "Calibration").
//
// Misfit between a simulated and a measured record (both in SI units, compression positive,
// split into cycles; displacements shifted so that each record's smallest value is 0):
//   compared cycles C: 2 .. n with n = min(simulated cycles, measured cycles) (the stabilised
//   cycles; cycle 1 alone when n = 1), matched by index;
//   per cycle c, each branch (loading: from the cycle start to its largest displacement;
//   unloading: from there to the cycle end) of both records is sampled at `points` displacements
//   d_j = lo + (j + 1/2) (hi - lo) / points, [lo, hi] the overlap of the two branches' ranges,
//   by linear interpolation of the samples sorted by displacement;
//     rms_c    = sqrt(mean_j over both branches (F_sim(d_j) - F_exp(d_j))^2) / P_c,
//                P_c = max |F_exp| over the measured cycle;
//     energy_c = |E_sim,c - E_exp,c| / |E_exp,c|   (E: loop area, vpp::analyze_cycles);
//   misfit = mean over C of (rms_c + energy_c).
#pragma once

#include <string>
#include <vector>

#include "vpp/analysis/analysis.h"
#include "vpp/analysis/record_format.h"
#include "vpp/study/study.h"

namespace vpp {

// A measured loop's columns, units and sign convention (its cycle_col is not used: cycles are
// found from the displacement).
using ExperimentFormat = RecordFormat;

// A measured loop in SI units, compression positive, displacement shifted to start at 0 (its
// minimum), cycles found by split_cycles. Throws naming the file and column on bad input.
LoopSeries read_experiment(const std::string& path, const ExperimentFormat& f);

// Refuses (std::runtime_error naming the file and the flag to use) a measured loop whose signs
// cannot be compression positive (vpp::orientation_doubt): a calibration against a loop of the
// wrong sign would fit the wrong sign.
void check_experiment_orientation(const LoopSeries& s, const std::string& path, bool compression_negative,
                                  bool compression_first);

// A damper's forces.csv with the chosen force column ("force_zeroed" or "force_total"),
// displacement shifted like the experiment's.
LoopSeries read_simulated(const std::string& forces_csv, const std::string& force_column);

struct Misfit {
    double value = 0;
    std::vector<int> cycles;               // compared cycle indices
    std::vector<double> rms, energy;       // per compared cycle
};

Misfit loop_misfit(const LoopSeries& sim, const LoopSeries& exp, int points = 50);

struct CalibrateOptions {
    SweepOptions sweep;
    std::string experiment;
    ExperimentFormat format;
    std::string force_column = "force_zeroed";  // simulated column compared with the measured force
    int points = 50;
    bool plot = true;
    // Optional prediction: "key=v1,v2,..." run at the best grid point; experiments, when given,
    // match the values one to one and are read with the same format.
    std::string predict;
    std::vector<std::string> predict_experiments;
};

// Runs the study's cases into sweep.out_dir (default grid grains.friction 0:1:0.1 when the study
// has none), writes misfit.csv, calibration.json, experiment.csv and calibration.png.
// Returns the exit status (0 ok, 1 when cases failed or no case could be compared); on failure
// the results go to misfit_failed.csv and calibration_failed.json, and the folder's earlier
// misfit.csv, calibration.json, experiment.csv and calibration.png are left as they are.
int run_calibration(Study s, const CalibrateOptions& opt);

}  // namespace vpp
