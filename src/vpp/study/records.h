// What a sweep records and reports (docs/studies.md, "Outputs"): each case's outcome, read from
// its finished folder (the only place an outcome is filled, for a case just run as for one
// finished earlier), its JSON form (the one serialisation, which the MPI gather sends), and the
// tables summary.csv, summary_cases.csv and summary_paired.csv made from the outcomes.
#pragma once

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vpp/study/file.h"

namespace vpp {

struct CaseOutcome {
    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    bool ok = false;
    bool skipped = false;        // finished in an earlier run of the sweep
    bool not_run = false;        // report only: no finished record in its folder (status "not run")
    std::string message;         // failure message
    double W = 0, dissipated_energy = 0, peak_force = 0;  // last cycle
    double run_seconds = 0;
    // Stationary loops (vpp/analysis/settle.h): mean W of the settled cycles (NaN: none settled), how
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

// A number of CaseOutcome, described once: summary.csv's column, the MPI gather's JSON key and
// the ensemble statistics' quantity all use `name`; outcome_json, read_outcome_lines, summary_csv
// and the quantities read this table, so a number cannot be in one of them and missing from
// another. Exactly one of real and count is set.
struct OutcomeNumber {
    const char* name;     // summary.csv column (docs/studies.md, "Outputs"), JSON key, quantity
    const char* unit;     // SI; "-" a ratio, "" a count
    const char* meaning;
    double CaseOutcome::*real = nullptr;
    int CaseOutcome::*count = nullptr;
    bool before_status = false;  // summary.csv: before the status and case columns (the first contract)
    bool zero_empty = false;     // summary.csv: 0 written as an empty field (none)
    bool any_run = false;        // summary.csv: written for a run that did not finish too
    double value(const CaseOutcome& o) const { return real ? o.*real : double(o.*count); }
};

// In summary.csv's order within each of its two blocks (before and after status, case).
const std::vector<OutcomeNumber>& outcome_numbers();

// What identifies a case's inputs: written to DIR/<case>/case.toml, compared on resume.
std::string case_record(const Study& s, const StudyCase& c);

// How a case folder's case.toml relates to the study's `record` for it: the same case (or no
// case.toml yet), or the same case but for a larger process.cycles (a study given more cycles:
// the case continues from its run.ckpt, its record then that of a run of that many cycles). A
// folder written for other settings is refused (std::runtime_error) rather than mixing results
// of two studies.
enum class CaseFolder { Same, MoreCycles };
CaseFolder check_case_folder(const std::filesystem::path& dir, const std::string& record);

// A study run again with seeds (key 'seeds', --seeds or a [grid] list of simulation.seed) into
// the folder of its run without them: each case folder of that run is renamed to the name of
// the seed it ran with (the config's simulation.seed, 1 by default), and its case.toml made that
// case's, so that it is reused (skipped when finished, resumed when not) rather than run again
// beside the old folder. Only a folder whose case.toml is the seed-less case's (check_case_folder:
// the same settings) is taken; one of other settings is left for the sweep to refuse. Returns
// the renamed folders' new names.
std::vector<std::string> adopt_seedless_runs(const std::filesystem::path& out, const Study& s,
                                             const std::vector<StudyCase>& cases);

// The finished runs' warnings (their summary.json "warnings"), one line per kind (the text
// before its first ':': "not quasi-static", "W not stationary", ...): how many runs of how many
// finished gave it, up to 3 of their cases, and the first one's whole message. What a study or a
// calibration passes on from its runs, which run quietly.
std::vector<std::string> run_warning_lines(const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes);

// The cycles a case folder's cycles.csv holds (0 without one).
std::size_t recorded_cycles(const std::filesystem::path& dir);

// The outcome of a case folder that finished for this study (nullopt: not yet; the caller runs
// or continues it): the same record (check_case_folder, which refuses a folder of other
// settings), a summary.json, and at least the config's process.cycles in cycles.csv (fewer: a
// study given more cycles, or a continuation interrupted). The one answer to "is this case done"
// for a sweep and its --report-only, reading cycles.csv once.
std::optional<CaseOutcome> finished_case(const std::filesystem::path& dir, const std::string& record,
                                         const Config& config);

// The outcome of a finished case folder: its last cycle (cycles.csv), the stationarity of its
// cycles (the case's analysis.settle_tolerance applied to the W column, as the damper did), its
// run time, grains, packing fraction and warnings (summary.json). skipped is false: the caller
// says whether the case finished in this run.
CaseOutcome read_case_outcome(const std::filesystem::path& dir, const Config& config);

// One case's outcome as one line of JSON (the case's index as "case"), and back: the MPI
// gather's message. NaN is written as null and read back as NaN.
std::string outcome_json(std::size_t index, const CaseOutcome& o);
// Reads the lines of outcome_json() into out[index] (an index outside out is ignored).
void read_outcome_lines(const std::string& text, std::vector<CaseOutcome>& out);

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
// over the finished runs that have Q (vpp/analysis/stats.h: Student t, n - 1 degrees of freedom; ci95 the
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
// sd and 95% half width of d (vpp/analysis/stats.h; sd and ci95 empty for n < 2, every number for n = 0),
// the mean of Q at the reference over the same seeds, and diff_mean / ref_mean. The seeds of
// one case branch from that seed's sample where A shares the preparation, so the sample's own
// scatter cancels in d (docs/studies.md, "Ensembles").
std::string paired_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes);

// Rows of the ensemble table: the indices of the runs of each case (grid order), the seed axis
// left out.
std::vector<std::vector<std::size_t>> ensemble_groups(const Study& s, const std::vector<StudyCase>& cases);

// The tables of a sweep, each written atomically into `out`: summary.csv, summary_cases.csv and,
// with seeds, summary_paired.csv. Returns the names written, for the closing message.
std::string write_study_tables(const std::filesystem::path& out, const Study& s, const std::vector<StudyCase>& cases,
                               const std::vector<CaseOutcome>& outcomes);

// Publishing a study's small records (SweepOptions::publish, `--publish RESULTS`), the one way a
// study's records reach a repository (the scripts under scripts/ only call it): what it keeps of
// each finished case, kRunRecords, and the study's tables, while the run folders (checkpoints,
// forces.csv, frames) stay on the machine.
inline const std::vector<std::string> kRunRecords = {"case.toml", "summary.json", "cycles.csv", "build.json"};
// The tables: the sweep's, and sources.csv, which an assembled study folder has (the paper
// report's: which published run each case folder is; python3 -m vppdem.report paper assemble).
inline const std::vector<std::string> kStudyTables = {"summary.csv", "summary_cases.csv", "summary_paired.csv",
                                                      "sources.csv"};
// The study folder's note of the command that ran it, written by a script that runs a build
// without --publish (scripts/paper_studies.sh: "... (pinned build <commit>)"), published with the
// records whenever the run folder has one.
inline const std::string kStudyCommand = "COMMAND";

// The published records back into the run folders before a study runs or is reported: each case
// of `cases` with RESULTS/<case>/summary.json whose run folder has neither summary.json nor
// run.ckpt gets them (so the sweep takes it as finished, or continues it to more cycles if it has
// a run.ckpt elsewhere: refused, as any records without one). Returns how many cases were restored.
std::size_t restore_published(const std::filesystem::path& results, const std::filesystem::path& out,
                              const std::vector<StudyCase>& cases);

// Every finished case's records (its outcome ok: records complete for this study, as the sweep or
// the report read them) into RESULTS/<case>/, each file only when it changed, through a temporary
// name (a reader never sees half a file), if its folder has a case.toml (records that say which
// case they are: an assembled folder's copies of published runs, which have none, stay where
// they came from); then the study's tables, unless the published summary.csv lists more finished
// cases (a sweep of part of the study); then OUT/COMMAND, when there is one. Returns how many
// cases RESULTS holds.
std::size_t publish_records(const std::filesystem::path& results, const std::filesystem::path& out,
                            const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes);

// A study's second leg (Study::continues, `continues = "NAME"`): each case of `cases` that OUT
// lacks and FROM holds finished (summary.json) with its run.ckpt is copied into OUT (every file
// but hidden ones, through a hidden temporary folder renamed when whole; FROM's run stays as it
// is), to be continued to this study's process.cycles from its run.ckpt. Its case.toml must be
// this study's case but for a larger process.cycles (check_case_folder), else ConfigError. A case
// FROM holds unfinished (a run.ckpt without summary.json) is refused with the others (ConfigError
// naming them, nothing copied); a case FROM lacks, or holds finished without a run.ckpt, runs
// anew (from its samples or its own preparation) and is named in `anew`. Returns the copies made.
std::size_t copy_continued_runs(const std::filesystem::path& from, const std::filesystem::path& out, const Study& s,
                                const std::vector<StudyCase>& cases, std::vector<std::string>* anew = nullptr);

}  // namespace vpp
