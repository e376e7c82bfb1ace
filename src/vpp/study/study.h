// `vppdem sweep`: parameter studies of the damper (docs/studies.md). The study file and its
// cases are vpp/study/file.h, the outcomes and tables vpp/study/records.h, MPI vpp/study/mpi.h;
// here the scheduler: cases run on a pool of threads (one damper per thread, simulation.threads
// = 1 unless the study sets it), preparers first, branches when their preparation is written,
// and under MPI round-robin over the ranks.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/io/folder_lock.h"
#include "vpp/study/file.h"
#include "vpp/study/mpi.h"
#include "vpp/study/records.h"

namespace dem::batch {
class BatchStepper;
}

namespace vpp {

struct SweepOptions {
    std::string out_dir;
    int jobs = 0;                    // concurrent cases on this process; 0: cores / threads per case
    bool quiet = false;
    double checkpoint_every = 60.0;  // [s] passed to each damper run
    double progress_every = 0;       // [s] between the study's progress lines; 0: 2 s on a terminal, 30 s in a log
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
    // Report only (`--report-only`): run, prepare and plot nothing, touch no case folder but to
    // put published records back (with publish); read the cases finished in out_dir (which must exist: ConfigError naming it otherwise) as a
    // resumed sweep does, and write its tables, the other cases marked "not run". A study that
    // runs over many sessions gets its interim tables, and a newer build re-analyses old records
    // (read_case_outcome recomputes the stationary loops) without running them again. Rank 0 alone
    // reads and writes, with no MPI call: the other ranks return at once.
    bool report_only = false;
    // How the cases' cycling stages are stepped (docs/gpu.md): "cpu", each case its own World;
    // "batch", the running cases (up to `jobs`) in lockstep through one batch of the batch
    // engine's host backend (the same bits as "cpu"); "cuda", the batch engine on a GPU (a build
    // with VPPDEM_CUDA and a device; refused otherwise). Preparations run as with "cpu".
    std::string backend = "cpu";
    // Continue in a folder whose runs another build made (their build.json, scene/build_info.h).
    // Without it such a sweep is refused before anything runs (ConfigError naming the cases and
    // both builds): a study's table would mix the results of two builds unknowingly.
    bool mix_builds = false;
    // Publish the small records into this folder (`--publish RESULTS`; empty: none): before the
    // cases run (or are reported), the published records of cases the run folder lacks are put
    // back (restore_published: they count as finished); after the tables, every finished case's
    // records, the tables and the folder's COMMAND go there (publish_records). With report_only
    // too.
    std::string publish;
};

// Thrown by run_sweep (and run_calibration) when SweepOptions::progress asked to stop.
struct SweepStopped : std::runtime_error {
    SweepStopped() : std::runtime_error("sweep stopped") {}
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

// `vppdem damper --backend NAME`: the batch one damper's cycling steps through, checked against
// this build and machine (ConfigError, naming what is missing): cuda, the device backend on the
// GPU (VPPDEM_EMULATE_DEVICE=1: the emulated device), its steps between samples run by the
// device alone (docs/gpu.md); nullptr for cpu (the run steps its World).
std::unique_ptr<dem::batch::BatchStepper> damper_backend(const std::string& backend);

// Study::samples_from: per preparation group, the other study's prepared sample it branches from
// (the first fitting one, folder by folder in the order given, in folder-name order; sample_misfit);
// a group no sample fits is not in the map and prepares its own (said on stderr unless opt.quiet).
// Read by every rank alike (the same files, the same answer). Empty without samples_from.
std::map<int, std::filesystem::path> find_shared_samples(const Study& s, const SweepOptions& opt,
                                                         const std::vector<StudyCase>& cases);

}  // namespace vpp
