// The damper run (damper/run.h): its start, fresh or from a checkpoint, and its stages in order;
// vpp::Damper, which runs them one call at a time.
#include "vpp/damper/run.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "scene/scene_runner.h"
#include "dem/io/checkpoint.h"
#include "vpp/damper/checks.h"
#include "vpp/damper/stages.h"

namespace vpp {

namespace damper_detail {

namespace fs = std::filesystem;

// The options and the config a run starts with: `from` resolved, a checkpoint's geometry and
// settings adopted (adopt_checkpoint_settings), and what else the checkpoint said.
struct RunStart {
    DamperOptions options;
    Config config;
    CheckpointStart checkpoint;
};

namespace {

RunStart start_of(const Config& c, const DamperOptions& o) {
    RunStart s{o, c, {}};
    // One resume rule for every command (the sweep's cases and `vppdem device` alike): running
    // into a folder that holds a run.ckpt again continues that run; --overwrite starts afresh.
    if (s.options.from.empty()) {
        s.options.from = scene::resume_checkpoint(s.options.out_dir, "", s.options.overwrite);
        if (!s.options.from.empty() && !s.options.quiet)
            std::fprintf(stderr, "damper: resuming from %s (the same command into the same --out continues its run; "
                         "--overwrite starts afresh)\n", s.options.from.c_str());
    }
    // From a checkpoint: its geometry (and, for a run that started, its settings) first, since
    // the foil is built from the config.
    if (!s.options.from.empty()) s.checkpoint = adopt_checkpoint_settings(s.config, s.options);
    return s;
}

}  // namespace

DamperRun::DamperRun(const Config& c, const DamperOptions& o) : DamperRun(start_of(c, o)) {}

DamperRun::DamperRun(RunStart&& start)
    : options_(std::move(start.options)), recorder_(options_.out_dir), scene_(start.config),
      services_(options_, recorder_) {
    setup(start.checkpoint);
}

void DamperRun::setup(const CheckpointStart& from) {
    dem::World& world = scene_.world;
    const Config& config = scene_.config;
    // Before anything is written or removed (--overwrite): a refused process leaves the folder.
    process_warnings_ = check_process(scene_);
    const std::size_t n_foil = scene_.lattice.particles.size();
    // The pour's grains; a checkpoint holds those and its re-fills' (an older one: the pour's).
    const std::size_t n = from.grains > 0 ? from.grains : grain_count(config);
    scene_.first_grain = uint32_t(n_foil);
    scene_.end_grain = uint32_t(n_foil + n * (scene_.clumps() ? scene_.shape.members.size() : 1));
    if (options_.from.empty()) {
        // A checkpoint's sample was checked when it was prepared.
        for (const std::string& w : check_grains_fit(scene_, n)) services_.warn(state_, w);
        check_preparation_damping(config);
    }

    if (options_.from.empty()) {
        const double funnel_h = scene_.pour(n);
        state_.geometry = sample_keys_of(config);
        state_.grains = scene_.grain_count_now();
        state_.report["prepare.grains_poured"] = double(scene_.grain_count_now());
        state_.report["prepare.funnel_height"] = funnel_h;
        world.params.dt = resolve_dt(config.simulation, world);
        check_steps(scene_);            // refuses a step that is no number, unstable, or too many of them
        check_sampling(scene_, true);   // refuses sampling faster than the time step
        recorder_.open(false, options_.overwrite, options_.from);  // only now: bad input writes nothing
        if (scene_.mesh_foil())
            services_.log("damper: %zu grains (r_k = %.4g m), mesh foil of %zu particles (%zu vacancies, %zu bonds; end rings "
                "%zu and %zu), radius %.5g m, height %.5g m, dt = %.4g s, %d thread(s)\n", n, config.grains.radius, n_foil,
                scene_.membrane.vacancies, scene_.membrane.bonds.size(), scene_.bottom_ring.size(), scene_.top_ring.size(),
                scene_.lattice.radius, scene_.z_top, world.params.dt, config.simulation.threads);
        else
            services_.log("damper: %zu grains (r_k = %.4g m), foil %d x %d = %zu particles (radius %.5g m), height %.5g m, "
                "dt = %.4g s, %d thread(s)\n", n, config.grains.radius, scene_.lattice.cols, scene_.lattice.rows, n_foil,
                scene_.lattice.radius, scene_.z_top, world.params.dt, config.simulation.threads);
        stages::next_stage(scene_, state_, services_, Stage::Fill);
    } else {
        const std::string blob = dem::load_checkpoint(options_.from, world);
        state_ = RunState::load(blob, options_.from);
        // Clumps: every clump a grain, its members the particles after the foil.
        if (scene_.clumps() && world.clumps().size() == n) scene_.end_grain = uint32_t(n_foil + world.clumps().member.size());
        if (world.particles.size() != scene_.end_grain || (scene_.clumps() ? world.clumps().size() != n : !world.clumps().empty()))
            throw std::runtime_error("checkpoint '" + options_.from + "' does not hold this damper's particles");
        state_.grains = n;
        // The mesh foil's pressure fans are not in the checkpoint (DamperRecorder::save_world): from the foil.
        if (scene_.mesh_foil() && state_.stage >= Stage::Vacuum) scene_.set_foil_pressure();
        state_.warnings.insert(state_.warnings.end(), from.warnings.begin(), from.warnings.end());
        if (from.cycles_raised_from > 0) {
            state_.settings["process.cycles"] = double(config.process.cycles);  // what its checkpoints now say
            stages::extend_cycling(scene_, state_, services_, from.cycles_raised_from);
        }
        // Resuming continues the run whose run.ckpt lives in --out; anything else (a branch from
        // a prepared sample, even into its own folder) starts a new run there.
        std::error_code ec;
        const fs::path own = recorder_.run_checkpoint();
        const bool resuming = fs::exists(own) && fs::equivalent(options_.from, own, ec);
        // A prepared sample takes the config's contact and process settings; a resumed run keeps
        // its own (adopt_checkpoint_settings), but for the thread count (set below for every path).
        // A branch is refused what a new sample is refused (sampling faster than its time step),
        // before its folder is touched.
        if (state_.stage == Stage::Prepared) {
            apply_run_settings();
            world.params.dt = resolve_dt(config.simulation, world);
            check_steps(scene_);
            check_sampling(scene_, true);
        }
        recorder_.open(resuming, options_.overwrite, options_.from);
        services_.log("damper: starting from %s at stage '%s', t = %.4g s, %d thread(s)\n", options_.from.c_str(),
            stage_name(state_.stage), world.time, config.simulation.threads);
    }
    world.params.threads = config.simulation.threads;
    for (const std::string& w : check_sampling(scene_, false)) process_warnings_.push_back(w);
    // The sample's own: with it, in prepared.ckpt too.
    if (!scene_.sizes.sieve_note.empty()) services_.warn_once(state_, {"grains.sieve_curve: " + scene_.sizes.sieve_note});
}

void DamperRun::apply_run_settings() {
    scene_.apply_run_settings();
    state_.settings = run_settings_of(scene_.config);  // from now on the run is bound to these
}

void DamperRun::prepare() {
    if (state_.stage == Stage::Fill) {
        stages::fill(scene_, state_, services_);
        stages::next_stage(scene_, state_, services_, Stage::Compress);
    }
    if (state_.stage == Stage::Compress) {
        stages::compress(scene_, state_, services_);
        stages::next_stage(scene_, state_, services_, Stage::Prepared);
        services_.save_prepared(scene_, state_);
        apply_run_settings();
    }
}

void DamperRun::vacuum() {
    prepare();
    services_.warn_once(state_, process_warnings_);  // after prepared.ckpt (see process_warnings_); once on a resume
    if (state_.stage == Stage::Prepared) stages::next_stage(scene_, state_, services_, Stage::Vacuum);
    if (state_.stage == Stage::Vacuum) {
        stages::vacuum(scene_, state_, services_);
        stages::next_stage(scene_, state_, services_, Stage::Cycling);
    }
}

int DamperRun::cycle(int n) {
    vacuum();
    const int ncyc = int(scene_.config.process.cycles);
    const int done = cycles_done();
    if (n == 0) return done;
    const int upto = n < 0 ? ncyc : done + n;
    if (upto > ncyc)
        throw std::runtime_error("cycle(" + std::to_string(n) + "): " + std::to_string(ncyc - done) + " of process.cycles = " +
                                 std::to_string(ncyc) + " cycle(s) remain; the cycling's motion is laid out for "
                                 "process.cycles when it starts: set process.cycles to the cycles wanted");
    if (state_.stage == Stage::Done) return done;
    stages::cycle(scene_, state_, services_, upto);
    if (upto == ncyc) stages::next_stage(scene_, state_, services_, Stage::Done);
    return upto;
}

void DamperRun::save(const std::string& path) const {
    // A prepared sample is saved as prepared.ckpt is: without the settings just applied to it, so
    // that a run from it takes the settings it is given (a branch, as `--from prepared.ckpt`).
    DamperRecorder::save_world(path, scene_.world,
                               state_.stage == Stage::Prepared ? state_.save_as_sample() : state_.save());
}

void DamperRun::write_records(const std::string& dir) const {
    DamperRecorder::write_forces(dir, forces());
    DamperRecorder::write_energy(dir, energy());
}

}  // namespace damper_detail

Damper::Damper(const Config& c, const DamperOptions& opt) : run_(std::make_unique<damper_detail::DamperRun>(c, opt)) {}
Damper::~Damper() = default;
Damper::Damper(Damper&&) noexcept = default;
Damper& Damper::operator=(Damper&&) noexcept = default;

void Damper::prepare() { run_->prepare(); }
void Damper::vacuum() { run_->vacuum(); }
int Damper::cycle(int n) { return run_->cycle(n); }
void Damper::save(const std::string& path) const { run_->save(path); }
void Damper::set_progress(std::function<void(const char*, uint64_t, uint64_t, double)> hook) {
    run_->set_progress(std::move(hook));
}
std::string Damper::stage() const { return damper_detail::stage_name(run_->state().stage); }
int Damper::cycles_done() const { return run_->cycles_done(); }
int Damper::cycles_total() const { return int(run_->config().process.cycles); }
const std::vector<DamperSample>& Damper::samples() const { return run_->state().samples; }
const std::vector<DamperAirSample>& Damper::air() const { return run_->state().air; }
ForcesTable Damper::forces() const { return run_->forces(); }
std::vector<std::vector<double>> Damper::energy() const {
    std::vector<std::vector<double>> rows;
    for (const damper_detail::EnergyRow& e : run_->state().energy)
        rows.emplace_back(e.v, e.v + damper_detail::kEnergyRowSize);
    return rows;
}
std::vector<std::string> Damper::energy_columns() { return dem::energy_column_names(); }
void Damper::write_records(const std::string& dir) const { run_->write_records(dir); }
const dem::World& Damper::world() const { return run_->world(); }
const Config& Damper::config() const { return run_->config(); }

}  // namespace vpp
