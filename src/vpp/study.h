// `vppdem sweep`: parameter studies of the damper (docs/studies.md).
//
// A study file (TOML) holds an optional base config, fixed overrides and a grid:
//     base = "damper.toml"                 # optional, relative to the study file
//     share_preparation = true             # optional (default true)
//     [set]                                # fixed overrides for every case
//     "damper.radius" = 0.012
//     [grid]                               # every combination is one case
//     "grains.friction" = [0.0, 0.3, 0.6]  # a list, or "start:stop:step" (stop included)
//     "process.underpressure" = [0.02e6, 0.08e6]
//     seeds = 3                            # optional: an ensemble, simulation.seed = 1..3
// Cases whose grid values differ only in keys that do not act before the end of the preparation
// (vpp/settings.h, shares_preparation: grain and cap friction, process.*, output.*, analysis.*, threads) share one
// preparation: the first case of each group prepares, the others branch from its prepared.ckpt. Cases run on a pool of threads (one damper per thread, simulation.threads = 1
// unless the study sets it), and under MPI round-robin over the ranks.
#pragma once

#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/io/folder_lock.h"
#include "vpp/config.h"

namespace vpp {

// One [grid] key and its values, in the order written.
struct GridAxis {
    std::string key;                    // dotted config key, e.g. "grains.friction"
    std::vector<std::string> literals;  // TOML literals handed to --set ("0.3", "2", "\"extension\"")
    std::vector<std::string> labels;    // the values as shown in names and summary.csv ("0.3", "2", "extension")
};

struct Study {
    std::string path;                // the study file
    std::string base;                // base config path (resolved), empty: the damper's defaults
    std::vector<std::string> set;    // "key=literal" fixed overrides ([set], then --set)
    std::vector<GridAxis> grid;      // in file order
    bool share_preparation = true;
};

// Keys whose values may differ between cases sharing one preparation (the damper's --from
// accepts them): the settings table's shares_preparation (vpp/settings.h).
bool is_shareable_key(const std::string& key);

// Reads and checks a study file (ConfigError naming the key on bad input); extra_sets are
// appended to [set]. An empty [grid] (or none) gives one case.
// Ensembles: `seeds = N` (top level; or seeds_override > 0, the command line's --seeds, which
// also replaces a [grid] list of simulation.seed) adds simulation.seed = 1..N as the last grid
// key. A [grid] list "simulation.seed" = [...] is an ensemble too.
inline constexpr int kMaxSeeds = 1000;
Study load_study(const std::string& path, const std::vector<std::string>& extra_sets = {}, int seeds_override = 0);

// Index of the ensemble axis (grid key simulation.seed), -1 without one.
int seed_axis(const Study& s);

// Parses "start:stop:step" (stop included when it lies on the grid, to 1e-9 of a step);
// integers when all three are integers. Throws ConfigError naming `key`.
std::vector<double> parse_range(const std::string& key, const std::string& text, bool* integers = nullptr);

// A grid axis from command-line text: "v1,v2,..." (each a TOML value or a bare word) or a range
// "start:stop:step". Throws ConfigError naming the key.
GridAxis axis_from_text(const std::string& key, const std::string& values);

struct StudyCase {
    std::size_t index = 0;
    std::string name;                    // folder name: swept keys and values, filesystem-safe
    std::vector<std::string> labels;     // one per grid axis
    std::vector<std::string> overrides;  // all --set assignments of the case, in order
    Config config;
    int group = 0;                       // preparation group
    std::size_t preparer = 0;            // index of the case that prepares for this group
};

// Expands the grid (first key outermost) and loads every case's config (errors name the case).
std::vector<StudyCase> expand_study(const Study& s);

// One line per case: index, folder name, preparation group and whether it prepares or branches.
std::string list_cases(const std::vector<StudyCase>& cases);

struct SweepOptions {
    std::string out_dir;
    int jobs = 0;                    // concurrent cases on this process; 0: cores / threads per case
    bool quiet = false;
    double checkpoint_every = 60.0;  // [s] passed to each damper run
    int rank = 0, ranks = 1;         // MPI: this process takes the cases i with i % ranks == rank
    // Progress and cancelling for callers that embed the sweep (the Python module); the command
    // line passes none, and its outputs do not depend on it. Called from the sweep's worker
    // threads, one call at a time: after each finished case (done of this process's total cases,
    // the case's folder name; cases finished in an earlier run count too), and with an empty
    // name every 256 steps of a running case, where it must be cheap. Returning false, or
    // throwing, stops the sweep: no case starts, running cases stop at their next poll without
    // a FAILED marker, and run_sweep throws (SweepStopped, or what the hook threw) without
    // writing summary.csv. The folder stays resumable: finished cases keep their summary.json,
    // a stopped case restarts from its last run.ckpt (or from its start).
    std::function<bool(std::size_t done, std::size_t total, const std::string& name)> progress;
    // Report only (`--report-only`): run, prepare and plot nothing, touch no case folder; read
    // the cases finished in out_dir (which must exist: ConfigError naming it otherwise) as a
    // resumed sweep does, and write its tables, the other cases marked "not run". A study that
    // runs over many sessions gets its interim tables, and a newer build re-analyses old records
    // (read_finished recomputes the stationary loops) without running them again. Rank 0 alone
    // reads and writes, with no MPI call: the other ranks return at once.
    bool report_only = false;
};

// Thrown by run_sweep (and run_calibration) when SweepOptions::progress asked to stop.
struct SweepStopped : std::runtime_error {
    SweepStopped() : std::runtime_error("sweep stopped") {}
};

struct CaseOutcome {
    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    bool ok = false;
    bool skipped = false;        // finished in an earlier run of the sweep
    bool not_run = false;        // report only: no finished record in its folder (status "not run")
    std::string message;         // failure message
    double W = 0, dissipated_energy = 0, peak_force = 0;  // last cycle
    double run_seconds = 0;
    // Stationary loops (vpp/settle.h): mean W of the settled cycles (NaN: none settled), how
    // many settled, the first (0: none).
    double W_settled = kNaN;
    int settled_cycles = 0, first_settled = 0;
    // Shares of the last cycle's dissipation (energy ledger; NaN without it):
    // friction / (friction + damping + viscous), damping / (the same).
    double friction_share = kNaN, damping_share = kNaN;
    // The prepared sample: grains (after the re-fills) and the packing fraction of the foil's
    // interior up to the cap at the end of the preparation (summary.json "preparation").
    int grains = 0;
    double packing_fraction = kNaN;
    std::vector<std::string> warnings;  // the case's summary.json "warnings"
};

struct SweepResult {
    std::vector<StudyCase> cases;
    std::vector<CaseOutcome> outcomes;  // complete on rank 0 only (gathered)
    int failed = 0;                     // failed cases; report only: records that could not be read
    // out_dir's lock (rank 0; none with report_only), held as long as the result lives, so that
    // what the caller writes there afterwards (the plots, a calibration's tables) is covered too.
    dem::FolderLock lock;
};

// Runs (or resumes) the sweep into opt.out_dir: one folder per case, DIR/summary.csv,
// summary_cases.csv and, with seeds, summary_paired.csv (rank 0). With opt.report_only, only
// the tables, from the cases already finished there.
// One sweep at a time writes into a folder: rank 0 takes out_dir's lock (dem/io/folder_lock.h)
// before any rank writes there, and a folder in use is refused (dem::FolderLocked naming the
// holder; under MPI the other ranks are aborted). Each case's damper run locks its own case
// folder. A report only takes no lock: it writes its tables atomically and may run beside the
// sweep.
SweepResult run_sweep(const Study& s, const SweepOptions& opt);

// The summary.csv text, one row per run: the swept keys, then W, dissipated_energy, peak_force,
// run_seconds, status, case (the contract), then W_settled, settled_cycles, first_settled_cycle,
// friction_share, damping_share, grains, packing_fraction, warnings (docs/studies.md, "Outputs").
// status: "ok", "failed: <message>" or (report only) "not run"; the numbers of a run that did
// not finish are empty.
std::string summary_csv(const Study& s, const std::vector<StudyCase>& cases,
                        const std::vector<CaseOutcome>& outcomes);

// Quantities summarised over an ensemble, in summary_cases.csv's order.
inline const std::vector<std::string> kEnsembleQuantities = {"W", "W_settled", "peak_force", "dissipated_energy",
                                                             "friction_share", "damping_share", "packing_fraction"};

// The summary_cases.csv text, one row per case of the grid without its seed axis (all rows of
// summary.csv that differ only in simulation.seed): the other swept keys, `seeds` (runs in the
// case), `ok` (finished runs), then per quantity Q of kEnsembleQuantities `Q_n,Q_mean,Q_sd,Q_ci95`
// over the finished runs that have Q (vpp/stats.h: Student t, n - 1 degrees of freedom; ci95 the
// half width, the interval is mean +- ci95), then `cases` (the runs' folders, ';'-separated).
// A study without seeds has one run per row (n = 1: sd and ci95 empty).
std::string cases_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes);

// Quantities of summary_paired.csv, in its order.
inline const std::vector<std::string> kPairedQuantities = {"W_settled", "W", "peak_force", "dissipated_energy",
                                                           "friction_share", "damping_share"};

// The summary_paired.csv text; empty unless the study has a seed axis of 2 values or more.
// Paired differences seed by seed: for each grid axis A but the seed with 2 values or more, each
// combination of the other axes but the seed (grid order), each value v of A but the reference
// (A's first value) and each Q of kPairedQuantities, d_s = Q(v, s) - Q(reference, s) over the
// seeds s whose two runs finished with a finite Q. Columns
// `key,value,reference,group,quantity,n,diff_mean,diff_sd,diff_ci95,ref_mean,rel_diff`: group is
// the other axes as `k1=v1;k2=v2` (empty without any), n the seeds paired, then the mean, sample
// sd and 95% half width of d (vpp/stats.h; sd and ci95 empty for n < 2, every number for n = 0),
// the mean of Q at the reference over the same seeds, and diff_mean / ref_mean. The seeds of
// one case branch from that seed's sample where A shares the preparation, so the sample's own
// scatter cancels in d (docs/studies.md, "Ensembles").
std::string paired_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes);

// Rows of the ensemble table: the indices of the runs of each case (grid order), the seed axis
// left out.
std::vector<std::vector<std::size_t>> ensemble_groups(const Study& s, const std::vector<StudyCase>& cases);

// MPI helpers (no-ops without MPI or outside mpirun).
void mpi_init_if_launched(int* argc, char*** argv, int* rank, int* ranks);
void mpi_finalize();
void mpi_abort_if_active(int code);  // after an error on one rank: stop them all

}  // namespace vpp
