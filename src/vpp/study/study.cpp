#include "vpp/study/study.h"

#include <cstdlib>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "dem/batch/batch_stepper.h"
#include "dem/batch/device_api.h"

#include "dem/io/csv.h"
#include "scene/build_info.h"
#include "scene/progress.h"
#include "scene/config.h"
#include "scene/scene_runner.h"
#include "scene/threads.h"
#include "vpp/damper/damper.h"
#include "vpp/study/study_progress.h"

namespace vpp {

namespace fs = std::filesystem;
using cfg::ConfigError;

namespace {

void publish(const SweepOptions& opt, const SweepResult& res);

// Another study's folder named by a study key (samples_from, continues): a relative name is the
// sibling of this --out, in the folder that holds it, as the studies of one project sit side by
// side (out/paper/friction, out/paper/timestep).
fs::path sibling_study_folder(const std::string& out_dir, const std::string& name) {
    const fs::path p(name);
    return p.is_relative() ? fs::path(out_dir).parent_path() / p : p;
}

// --report-only: the tables from the records already in DIR. No FAILED marker or case.toml is
// written, so a sweep running into DIR at the same time is not disturbed (a case it finishes
// meanwhile is either read whole or not at all: summary.json is written last and atomically).
// With --publish the published records DIR lacks come back first, as before a sweep (only into
// case folders with neither summary.json nor run.ckpt: a sweep with the same --publish has put
// them back before it started, so none of them is running): the report then covers every
// finished case, and a build without --publish can resume from them (scripts/paper_studies.sh).
SweepResult report_sweep(const Study& s, const SweepOptions& opt, SweepResult res) {
    const fs::path out(opt.out_dir);
    if (!fs::is_directory(out))
        throw ConfigError("--out '" + opt.out_dir + "': " + (fs::exists(out) ? "not a directory" : "no such folder") +
                          " (--report-only reads the cases a sweep finished there and runs nothing)");
    res.outcomes.assign(res.cases.size(), CaseOutcome{});
    if (opt.rank != 0) return res;
    if (!opt.publish.empty()) {
        const std::size_t n = restore_published(opt.publish, out, res.cases);
        if (n && !opt.quiet)
            std::fprintf(stderr, "sweep --report-only: %zu finished case(s) restored from %s\n", n, opt.publish.c_str());
    }
    std::size_t finished = 0;
    for (std::size_t i = 0; i < res.cases.size(); ++i) {
        const StudyCase& c = res.cases[i];
        const fs::path dir = out / c.name;
        CaseOutcome& o = res.outcomes[i];
        if (!fs::exists(dir / "summary.json")) {
            o.not_run = true;
            o.run_seconds = CaseOutcome::kNaN;  // an empty cell: it has not run, rather than ran 0 s
            continue;
        }
        try {
            // A case the study gives more cycles than it ran (or whose continuation was
            // interrupted) has not finished for this study.
            std::optional<CaseOutcome> done = finished_case(dir, case_record(s, c), c.config);
            if (!done) {
                o.not_run = true;
                o.run_seconds = CaseOutcome::kNaN;
                continue;
            }
            o = std::move(*done);
            o.skipped = true;
            ++finished;
        } catch (const std::exception& e) {
            o.message = e.what();
            ++res.failed;
            if (!opt.quiet) std::fprintf(stderr, "sweep: %s: unreadable: %s\n", c.name.c_str(), e.what());
        }
    }
    const std::string names = write_study_tables(out, s, res.cases, res.outcomes);
    if (!opt.quiet)
        std::fprintf(stderr, "sweep --report-only: %zu of %zu cases finished%s; ran nothing; wrote %s\n", finished,
                     res.cases.size(), res.failed ? (", " + std::to_string(res.failed) + " unreadable").c_str() : "",
                     names.c_str());
    publish(opt, res);
    return res;
}

// Refuses a study folder holding runs that another build made or resumed (SweepOptions::mix_builds).
void refuse_other_builds(const fs::path& out, const std::vector<StudyCase>& cases) {
    std::string list;
    std::size_t n = 0;
    for (const StudyCase& c : cases) {
        const std::vector<scene::BuildStamp> other = scene::other_builds((out / c.name).string());
        if (other.empty()) continue;
        if (++n <= 3) list += std::string(n > 1 ? "; " : "") + c.name + " (commit " + other.front().commit + ", build " + other.front().id + ")";
    }
    if (!n) return;
    throw ConfigError("--out '" + out.string() + "' holds " + std::to_string(n) + " case(s) run by another build: " + list +
                      (n > 3 ? "; ..." : "") + ". This vppdem is commit " + scene::build_commit() + ", build " +
                      scene::build_id() + ": its results would be mixed with theirs in one study. Run the study with " +
                      "the build that made them, use another --out, or pass --mix-builds to continue anyway (each " +
                      "case's build.json lists the builds that ran it)");
}

// What --backend asks for, checked against this build and machine before anything runs.
struct Backend {
    std::string name;       // cpu, batch or cuda
    bool emulated = false;  // cuda on the emulated device (VPPDEM_EMULATE_DEVICE=1: its kernels on the host)
    int chunk = 256;        // the device's longest chunk [steps] (VPPDEM_CHUNK)
};

Backend choose_backend(const std::string& backend) {
    if (backend != "cpu" && backend != "batch" && backend != "cuda")
        throw ConfigError("--backend '" + backend + "' is not one of cpu, batch, cuda");
    // --backend cuda: the batch engine's device backend on the GPU. VPPDEM_EMULATE_DEVICE=1 runs it
    // on the emulated device instead (its kernels on the host: the tests' stand-in for a GPU).
    const char* emulate = std::getenv("VPPDEM_EMULATE_DEVICE");
    const bool emulated = backend == "cuda" && emulate && std::string(emulate) == "1";
    // VPPDEM_CHUNK=K: the device's longest chunk [steps] (docs/gpu.md; a measurement's knob).
    int chunk = 256;
    if (const char* c = std::getenv("VPPDEM_CHUNK"); c && *c) {
        char* end = nullptr;
        const long k = std::strtol(c, &end, 10);
        if (*end || k < 1 || k > 1000000)
            throw ConfigError(std::string("VPPDEM_CHUNK = '") + c + "': allowed a whole number of steps from 1 to 1000000");
        chunk = int(k);
    }
    if (backend == "cuda" && !emulated && !dem::batch::dev::cuda_built())
        throw ConfigError("--backend cuda: this vppdem was built without CUDA. Build it with the option VPPDEM_CUDA "
                          "(cmake -S . -B build-cuda -DVPPDEM_CUDA=ON -DVPPDEM_NVCC=/usr/local/cuda/bin/nvcc, then "
                          "cmake --build build-cuda --target vppdem; docs/gpu.md), or use --backend cpu (or, for a "
                          "sweep, batch: the same engine on the CPU)");
    if (backend == "cuda" && !emulated) {
        const char* why = nullptr;
        if (dem::batch::dev::cuda_devices(&why) == 0)
            throw ConfigError(std::string("--backend cuda: no CUDA device (") + (why ? why : "none") + ")");
    }
    return {backend, emulated, chunk};
}

std::unique_ptr<dem::batch::BatchStepper> make_stepper(const Backend& backend, int jobs) {
    // The batch the running cases step their cycling through (--backend batch, cuda).
    if (backend.name == "batch") return std::make_unique<dem::batch::BatchStepper>(jobs);
    if (backend.name == "cuda")
        return std::make_unique<dem::batch::BatchStepper>(
            jobs, backend.emulated ? dem::batch::BatchStepper::Backend::kEmulated : dem::batch::BatchStepper::Backend::kCuda,
            backend.chunk);
    return nullptr;
}

// The study folder: rank 0 takes its lock (the ranks share the folder, so one lock serves them
// all; the others wait at the barrier, and if rank 0 is refused its error aborts them there,
// before they write) and refuses runs of other builds unless --mix-builds.
void open_study_folder(const Study& s, const SweepOptions& opt, SweepResult& res) {
    const fs::path out(opt.out_dir);
    if (fs::exists(out) && !fs::is_directory(out))
        throw ConfigError("--out '" + opt.out_dir + "' exists and is not a directory");
    if (opt.rank == 0) res.lock = scene::lock_output_dir(opt.out_dir);
    // The published records first, so that the build check covers them too.
    if (opt.rank == 0 && !opt.publish.empty()) {
        const std::size_t n = restore_published(opt.publish, out, res.cases);
        if (n && !opt.quiet)
            std::fprintf(stderr, "sweep: %zu finished case(s) restored from %s\n", n, opt.publish.c_str());
    }
    // A second leg's copies of the runs it continues, before the build check: continuing another
    // build's runs mixes builds as much as resuming them does.
    if (opt.rank == 0 && !s.continues.empty()) {
        const fs::path from = sibling_study_folder(opt.out_dir, s.continues);
        std::vector<std::string> anew;
        const std::size_t n = copy_continued_runs(from, out, s, res.cases, &anew);
        if (!opt.quiet) {
            std::fprintf(stderr, "sweep: continues %s: %zu finished run(s) copied to continue\n", from.string().c_str(), n);
            if (!anew.empty()) {
                std::string list;
                for (std::size_t k = 0; k < anew.size() && k < 5; ++k) list += (k ? ", " : "") + anew[k];
                std::fprintf(stderr, "sweep: continues %s: %zu case(s) not there with a run.ckpt run anew: %s%s\n",
                             from.string().c_str(), anew.size(), list.c_str(), anew.size() > 5 ? ", ..." : "");
            }
        }
    }
    // The same study run before without seeds: its runs are the seed they ran with.
    if (opt.rank == 0) {
        const std::vector<std::string> adopted = adopt_seedless_runs(out, s, res.cases);
        if (!adopted.empty() && !opt.quiet)
            std::fprintf(stderr, "sweep: %zu run(s) of this study without seeds reused as their seed's: %s%s\n",
                         adopted.size(), adopted.front().c_str(), adopted.size() > 1 ? ", ..." : "");
    }
    if (opt.rank == 0 && !opt.mix_builds) refuse_other_builds(out, res.cases);
    mpi_barrier();
    fs::create_directories(out);
}

// This rank's cases (every ranks-th), preparers first, then the branches, each in grid order.
std::vector<std::size_t> cases_of_this_rank(const std::vector<StudyCase>& cases, const SweepOptions& opt) {
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < cases.size(); ++i)
        if (int(i % std::size_t(std::max(1, opt.ranks))) == opt.rank) mine.push_back(i);
    std::stable_sort(mine.begin(), mine.end(), [&](std::size_t a, std::size_t b) {
        return (cases[a].preparer == a) > (cases[b].preparer == b);
    });
    return mine;
}

// How many cases run at once: --jobs, or the free cores over each case's threads (not all the
// cores: a busy core slows every case's threads, scene/threads.h); one per rank under MPI.
int job_count(const SweepOptions& opt, const std::vector<StudyCase>& cases, std::size_t mine) {
    int jobs = opt.jobs;
    if (jobs <= 0) {
        const int cores = scene::default_threads();
        const int per_case = cases.empty() ? 1 : std::max(1, cases[0].config.simulation.threads);
        jobs = opt.ranks > 1 ? 1 : std::max(1, cores / per_case);
    }
    return std::max(1, std::min<int>(jobs, int(mine)));
}

// The running cases of one rank: a pool of `jobs` workers takes the cases whose samples are
// ready (their preparer's prepared.ckpt), each a damper run into its folder, resumed from its
// run.ckpt or skipped when its records are complete. The workers share the case states and the
// stop flag under one mutex.
class CaseRunner {
public:
    CaseRunner(const Study& s, const SweepOptions& opt, const Backend& backend, SweepResult& res,
               std::vector<std::size_t> mine, int jobs, std::map<int, fs::path> shared_samples)
        : s_(s), opt_(opt), cases_(res.cases), out_(opt.out_dir), res_(res), mine_(std::move(mine)), jobs_(jobs),
          shared_(std::move(shared_samples)) {
        batch_ = make_stepper(backend, jobs);
        for (std::size_t i : mine_) state_[i] = 0;
        if (!opt_.quiet)
            progress_.emplace(opt_.ranks > 1 ? "sweep rank " + std::to_string(opt_.rank) : std::string("sweep"),
                              mine_.size(), jobs_,
                              opt_.progress_every > 0 ? opt_.progress_every : scene::default_progress_every());
    }

    // Runs every case of this rank; rethrows what the progress hook threw, SweepStopped when it
    // asked to stop.
    void run() {
        std::vector<std::thread> pool;
        for (int j = 0; j < jobs_; ++j) pool.emplace_back([this] { worker(); });
        for (auto& t : pool) t.join();
        if (hook_error_) std::rethrow_exception(hook_error_);
        if (stop_.load()) throw SweepStopped();
        if (batch_ && !opt_.quiet)
            std::fprintf(stderr, "sweep: %s backend: %llu half steps launched, up to %zu runs at once\n",
                         opt_.backend.c_str(), (unsigned long long)batch_->launches(), batch_->most_systems());
    }

private:
    void report(std::size_t i, const CaseOutcome& o) {
        if (opt_.quiet) return;
        std::lock_guard<std::mutex> lk(mu_);
        const std::string who = (opt_.ranks > 1 ? "rank " + std::to_string(opt_.rank) + " " : "");
        if (o.ok)
            std::fprintf(stderr, "%s[%zu/%zu] %s: %s W = %.5g J/m^2, energy %.5g J, peak %.4g N (%.1f s)\n", who.c_str(),
                         i + 1, cases_.size(), cases_[i].name.c_str(), o.skipped ? "done earlier," : "ok,", o.W,
                         o.dissipated_energy, o.peak_force, o.run_seconds);
        else
            std::fprintf(stderr, "%s[%zu/%zu] %s: FAILED: %s\n", who.c_str(), i + 1, cases_.size(),
                         cases_[i].name.c_str(), o.message.c_str());
    }

    // What a case waits for: its preparer's prepared.ckpt (unless it has its own checkpoint).
    // Returns 1 ready, 0 wait, -1 the preparation failed (message set), 2 prepare it itself.
    int readiness(std::size_t i, std::string& why) const {
        const StudyCase& c = cases_[i];
        const fs::path dir = out_ / c.name;
        if (c.preparer == i || fs::exists(dir / "summary.json") || fs::exists(dir / "run.ckpt")) return 1;
        if (shared_.count(c.group)) return 1;  // another study's sample (samples_from)
        const fs::path pdir = out_ / cases_[c.preparer].name;
        if (fs::exists(pdir / "prepared.ckpt")) return 1;
        if (fs::exists(pdir / "FAILED")) {
            why = "its preparation (case " + cases_[c.preparer].name + ") failed";
            return -1;
        }
        // The preparer finished earlier but its prepared.ckpt is gone: prepare this case itself.
        if (fs::exists(pdir / "summary.json")) return 2;
        return 0;
    }

    // Cancelling (SweepOptions::progress): `stop_` makes the workers take no new case and the
    // running cases throw at their next poll; `hook_error_` keeps what the hook threw.
    void ask_hook(std::size_t done, const std::string& name) {
        if (!opt_.progress || stop_.load()) return;
        std::lock_guard<std::mutex> lk(hook_mu_);
        if (stop_.load()) return;
        try {
            if (!opt_.progress(done, mine_.size(), name)) stop_.store(true);
        } catch (...) {
            if (!hook_error_) hook_error_ = std::current_exception();
            stop_.store(true);
        }
    }

    // One case: skipped when its records are complete, else a damper run into its folder from
    // its run.ckpt, its preparer's sample, or its own preparation. Failures are outcomes (and a
    // FAILED marker), never exceptions.
    CaseOutcome run_case(std::size_t i, bool self_prepare) {
        const StudyCase& c = cases_[i];
        const fs::path dir = out_ / c.name;
        CaseOutcome o;
        try {
            fs::create_directories(dir);
            const std::string rec = case_record(s_, c);
            if (std::optional<CaseOutcome> done = finished_case(dir, rec, c.config)) {
                o = std::move(*done);
                o.skipped = true;
                return o;
            }
            // Records of fewer cycles than the study's (its process.cycles raised): the case
            // continues from its run.ckpt (below), never from the sample, which would replace it.
            if (fs::exists(dir / "summary.json") && !fs::exists(dir / "run.ckpt"))
                throw std::runtime_error("folder '" + dir.string() + "' holds " +
                                         std::to_string(recorded_cycles(dir)) +
                                         " cycles of this case and no run.ckpt to continue from to " +
                                         std::to_string(c.config.process.cycles) + ": give the sweep another --out");
            dem::write_text_atomic((dir / "case.toml").string(), rec);
            if (progress_) progress_->started(i, c.name, seconds());
            DamperOptions d;
            d.out_dir = dir.string();
            d.quiet = true;
            d.plot = false;
            d.overwrite = true;  // the folder holds case.toml, perhaps leftovers of a killed start
            d.checkpoint_every = opt_.checkpoint_every;
            d.check_preparation = true;  // never a branch from a sample of other settings
            // Clumps and the mesh foil's pressure fans are not in the batch yet: those cases step
            // on the CPU, as --backend cpu (the same bits).
            d.batch = c.config.grains.shape == GrainShape::Sphere && c.config.damper.foil_builder == FoilBuilder::Lattice
                          ? batch_.get() : nullptr;
            if (opt_.progress || progress_)
                d.progress = [this, i](const char* stage, uint64_t done, uint64_t total, double) {
                    if (progress_) {
                        const double now = seconds();
                        progress_->stage(i, stage, done, total, now);
                        if (const std::string l = progress_->due(now); !l.empty()) std::fprintf(stderr, "%s\n", l.c_str());
                    }
                    ask_hook(0, "");
                    if (stop_.load()) throw SweepStopped();
                };
            // The case's own run.ckpt first (the one resume rule), then its sample.
            d.from = scene::resume_checkpoint(dir.string(), "", false);
            const auto shared = shared_.find(c.group);
            if (d.from.empty() && shared != shared_.end()) {
                // Another study's sample: matched by geometry alone, the case cycles it with its
                // own settings (samples_match = "geometry"), as a damper --from by hand would.
                d.from = shared->second.string();
                d.check_preparation = !s_.samples_match_geometry;
            } else if (d.from.empty() && c.preparer != i && !self_prepare) {
                d.from = (out_ / cases_[c.preparer].name / "prepared.ckpt").string();
            }
            const DamperResult r = run_damper(c.config, d);
            if (r.cycles.empty()) throw std::runtime_error("the run recorded no complete cycle");
            if (r.incomplete)
                for (const std::string& w : r.warnings)
                    if (w.starts_with("incomplete: ")) throw std::runtime_error(w);
            // From the records the run wrote, as for a case finished earlier: one place fills
            // an outcome, so a resumed sweep's tables are those of an uninterrupted one.
            o = read_case_outcome(dir, c.config);
        } catch (const SweepStopped&) {
            // Stopped, not failed: no FAILED marker, the next run of the sweep takes it up.
            o.ok = false;
            o.message = "stopped";
        } catch (const dem::FolderLocked& e) {
            // Another process (a damper run started by hand) writes into the case folder: failed,
            // but no FAILED marker in a folder that is not ours now.
            o.ok = false;
            o.message = e.what();
        } catch (const std::exception& e) {
            o.ok = false;
            o.message = e.what();
            try {
                dem::write_text_atomic((dir / "FAILED").string(), o.message + "\n");
            } catch (...) {
            }
        }
        return o;
    }

    // The next ready case (SIZE_MAX: none yet); a case whose preparation failed is finished on
    // the spot. Called under mu_ (lk), which it releases to report.
    std::size_t pick_case(std::unique_lock<std::mutex>& lk, bool& self_prepare) {
        for (std::size_t i : mine_) {
            if (state_[i] != 0) continue;
            std::string why;
            const int r = readiness(i, why);
            if (r == -1) {
                state_[i] = 2;
                ++finished_;
                res_.outcomes[i].ok = false;
                res_.outcomes[i].message = why;
                lk.unlock();
                report(i, res_.outcomes[i]);
                lk.lock();
                return SIZE_MAX;  // rescan
            }
            if (r > 0) {
                self_prepare = r == 2;
                state_[i] = 1;
                return i;
            }
        }
        return SIZE_MAX;
    }

    void worker() {
        for (;;) {
            std::size_t pick = SIZE_MAX;
            bool self_prepare = false;
            {
                std::unique_lock<std::mutex> lk(mu_);
                if (finished_ == mine_.size() || stop_.load()) return;
                pick = pick_case(lk, self_prepare);
            }
            if (pick == SIZE_MAX) {
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
                continue;
            }
            const CaseOutcome o = run_case(pick, self_prepare);
            if (progress_) progress_->finished(pick, o.ok && !o.skipped, seconds());
            std::size_t done = 0;
            {
                std::lock_guard<std::mutex> lk(mu_);
                res_.outcomes[pick] = o;
                state_[pick] = 2;
                done = ++finished_;
            }
            if (stop_.load()) return;  // a stopped case is neither reported nor counted as done
            report(pick, o);
            ask_hook(done, cases_[pick].name);
        }
    }

    const Study& s_;
    const SweepOptions& opt_;
    const std::vector<StudyCase>& cases_;
    const fs::path out_;
    SweepResult& res_;
    const std::vector<std::size_t> mine_;
    const int jobs_;
    std::unique_ptr<dem::batch::BatchStepper> batch_;
    std::mutex mu_;
    const std::map<int, fs::path> shared_;  // preparation group -> another study's prepared.ckpt
    std::map<std::size_t, int> state_;  // 0 pending, 1 running, 2 finished
    std::optional<StudyProgress> progress_;  // the study's progress line (none when quiet)
    // [s] of the steady clock, for the progress line.
    static double seconds() {
        return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    }
    std::size_t finished_ = 0;
    std::atomic<bool> stop_{false};
    std::exception_ptr hook_error_;
    std::mutex hook_mu_;  // one hook call at a time
};

// --publish: the finished cases' small records and the tables into the results folder.
void publish(const SweepOptions& opt, const SweepResult& res) {
    if (opt.publish.empty()) return;
    const std::size_t held = publish_records(opt.publish, opt.out_dir, res.cases, res.outcomes);
    if (!opt.quiet)
        std::fprintf(stderr, "sweep: published into %s (%zu of %zu cases there)\n", opt.publish.c_str(), held,
                     res.cases.size());
}

// Gathers the ranks' outcomes on rank 0, which writes the study's tables; every rank learns the
// failure count.
void gather_and_write_tables(const Study& s, const SweepOptions& opt, SweepResult& res,
                             const std::vector<std::size_t>& mine) {
    std::string text;
    for (std::size_t i : mine) text += outcome_json(i, res.outcomes[i]);
    const std::string all = mpi_gather_text(text, opt.ranks);
    if (opt.rank == 0) {
        read_outcome_lines(all, res.outcomes);
        for (const CaseOutcome& o : res.outcomes) res.failed += o.ok ? 0 : 1;
        const std::string names = write_study_tables(fs::path(opt.out_dir), s, res.cases, res.outcomes);
        if (!opt.quiet) {
            std::fprintf(stderr, "sweep: %zu cases, %d failed; wrote %s\n", res.cases.size(), res.failed, names.c_str());
            // The runs ran quietly: their warnings, once per kind (summary.csv has each run's).
            for (const std::string& w : run_warning_lines(res.cases, res.outcomes))
                std::fprintf(stderr, "WARNING: runs: %s\n", w.c_str());
        }
        publish(opt, res);
    }
    res.failed = mpi_broadcast_int(res.failed);
}

}  // namespace

SweepResult run_sweep(const Study& s, const SweepOptions& opt) {
    SweepResult res;
    res.cases = expand_study(s);  // every case's config is checked before anything runs
    if (opt.report_only) return report_sweep(s, opt, std::move(res));
    const Backend backend = choose_backend(opt.backend);
    open_study_folder(s, opt, res);
    res.outcomes.assign(res.cases.size(), CaseOutcome{});
    const std::vector<std::size_t> mine = cases_of_this_rank(res.cases, opt);
    // Failure markers of an earlier attempt are cleared before any rank looks at them.
    for (std::size_t i : mine) fs::remove(fs::path(opt.out_dir) / res.cases[i].name / "FAILED");
    mpi_barrier();
    const int jobs = job_count(opt, res.cases, mine.size());
    if (!opt.quiet && opt.rank == 0) {
        int preparations = 0;
        for (const StudyCase& c : res.cases) preparations = std::max(preparations, c.group + 1);
        std::fprintf(stderr, "sweep: %zu cases, %d preparation(s), %d job(s)%s, out %s\n", res.cases.size(),
                     preparations, jobs,
                     opt.ranks > 1 ? (" per rank x " + std::to_string(opt.ranks) + " ranks").c_str() : "",
                     opt.out_dir.c_str());
    }
    CaseRunner(s, opt, backend, res, mine, jobs, find_shared_samples(s, opt, res.cases)).run();
    gather_and_write_tables(s, opt, res, mine);
    return res;
}

std::map<int, fs::path> find_shared_samples(const Study& s, const SweepOptions& opt, const std::vector<StudyCase>& cases) {
    std::map<int, fs::path> found;
    if (s.samples_from.empty()) return found;
    // The folders in the order given, each one's samples in folder-name order.
    std::vector<fs::path> samples;
    std::string where;
    for (const std::string& name : s.samples_from) {
        const fs::path from = sibling_study_folder(opt.out_dir, name);
        if (!fs::is_directory(from))
            throw ConfigError("study '" + s.path + "': key 'samples_from' names \"" + name + "\": no folder '" +
                              from.string() + "' (another study's --out, relative to the folder that holds this --out)");
        std::vector<fs::path> here;
        for (const auto& e : fs::directory_iterator(from))
            if (e.is_directory() && fs::exists(e.path() / "prepared.ckpt")) here.push_back(e.path() / "prepared.ckpt");
        std::sort(here.begin(), here.end());
        samples.insert(samples.end(), here.begin(), here.end());
        where += (where.empty() ? "" : ", ") + from.string();
    }
    // Each file read once, whatever the number of groups it is matched against.
    std::vector<std::optional<SampleRecord>> records(samples.size());
    std::vector<std::string> unreadable(samples.size());
    for (std::size_t k = 0; k < samples.size(); ++k) {
        try {
            records[k] = read_sample_record(samples[k].string());
        } catch (const std::exception& e) {
            unreadable[k] = std::string("unreadable: ") + e.what();
        }
    }
    std::size_t groups = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        if (cases[i].preparer != i) continue;
        ++groups;
        std::string first_why;
        for (std::size_t k = 0; k < samples.size(); ++k) {
            const std::string why =
                records[k] ? sample_misfit(cases[i].config, *records[k], !s.samples_match_geometry) : unreadable[k];
            if (why.empty()) {
                found[cases[i].group] = samples[k];
                break;
            }
            if (first_why.empty()) first_why = samples[k].parent_path().filename().string() + ": " + why;
        }
        if (!found.count(cases[i].group) && !opt.quiet && opt.rank == 0)
            std::fprintf(stderr, "sweep: %s: no sample in %s fits (%s); it prepares its own if it runs\n", cases[i].name.c_str(),
                         where.c_str(), samples.empty() ? "none there" : first_why.c_str());
    }
    if (!opt.quiet && opt.rank == 0)
        std::fprintf(stderr, "sweep: samples from %s (%zu there, matched by %s): %zu of %zu preparation(s)\n",
                     where.c_str(), samples.size(), s.samples_match_geometry ? "geometry" : "preparation",
                     found.size(), groups);
    return found;
}


std::unique_ptr<dem::batch::BatchStepper> damper_backend(const std::string& backend) {
    if (backend != "cpu" && backend != "cuda")
        throw ConfigError("--backend '" + backend + "' is not one of cpu, cuda (a damper run; a sweep has batch too)");
    return make_stepper(choose_backend(backend), 1);
}

}  // namespace vpp
