// The damper's world: foil cylinder, grains in the foil and a funnel above it, caps; the checks
// of the input; a checkpoint's geometry and settings; the settings applied to a prepared sample.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "scene/scene_runner.h"
#include "dem/io/checkpoint.h"
#include "dem/io/csv.h"
#include "dem/walls/facet_sets.h"
#include "vpp/damper_run.h"
#include "vpp/settings.h"

namespace vpp {

namespace damper_detail {

namespace {

// A config value stored in the checkpoint's app state: a row of the settings table, with how to
// read it from and write it into a Config (vpp/settings.h).
using StoredKey = Setting;

// Geometry of the prepared sample. A run from a checkpoint must match the keys it gives and
// takes the checkpoint's values of the others.
const std::vector<StoredKey> kGeometryKeys = geometry_settings();

// What a run applies to its prepared sample (apply_config_to_prepared) and records from then
// on: a resumed run continues with these, so its record is one run's, not a splice of two.
// Not here: simulation.threads (results do not depend on it), output.vtk_interval (frames only).
const std::vector<StoredKey> kRunKeys = run_settings();

// What else acted during the preparation: recorded beside the geometry (not checked by a run
// --from a sample by hand; checked for a study's branch, DamperOptions::check_preparation).
const std::vector<StoredKey> kPreparationKeys = preparation_settings();

std::map<std::string, double> values_of(const Config& c, const auto& keys) {
    std::map<std::string, double> m;
    for (const StoredKey& k : keys) m[k.key] = k.get(c);
    return m;
}

bool same_value(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

// A stored value as the config file writes it, for messages.
std::string show(const std::string& key, double v) {
    if (key == "process.direction") return v == 0.0 ? "\"compression\"" : "\"extension\"";
    if (key == "process.pressure_model") return v == 0.0 ? "\"constant\"" : "\"pump\"";
    if (key == "process.waveform") return v == 0.0 ? "\"triangle\"" : "\"sine\"";
    if (key == "output.energy" || key == "damper.refill") return v != 0.0 ? "true" : "false";
    if (key == "foil.builder") return v == 0.0 ? "\"lattice\"" : "\"mesh\"";
    if (key == "foil.bond_arm") return "\"" + std::string(dem::bond_arm_name(dem::BondArm(int(v)))) + "\"";
    if (key == "simulation.dt" && v == 0.0) return "\"auto\"";
    if (key == "damper.cap_friction" && v < 0.0) return "(unset: the grains' friction)";
    // Words, not the numbers the checkpoint keeps for them (a refusal said "grains.shape = 5").
    if (key == "grains.shape") {
        const char* const names[] = {"\"sphere\"", "\"dimer\"", "\"trimer\"", "\"tetrahedron\"", "\"pellet\"", "\"template\""};
        if (v >= 0 && v < 6 && v == std::floor(v)) return names[int(v)];
    }
    if (key == "grains.radius_distribution") {
        const char* const names[] = {"\"single\"", "\"uniform\"", "\"lognormal\"", "\"sieve\""};
        if (v >= 0 && v < 4 && v == std::floor(v)) return names[int(v)];
    }
    std::string out;
    dem::append_number(out, v);
    return out;
}


// Grain positions: a jittered cubic lattice inside the foil and the funnel above it, filled
// from the bottom up, so the grains never overlap each other, the foil or the funnel.
// A re-fill (refill = true) places its grains the same way above z_floor (the top of the grains
// already in) in the funnel that is there, as many of n as fit, with its own random stream.
// The sites are sized for the largest grain r_max (a size distribution's; else grains.radius).
std::vector<Vec3> generate_grains(const Config& c, const FoilLattice& L, std::size_t n, double z_top,
                                  double funnel_top_radius, double& funnel_height, double r_max, double z_floor = 0.0,
                                  uint64_t stream = 0, bool refill = false) {
    const double rk = r_max, rf = c.foil.particle_radius;
    const double gap = 0.05 * rk;                // [m] clearance to every wall
    const double s = 2.0 * rk * 1.04;            // [m] lattice spacing
    const double r_in = L.radius - rf;           // [m] inner surface of the foil
    std::mt19937_64 rng(c.simulation.seed + stream * 0x9E3779B97F4A7C15ull);
    std::uniform_real_distribution<double> jit(-0.015 * rk, 0.015 * rk);
    // Funnel: cone from r_in at z_top to funnel_top_radius; grow it until the sites suffice.
    if (!refill) funnel_height = 2.0 * r_in;
    for (int attempt = 0; attempt < (refill ? 1 : 40); ++attempt, funnel_height *= refill ? 1.0 : 1.25) {
        std::vector<Vec3> sites;
        const double slope = (funnel_top_radius - r_in) / funnel_height;
        const double half_angle = std::atan(slope);
        const int nxy = int(funnel_top_radius / s) + 1;
        for (int kz = 0;; ++kz) {
            const double z = z_floor + rk + gap + kz * s;
            if (z > z_top + funnel_height - rk - gap) break;
            // Largest centre radius at this height: inside the foil or inside the cone (the
            // wall distance of a cone point is its radial distance times cos(half angle)).
            double rmax;
            if (z + rk <= z_top) rmax = r_in - rk - gap;
            else rmax = r_in + slope * std::max(0.0, z - rk - z_top) - (rk + gap) / std::cos(half_angle);
            // Within one grain radius above z_top the funnel bottom edge and the top ring meet.
            if (z + rk > z_top && z - rk < z_top) rmax = std::min(rmax, r_in - rk - gap);
            const double off = (kz % 2) ? 0.5 * s : 0.0;  // stagger layers
            for (int ix = -nxy; ix <= nxy; ++ix)
                for (int iy = -nxy; iy <= nxy; ++iy) {
                    const double x = ix * s + off, y = iy * s + off;
                    if (std::hypot(x, y) <= rmax) sites.push_back({x, y, z});
                }
            if (sites.size() >= n + n / 20) break;
        }
        if (sites.size() < n && !refill) continue;
        std::vector<Vec3> out(sites.begin(), sites.begin() + long(std::min(n, sites.size())));
        for (Vec3& p : out) p += Vec3{jit(rng), jit(rng), jit(rng)};
        return out;
    }
    throw std::runtime_error("could not place the grains in the foil and funnel");
}

}  // namespace

DamperRun::DamperRun(const Config& c, const DamperOptions& o) : config_(c), options_(o), recorder_(o.out_dir) {
    // One resume rule for every command (the sweep's cases and `vppdem device` alike): running
    // into a folder that holds a run.ckpt again continues that run; --overwrite starts afresh.
    if (options_.from.empty()) {
        options_.from = scene::resume_checkpoint(options_.out_dir, "", options_.overwrite);
        if (!options_.from.empty())
            log("damper: resuming from %s (the same command into the same --out continues its run; --overwrite "
                "starts afresh)\n", options_.from.c_str());
    }
    setup();
}

// The world as the first stage to run finds it: built and filled with grains, or loaded.
void DamperRun::setup() {
    // From a checkpoint: its geometry (and, for a run that started, its settings) first, since
    // the foil is built from the config.
    if (!options_.from.empty()) adopt_checkpoint_settings();
    // A checkpoint's sample holds its radii; its sieve curve is read only when given (a re-fill
    // of a sample in the fill stage needs it, refill() says so).
    if (config_.grains.radius_distribution != 3 || !config_.grains.sieve_curve.empty()) sizes_ = grain_sizes(config_);
    else sizes_.kind = scene::SizeDistribution::Kind::Sieve;
    // A checkpoint's clumps hold their shape; its template is read only when given (a re-fill
    // in the fill stage needs it).
    if (clumps() && (config_.grains.shape != 5 || !config_.grains.clump_template.empty())) shape_ = grain_shape(config_);
    build();
    // Before anything is written or removed (--overwrite): a refused process leaves the folder.
    process_warnings_ = check_process();
    const std::size_t n_foil = lattice_.particles.size();
    // The pour's grains; a checkpoint holds those and its re-fills' (an older one: the pour's).
    const std::size_t n = ckpt_grains_ > 0 ? ckpt_grains_ : grain_count(config_);
    first_grain_ = uint32_t(n_foil);
    end_grain_ = uint32_t(n_foil + n * (clumps() ? shape_.members.size() : 1));
    if (options_.from.empty()) check_grains_fit(n);  // a checkpoint's sample was checked when it was prepared
    // The preparation is frictionless and has no dashpot: local damping is its only dissipation.
    // Without it the pour never comes to rest and the step diverged ("cannot create std::vector
    // larger than max_size()"). From a prepared sample 0 is a dynamic run (docs/damper.md).
    if (options_.from.empty() && config_.simulation.local_damping == 0.0)
        throw std::runtime_error("config key 'simulation.local_damping' = 0: the preparation (frictionless, no "
                                 "dashpot) then dissipates nothing and the poured grains never come to rest; allowed "
                                 "here: in (0, 0.9] (default 0.2). For an undamped run give process.local_damping = 0: "
                                 "the preparation keeps simulation.local_damping, the vacuum and cycling have none");

    if (options_.from.empty()) {
        // Materials in fixed order: grain (frictionless while filling), cap, funnel.
        dem::Material g{"grain", config_.grains.density, config_.grains.young, config_.grains.stiffness_ratio, 0.0, 1.0};
        world_.add_material(g);
        dem::Material cap{"cap", config_.grains.density, config_.grains.young, config_.grains.stiffness_ratio, 0.0, 1.0};
        world_.add_material(cap);
        dem::Material fun{"funnel", config_.grains.density, config_.grains.young, config_.grains.stiffness_ratio, 0.0, 1.0};
        world_.add_material(fun);
        for (uint32_t i : bottom_ring_) world_.set_fixed(i);
        for (uint32_t i : top_ring_) world_.set_fixed(i);
        double funnel_h = 0;
        const double funnel_top_r = 1.6 * lattice_.radius;
        const auto pos = generate_grains(config_, lattice_, n, z_top_, funnel_top_r, funnel_h, grain_reach(sizes_.max_radius()));
        add_grains(pos, draw_radii(pos.size(), 0), 0);
        end_grain_ = uint32_t(world_.particles.size());
        double zmax = 0;
        for (const Vec3& p : pos) zmax = std::max(zmax, p.z);
        dem::Plane bottom;
        bottom.point = {0, 0, 0};
        bottom.normal = {0, 0, 1};
        bottom.material = kCapMat;
        bottom.mask = kMaskCap;
        world_.add_plane(bottom);
        dem::Plane top = bottom;
        top.point = {0, 0, std::max(zmax + grain_reach(sizes_.max_radius()) + 1e-3, z_top_)};
        top.normal = {0, 0, -1};
        world_.add_plane(top);
        for (dem::Facet f : dem::make_funnel_facets({0, 0, z_top_}, lattice_.radius, funnel_top_r, funnel_h, 72, true)) {
            f.material = kFunnelMat;
            f.mask = kMaskCap;
            world_.add_facet(f);
        }
        state_.geometry = values_of(config_, kGeometryKeys);
        for (const auto& [k, v] : values_of(config_, kPreparationKeys)) state_.geometry[k] = v;
        state_.grains = grain_count_now();
        state_.report["prepare.grains_poured"] = double(grain_count_now());
        state_.report["prepare.funnel_height"] = funnel_h;
        world_.params.dt = resolve_dt(config_.simulation, world_);
        check_steps();            // refuses a step that is no number, unstable, or too many of them
        check_sampling(true);     // refuses sampling faster than the time step
        recorder_.open(false, options_.overwrite, options_.from);  // only now: bad input writes nothing
        if (mesh_foil())
            log("damper: %zu grains (r_k = %.4g m), mesh foil of %zu particles (%zu vacancies, %zu bonds; end rings "
                "%zu and %zu), radius %.5g m, height %.5g m, dt = %.4g s, %d thread(s)\n", n, config_.grains.radius, n_foil,
                membrane_.vacancies, membrane_.bonds.size(), bottom_ring_.size(), top_ring_.size(), lattice_.radius, z_top_, world_.params.dt,
                config_.simulation.threads);
        else
            log("damper: %zu grains (r_k = %.4g m), foil %d x %d = %zu particles (radius %.5g m), height %.5g m, "
                "dt = %.4g s, %d thread(s)\n", n, config_.grains.radius, lattice_.cols, lattice_.rows, n_foil, lattice_.radius, z_top_,
                world_.params.dt, config_.simulation.threads);
        next_stage(Stage::Fill);
    } else {
        const std::string blob = dem::load_checkpoint(options_.from, world_);
        state_ = RunState::load(blob, options_.from);
        // Clumps: every clump a grain, its members the particles after the foil.
        if (clumps() && world_.clumps().size() == n) end_grain_ = uint32_t(n_foil + world_.clumps().member.size());
        if (world_.particles.size() != end_grain_ || (clumps() ? world_.clumps().size() != n : !world_.clumps().empty()))
            throw std::runtime_error("checkpoint '" + options_.from + "' does not hold this damper's particles");
        state_.grains = n;
        // The mesh foil's pressure fans are not in the checkpoint (DamperRecorder::save_world): from the foil.
        if (mesh_foil() && state_.stage >= Stage::Vacuum) set_foil_pressure();
        state_.warnings.insert(state_.warnings.end(), pending_warnings_.begin(), pending_warnings_.end());
        if (ckpt_cycles_ > 0) {
            state_.settings["process.cycles"] = double(config_.process.cycles);  // what its checkpoints now say
            extend_cycling(ckpt_cycles_);
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
            apply_config_to_prepared();
            world_.params.dt = resolve_dt(config_.simulation, world_);
            check_steps();
            check_sampling(true);
        }
        recorder_.open(resuming, options_.overwrite, options_.from);
        log("damper: starting from %s at stage '%s', t = %.4g s, %d thread(s)\n", options_.from.c_str(),
            stage_name(state_.stage), world_.time, config_.simulation.threads);
    }
    world_.params.threads = config_.simulation.threads;
    for (const std::string& w : check_sampling(false)) process_warnings_.push_back(w);
    // The sample's own: with it, in prepared.ckpt too.
    if (!sizes_.sieve_note.empty()) warn_once({"grains.sieve_curve: " + sizes_.sieve_note});
}

void DamperRun::warn_once(const std::vector<std::string>& what) {
    for (const std::string& w : what)
        if (std::find(state_.warnings.begin(), state_.warnings.end(), w) == state_.warnings.end()) warn(w);
}

namespace {

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

}  // namespace

std::vector<std::string> DamperRun::check_process() const {
    std::vector<std::string> warnings;
    const ProcessDef& p = config_.process;
    const double H = z_top_, A = p.amplitude, off = p.start_offset;
    // The stroke against the sample's height H. A poured packing (about 0.6) reaches the densest
    // packing of spheres (0.74) at a compression of 1 - 0.6 / 0.74 = 19% of its height: beyond
    // about 20% the grains themselves must deform, i.e. the contact model's overlaps carry the
    // stroke (warned). At half the height they would overlap by about their own size, and the
    // linear contact law means nothing (refused; start_offset 0.02 on a 30 mm damper gave W
    // -440, amplitude 0.035 gave W 9.7e6). Upwards the foil is stretched by the same fraction
    // of its height: beyond 50% a polymer foil tears (tension.strain is limited to 0.5 too).
    constexpr double kWarnStrain = 0.2, kMaxStrain = 0.5;  // [-] of the damper height
    const double down = off + (p.compression_first ? A : 0.0);  // [m] the cap's lowest point below its start
    const double up = -off + (p.compression_first ? 0.0 : A);   // [m] its highest above
    auto blame = [&](bool downward) {
        const bool stroke = downward ? p.compression_first : !p.compression_first;
        const double offset_part = downward ? off : -off;
        if (stroke && offset_part <= 0.0) return std::string("process.amplitude' = ") + show("", A);
        if (!stroke) return std::string("process.start_offset' = ") + show("", off);
        return std::string("process.start_offset' = ") + show("", off) + " with 'process.amplitude' = " + show("", A);
    };
    auto refuse = [&](bool downward, double d) {
        throw std::runtime_error(
            "config key '" + blame(downward) + ": the cap would move " + fmt("%.4g", 1e3 * d) + " mm " +
            (downward ? "down" : "up") + ", " + fmt("%.0f", 100.0 * d / H) + "% of the sample's height " +
            fmt("%.4g", 1e3 * H) + " mm (damper.height); allowed: less than " + fmt("%.0f", 100.0 * kMaxStrain) +
            "% of the height (" + fmt("%.4g", 1e3 * kMaxStrain * H) + " mm here): " +
            (downward ? "beyond, the grains would overlap by about their own size (a crushed sample, not a damper)"
                      : "beyond, the foil would be stretched past tearing"));
    };
    if (down >= kMaxStrain * H) refuse(true, down);
    if (up >= kMaxStrain * H) refuse(false, up);
    if (down > kWarnStrain * H)
        warnings.push_back("process: the cap moves " + fmt("%.4g", 1e3 * down) + " mm down, " +
                           fmt("%.0f", 100.0 * down / H) + "% of the sample's height: beyond about 20% a poured "
                           "packing is past the densest packing and the grains' overlaps carry the stroke; W measures "
                           "the contact model, not the damper (docs/config.md, \"Limits from the physics\")");
    if (up > kWarnStrain * H)
        warnings.push_back("process: the cap moves " + fmt("%.4g", 1e3 * up) + " mm up, " +
                           fmt("%.0f", 100.0 * up / H) + "% of the sample's height: the foil is stretched by about as "
                           "much (docs/config.md, \"Limits from the physics\")");
    // The contacts against the load. The underpressure dp (or, without it, the weight of the
    // column, rho g H) presses a grain over its cross-section (2 r)^2 into contacts of stiffness
    // about E r / 2 (linear law, harmonic mean of E r): an overlap of delta / r = 8 load / E. At
    // half the radius the grains sit in each other (a modulus of 5e-324 Pa gave NaN): refused. The
    // foil, a cylinder of radius R under dp, stretches by the hoop strain dp R / (E_f t_f); beyond
    // 50% a polymer foil tears (as tension.strain and the stroke up).
    {
        constexpr double kMaxOverlap = 0.5;    // [grain radii]
        constexpr double kMaxHoopStrain = 0.5; // [-]
        constexpr double kGravity = 9.81;      // [m/s^2]
        const double weight = config_.grains.density * kGravity * H;  // [Pa] at the column's foot
        const double load = std::max(p.underpressure, weight);    // [Pa]
        const double overlap = 8.0 * load / config_.grains.young;
        const std::string by = weight > p.underpressure
                                   ? " with 'grains.density' = " + show("", config_.grains.density) + ": under the column's "
                                     "weight rho g H = " + fmt("%.4g", weight) + " Pa"
                                   : ": under process.underpressure = " + show("", p.underpressure) + " Pa";
        if (!(overlap <= kMaxOverlap))
            throw std::runtime_error(
                "config key 'grains.young' = " + show("", config_.grains.young) + by + " the grains would overlap by about " +
                fmt("%.3g", overlap) + " of their radius (8 load / E); allowed: at least " +
                fmt("%.4g", 8.0 * load / kMaxOverlap) + " Pa here (an overlap under half the radius)");
        const double strain = p.underpressure * lattice_.radius / (config_.foil.young * config_.foil.thickness);
        if (!(strain <= kMaxHoopStrain))
            throw std::runtime_error(
                "config key 'foil.young' = " + show("", config_.foil.young) + " with 'foil.thickness' = " +
                show("", config_.foil.thickness) + ": under process.underpressure = " + show("", p.underpressure) +
                " Pa the foil would stretch by " + fmt("%.3g", strain) + " (the hoop strain dp R / (E_f t_f), R = " +
                fmt("%.4g", lattice_.radius) + " m); allowed: E_f t_f at least " +
                fmt("%.4g", p.underpressure * lattice_.radius / kMaxHoopStrain) + " N/m here (a strain under 50%: beyond, "
                "a polymer foil tears)");
    }
    // Local damping above 0.5: an oscillation already loses most of its amplitude each half
    // period; more holds the grains back, and the loop's area is then largely the damping's.
    if (cycling_local_damping(config_) > 0.5)
        warnings.push_back("local damping " + show("", cycling_local_damping(config_)) + " from the vacuum on (" +
                           (config_.process.local_damping >= 0.0 ? "process" : "simulation") + ".local_damping) is above 0.5: "
                           "it holds the grains back, and W is then largely the damping's (cycles.csv "
                           "damping_dissipation)");
    // A frequency sets the period and the start offset's speed (2 A f): the velocity is then
    // not used at all.
    if (p.frequency > 0.0 && config_.given.count("process.velocity"))
        warnings.push_back("process.velocity = " + show("", p.velocity) + " m/s is not the cap's speed: process.frequency = " +
                           show("", p.frequency) + " Hz sets the period (peak speed " +
                           fmt("%.4g", peak_speed(p)) + " m/s) and the start offset's speed: the velocity is not used");
    // A pump-down runs until the pump has drawn the gas down: time constant V / S, the stage
    // waiting five of them. The gas volume is at most the foil's interior less the poured grains.
    if (p.pressure_model != 0 && p.pump_down && p.pump_speed > 0.0) {
        constexpr double kMaxPumpDown = 60.0;  // [s] of simulated time: a minute (2 m^3/h on the paper's damper: 0.7 s)
        const double r_in = lattice_.radius - config_.foil.particle_radius;
        const double gas = std::numbers::pi * r_in * r_in * H * (1.0 - config_.grains.volume_fraction);
        const double t = 5.0 * gas / p.pump_speed;
        if (t > kMaxPumpDown)
            throw std::runtime_error(
                "config key 'process.pump_speed' = " + show("", p.pump_speed) + ": the pump-down (process.pump_down) "
                "would take about " + fmt("%.3g", t) + " s (" + fmt("%.3g", t / 3600.0) + " h) of simulated time to "
                "draw the gas (about " + fmt("%.3g", gas * 1e3) + " L) down (5 V / S); allowed: at most " +
                fmt("%g", kMaxPumpDown) + " s, i.e. process.pump_speed >= " + fmt("%.3g", 5.0 * gas / kMaxPumpDown) +
                " m^3/s here, or process.pump_down = false");
    }
    return warnings;
}

namespace {

// Of the keys that set the critical step sqrt(m/k), the one given farthest from its default (in
// decades, either way), as "key = value": the one a message about the step should name first.
std::string step_key(const Config& c) {
    const std::pair<const char*, double> parts[] = {{"grains.young", c.grains.young},     {"foil.young", c.foil.young},
                                                    {"foil.thickness", c.foil.thickness}, {"grains.density", c.grains.density},
                                                    {"foil.density", c.foil.density},     {"grains.radius", c.grains.radius}};
    std::string best = "grains.young = " + show("", c.grains.young);
    double most = -1.0;
    for (const auto& [key, value] : parts) {
        const Setting* s = find_setting(key);
        if (s == nullptr || !(s->def > 0.0) || !(value > 0.0)) continue;
        const double d = std::abs(std::log10(value / s->def));
        if (d > most) most = d, best = std::string(key) + " = " + show("", value);
    }
    return best;
}

}  // namespace

void DamperRun::check_steps() const {
    const SimulationDef& sim = config_.simulation;
    const ProcessDef& p = config_.process;
    const double dt = world_.params.dt, critical = world_.critical_dt();
    // The automatic step comes from every contact's stiffness and every particle's mass; a
    // message names first the key farthest from its default (step_key).
    auto from_auto = [&] {
        return "simulation.dt_safety = " + show("", sim.dt_safety) + " times the critical step sqrt(m/k) of the "
               "contacts, here from " + step_key(config_) + " (of grains.young, grains.density, grains.radius, "
               "foil.young, foil.thickness, foil.density, the stiffness ratios)";
    };
    const bool tiny = !(dt >= std::numeric_limits<double>::min());
    // A modulus of 1e300 or 5e-324 leaves a step of 0, a subnormal or infinity: nothing to integrate with.
    if (tiny || !std::isfinite(dt)) {
        const std::string key = sim.dt_auto ? step_key(config_) : "simulation.dt = " + show("", sim.dt);
        throw std::runtime_error("config key '" + key.substr(0, key.find(' ')) + "' = " + key.substr(key.find('=') + 2) +
                                 ": the time step " + fmt("%.3g", dt) + " s (" +
                                 (sim.dt_auto ? from_auto() : key) + ") is not a positive finite number of "
                                 "seconds; allowed: moduli, densities and sizes of real materials");
    }
    const std::string source = sim.dt_auto ? from_auto() : "simulation.dt = " + show("", sim.dt);
    // A fixed step has the automatic one's bound: half one contact's critical step (dt_safety <= 0.5).
    if (!sim.dt_auto && std::isfinite(critical) && sim.dt > 0.5 * critical)
        throw std::runtime_error("config key 'simulation.dt' = " + show("", sim.dt) + ": more than half the critical "
                                 "step sqrt(m/k) = " + fmt("%.4g", critical) + " s of the stiffest contact (the bound of "
                                 "simulation.dt_safety); allowed: at most " + fmt("%.4g", 0.5 * critical) +
                                 " s here, or \"auto\"");
    // The neighbour lists' skin: a few tenths of a radius saves list rebuilds; ten radii already
    // lists hundreds of pairs per grain that never touch, and 1e300 m overflowed the cell grid.
    const double max_skin = 10.0 * sizes_.max_radius();
    if (!(sim.skin <= max_skin))
        throw std::runtime_error("config key 'simulation.skin' = " + show("", sim.skin) + ": allowed: at most ten "
                                 "times the largest grain radius (" + fmt("%.4g", max_skin) + " m here; 0: half the "
                                 "smallest radius)");
    // The steps the run needs from the vacuum on: the ramp, the hold and every cycle. 1e12 steps
    // are 33,000 of the paper's cycles (3e7 steps each), months on any machine: beyond, a value is
    // a slip (a velocity of 1e-300 m/s, a modulus of 1e300 Pa), not a run.
    constexpr double kMaxSteps = 1e12;
    const double T = cycle_period(p), cycling = double(p.cycles) * T;
    const double total = cycling + p.ramp_time + p.hold_time;  // [s] of simulated time
    if (!(total / dt <= kMaxSteps)) {
        // The count is a ratio: the message leads with the factor farther outside what a damper
        // run has (up to 1000 s of simulated time; a step of at least 1 ns).
        const bool blame_step = std::log10(1e-9 / dt) > std::log10(total / 1e3);
        std::string what;
        if (blame_step) {
            const std::string key = sim.dt_auto ? step_key(config_) : "simulation.dt = " + show("", sim.dt);
            what = key;
        } else if (cycling >= p.ramp_time && cycling >= p.hold_time) {
            // One cycle longer than a whole run: the period's key; else the count of cycles.
            const std::string period = p.frequency > 0.0 ? "process.frequency = " + show("", p.frequency)
                                                         : "process.velocity = " + show("", p.velocity) +
                                                               " (period 2 process.amplitude / process.velocity)";
            what = T > 1e3 ? period + ", " + std::to_string(p.cycles) + " cycles of " + fmt("%.4g", T) + " s"
                           : "process.cycles = " + std::to_string(p.cycles) + " cycles of " + fmt("%.4g", T) + " s (" +
                                 period + ")";
        }
        else if (p.ramp_time >= p.hold_time)
            what = "process.ramp_time = " + show("", p.ramp_time);
        else
            what = "process.hold_time = " + show("", p.hold_time);
        throw std::runtime_error("config key '" + what.substr(0, what.find(' ')) + "' (" + what + "): the run would take " +
                                 fmt("%.3g", total / dt) + " steps, " + fmt("%.4g", total) + " s of simulated time (the "
                                 "cycles, process.ramp_time and process.hold_time) over a time step of " +
                                 fmt("%.3g", dt) + " s (" + source + "); allowed: at most " + fmt("%.0e", kMaxSteps) +
                                 " steps (months on any machine)");
    }
}

std::vector<std::string> DamperRun::check_sampling(bool refuse) const {
    std::vector<std::string> warnings;
    const ProcessDef& p = config_.process;
    const double T = cycle_period(p), dt = world_.params.dt;
    if (!(dt > 0.0)) return warnings;
    const double spacing = T / double(p.samples_per_cycle);  // [s] between two samples
    // One sample per step at most: more samples per cycle than steps fall behind, and the run
    // ends with fewer cycles recorded than asked.
    // The period's own keys are named too: a velocity of 1e300 m/s is the slip, not the count.
    const std::string period = p.frequency > 0.0 ? "process.frequency = " + show("", p.frequency)
                                                 : "2 process.amplitude / process.velocity = 2 x " + show("", p.amplitude) +
                                                       " m / " + show("", p.velocity) + " m/s";
    if (spacing < dt && refuse)
        throw std::runtime_error("config key 'process.samples_per_cycle' = " + std::to_string(p.samples_per_cycle) +
                                 ": a sample every " + fmt("%.3g", spacing) + " s (the period " + fmt("%.4g", T) +
                                 " s, " + period + ", / samples_per_cycle) is less than the time step " + fmt("%.3g", dt) +
                                 " s; allowed: at most " + fmt("%.0f", std::floor(T / dt)) +
                                 " here (one sample per step), or a longer period");
    if (spacing < dt)
        warnings.push_back("process.samples_per_cycle = " + std::to_string(p.samples_per_cycle) + " asks for a sample every " +
                           fmt("%.3g", spacing) + " s, less than the time step " + fmt("%.3g", dt) +
                           " s: at most one sample is taken per step, so at most " +
                           fmt("%.0f", std::floor(T / dt)) + " per cycle are taken and the last cycles go unrecorded");
    // Each sample averages the forces since the previous one at most: a longer window is cut.
    if (p.sample_window > spacing)
        warnings.push_back("process.sample_window = " + show("", p.sample_window) + " s is longer than the samples' "
                           "spacing " + fmt("%.3g", spacing) + " s (period / process.samples_per_cycle): each force is "
                           "averaged over the spacing only");
    return warnings;
}

void DamperRun::log(const char* fmt, ...) const {
    if (options_.quiet) return;
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stderr, fmt, ap);
    va_end(ap);
}

}  // namespace damper_detail

SampleRecord read_sample_record(const std::string& checkpoint) {
    using namespace damper_detail;
    dem::World scratch;
    const RunState ck = RunState::load(dem::load_checkpoint(checkpoint, scratch), checkpoint);
    SampleRecord r;
    r.prepared = ck.stage == Stage::Prepared;
    r.keys = ck.geometry;
    for (const StoredKey& k : kGeometryKeys)
        if (!r.keys.count(k.key) && std::isfinite(k.legacy)) r.keys[k.key] = k.legacy;
    return r;
}

std::string sample_misfit(const Config& c, const SampleRecord& sample, bool preparation_keys) {
    using namespace damper_detail;
    if (!sample.prepared) return "not a prepared sample (its stage is past the preparation)";
    const std::map<std::string, double>& stored = sample.keys;
    std::string diffs;
    auto compare = [&](const StoredKey& k, bool missing_differs) {
        const auto it = stored.find(k.key);
        if (it == stored.end() && !missing_differs) return;  // an older vppdem's sample: not recorded
        if (it != stored.end() && same_value(it->second, k.get(c))) return;
        diffs += (diffs.empty() ? "" : ", ") + std::string(k.key) + " = " +
                 (it == stored.end() ? std::string("?") : show(k.key, it->second)) + " (the case: " +
                 show(k.key, k.get(c)) + ")";
    };
    for (const StoredKey& k : kGeometryKeys) compare(k, true);
    if (preparation_keys)
        for (const StoredKey& k : kPreparationKeys) compare(k, false);
    return diffs;
}

namespace damper_detail {

void DamperRun::adopt_checkpoint_settings() {
    dem::World scratch;  // only the app state is needed here; run() loads the World itself
    const RunState ck = RunState::load(dem::load_checkpoint(options_.from, scratch), options_.from);
    // Geometry: a key the config gives must match the sample's; the others take its values.
    std::string diffs;
    std::map<std::string, double> geometry = ck.geometry;
    for (const StoredKey& k : kGeometryKeys)
        if (!geometry.count(k.key) && std::isfinite(k.legacy)) geometry[k.key] = k.legacy;
    for (const StoredKey& k : kGeometryKeys) {
        const auto it = geometry.find(k.key);
        const double value = k.get(config_);
        if (it != geometry.end() && !config_.given.count(k.key)) {
            k.set(config_, it->second);
        } else if (it != geometry.end() && (std::string(k.key) == "grains.sieve_curve" ||
                                            std::string(k.key) == "grains.clump_template") &&
                   !same_value(it->second, value)) {
            const std::string& file = std::string(k.key) == "grains.sieve_curve" ? config_.grains.sieve_curve
                                                                                 : config_.grains.clump_template;
            diffs += (diffs.empty() ? "" : ", ") + std::string(k.key) + ": the sample was drawn from " +
                     (it->second == 0.0 ? std::string("none") : std::string("a file with other numbers")) +
                     " (the config asks for " + (file.empty() ? std::string("none") : "'" + file + "'") + ")";
        } else if (it == geometry.end() || !same_value(it->second, value)) {
            diffs += (diffs.empty() ? "" : ", ") + std::string(k.key) + " = " +
                     (it == geometry.end() ? std::string("?") : show(k.key, it->second)) +
                     " (the config asks for " + show(k.key, value) + ")";
        }
    }
    // A study's branch: the keys that acted during the preparation must be the case's too, or
    // the case would cycle a sample its settings did not make (a stiffer grain settles into
    // another packing). A checkpoint of an older vppdem did not record them: not checked.
    if (options_.check_preparation && ck.stage == Stage::Prepared)
        for (const StoredKey& k : kPreparationKeys) {
            const auto it = ck.geometry.find(k.key);
            if (it != ck.geometry.end() && !same_value(it->second, k.get(config_)))
                diffs += (diffs.empty() ? "" : ", ") + std::string(k.key) + " = " + show(k.key, it->second) +
                         " (the config asks for " + show(k.key, k.get(config_)) + "; it acts during the preparation)";
        }
    ckpt_grains_ = ck.grains;
    if (!diffs.empty())
        throw std::runtime_error("checkpoint '" + options_.from + "' was prepared with another geometry: " + diffs +
                                 "; prepare a new sample (run without --from)");
    if (ck.settings.empty()) {
        // A prepared sample (or a run stopped before its settings were applied) takes the
        // config's settings. Only a checkpoint of an older vppdem can be past that point
        // without them: it is run with the config's settings, as that vppdem did.
        if (ck.stage > Stage::Prepared) {
            pending_warnings_.push_back("resume: the checkpoint (an older vppdem's) stores no run settings; the "
                                        "config's are used");
            log("damper: warning: checkpoint '%s' (an older vppdem's) stores no process settings: the config's are "
                "used; give the ones the run started with\n", options_.from.c_str());
        }
        return;
    }
    // A run that started: it continues with its own settings, whatever the command line says;
    // a key given with another value is refused rather than spliced into the record.
    std::string conflicts;
    for (const StoredKey& k : kRunKeys) {
        const auto it = ck.settings.find(k.key);
        // A key an older vppdem did not store: the run went on with the value it had then
        // (the key's legacy value), e.g. process.pressure_model "constant".
        if (it == ck.settings.end() && !std::isfinite(k.legacy)) continue;
        const double stored = it != ck.settings.end() ? it->second : k.legacy;
        // More cycles than the run started with: it goes on (extend_cycling); fewer would end a
        // record that already holds them, or promise a run it is not.
        if (std::string(k.key) == "process.cycles" && config_.given.count(k.key) && k.get(config_) > stored) {
            ckpt_cycles_ = int(stored);
            continue;
        }
        if (config_.given.count(k.key) && !same_value(k.get(config_), stored))
            conflicts += (conflicts.empty() ? "" : ", ") + std::string(k.key) + " = " + show(k.key, stored) +
                         " in the checkpoint, " + show(k.key, k.get(config_)) + " given" +
                         (std::string(k.key) == "process.cycles" ? " (more cycles continue the run, fewer cannot)" : "");
        else
            k.set(config_, stored);
    }
    if (!conflicts.empty())
        throw std::runtime_error("checkpoint '" + options_.from + "' continues a run with other settings: " + conflicts +
                                 "; a resumed run keeps the settings it started with: leave these keys out (or give "
                                 "the checkpoint's values), or start a new run from the sample's prepared.ckpt");
}

std::vector<double> DamperRun::draw_radii(std::size_t n, uint64_t stream) const {
    if (sizes_.kind == scene::SizeDistribution::Kind::Single) return std::vector<double>(n, config_.grains.radius);
    // A stream of its own (not the positions'), one per fill: the pour 0, re-fill k stream k.
    std::mt19937_64 rng((config_.simulation.seed ^ 0x51E7E5C0FFEEull) + stream * 0x9E3779B97F4A7C15ull);
    std::vector<double> r(n);
    for (double& x : r) x = sizes_.draw(rng);
    return r;
}

void DamperRun::report_grain_sizes() {
    if (sizes_.kind == scene::SizeDistribution::Kind::Single) return;  // every grain grains.radius
    const scene::SizeStats s = scene::size_stats(grain_radii());
    auto& rep = state_.report;
    rep["prepare.radius_mean"] = s.mean;
    rep["prepare.radius_sd"] = s.sd;
    rep["prepare.radius_min"] = s.min;
    rep["prepare.radius_max"] = s.max;
    rep["prepare.d10"] = s.d10;
    rep["prepare.d50"] = s.d50;
    rep["prepare.d90"] = s.d90;
}

void DamperRun::check_grains_fit(std::size_t n) {
    const double rk = sizes_.max_radius();
    const double r_in = lattice_.radius - config_.foil.particle_radius;  // [m] inner surface of the foil
    if (rk > r_in / 3.0) {
        const char* const kinds[] = {"single", "uniform", "lognormal", "sieve"};
        const std::string what = sizes_.kind == scene::SizeDistribution::Kind::Single
                                     ? "config key 'grains.radius' = " + show("", rk) + ": too large"
                                     : std::string("config key 'grains.radius_distribution' = \"") +
                                           kinds[config_.grains.radius_distribution] + "\": its largest grain (radius " +
                                           show("", rk) + " m) is too large";
        throw std::runtime_error(what + " for the damper; at most a third of the foil's inner radius (" +
                                 show("", r_in / 3.0) + " m)");
    }
    // A clump reaches further than its volume-equivalent radius: one whose members span more
    // than half the foil's inner radius from its centre cannot turn inside the foil, and a
    // template reaching the foil's inner radius itself was accepted (issue 48) where a sphere of
    // a third of it is refused.
    if (clumps() && grain_reach(rk) > 0.5 * r_in) {
        const char* const shapes[] = {"sphere", "dimer", "trimer", "tetrahedron", "pellet", "template"};
        const std::string what = config_.grains.shape == 5 ? "config key 'grains.clump_template' = '" + config_.grains.clump_template + "'"
                                                      : std::string("config key 'grains.shape' = \"") + shapes[config_.grains.shape] + "\"";
        throw std::runtime_error(what + ": its grains reach " + show("", grain_reach(rk)) + " m from their centre (at "
                                 "grains.radius " + show("", rk) + " m); at most half the foil's inner radius (" +
                                 show("", 0.5 * r_in) + " m), so that a grain can turn inside the foil");
    }
    // Fewest grains: one layer across the foil. A VPP damper is a packing that the vacuum
    // jams; grains that do not even cover the bottom once lie loose on the lower cap, the
    // cap never loads them and the "loop" is the foil's alone (0 grains gave a negative W).
    // A hexagonal layer of circles of radius r_k covers pi / (2 sqrt 3) = 0.907 of the area.
    const double v_grain = sizes_.mean_volume();
    const std::size_t n_layer = std::size_t(std::max(1.0, std::floor(0.9069 * (r_in / rk) * (r_in / rk))));
    if (n < n_layer) {
        const double phi_min = double(n_layer) * v_grain /
                               (std::numbers::pi * config_.damper.radius * config_.damper.radius * config_.damper.height);
        throw std::runtime_error("config key 'grains.volume_fraction' = " + show("", config_.grains.volume_fraction) +
                                 ": gives " + std::to_string(n) + " grain(s) in this damper; at least " +
                                 std::to_string(n_layer) + " are needed (one layer across the foil's inner radius " +
                                 show("", r_in) + " m), i.e. grains.volume_fraction >= " + show("", phi_min));
    }
    // Densest: the grains must fit into the foil once the cap is down. Poured grains settle at
    // random close packing (0.64) at most; more needs the foil to bulge out, which it does (it
    // is elastic), by a hoop strain of sqrt(phi_in / 0.64) - 1: unusual, warned. Above the
    // densest packing of spheres (0.74, a perfect crystal) the grains cannot be put into the
    // unstretched foil at all: refused.
    const double v_in = std::numbers::pi * r_in * r_in * z_top_;
    const double phi_in = double(n) * v_grain / v_in;
    if (phi_in > 0.74)
        throw std::runtime_error("config key 'grains.volume_fraction' = " + show("", config_.grains.volume_fraction) +
                                 ": " + std::to_string(n) + " grains fill " + show("", std::round(1000 * phi_in) / 10) +
                                 "% of the foil's interior (radius " + show("", r_in) + " m, height " +
                                 show("", z_top_) + " m); at most 74% (the densest sphere packing) can be prepared");
    if (phi_in > 0.64) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "prepare: %zu grains fill %.1f%% of the foil's interior, above random close packing (64%%): the "
                      "foil bulges by about %.1f%% (hoop strain) when the cap compresses them",
                      n, 100.0 * phi_in, 100.0 * (std::sqrt(phi_in / 0.64) - 1.0));
        warn(msg);
    }
}

void DamperRun::build() {
    // Foil first: its particles are 0 .. n_f - 1 and its material index 0.
    world_.params.gravity = {0, 0, -9.81};
    world_.params.local_damping = config_.simulation.local_damping;
    world_.params.threads = config_.simulation.threads;
    world_.params.skin = config_.simulation.skin;
    world_.set_bond_arm(config_.foil.bond_arm);
    if (mesh_foil()) {
        // The lattice's cylinder (its ring radius and height, which the paper's rules choose
        // from damper.radius and damper.height), built by the membrane builder: the two foils
        // differ in their network only.
        const double rf = config_.foil.particle_radius;
        const double R = rf / std::sin(std::numbers::pi / choose_columns(config_.damper.radius, rf));
        const double H = (choose_rows(config_.damper.height, rf) - 1) * 2.0 * rf;
        const MembraneDef d = membrane_def();
        membrane_ = membrane_tube_sites(d, R, H, 0.0);
        place_membrane(world_, d, membrane_);
        lattice_ = FoilLattice{};
        lattice_.radius = R;
        lattice_.spacing = 2.0 * rf;
        lattice_.material = membrane_.material;
        lattice_.particles = membrane_.particles;
        z_top_ = H;
        bottom_ring_ = membrane_.boundary[0];
        top_ring_ = membrane_.boundary[1];
        std::vector<uint8_t> ring(world_.particles.size(), 0);
        for (uint32_t i : bottom_ring_) ring[i] = 1;
        for (uint32_t i : top_ring_) ring[i] = 1;
        free_foil_.clear();
        for (uint32_t i : membrane_.particles)
            if (!ring[i]) free_foil_.push_back(i);
        return;
    }
    lattice_ = build_cylinder(world_, config_.foil, config_.damper.radius, config_.damper.height);
    z_top_ = (lattice_.rows - 1) * lattice_.spacing;
    top_ring_ = lattice_.row(lattice_.rows - 1);
    bottom_ring_ = lattice_.row(0);
    free_foil_.clear();
    for (int k = 1; k + 1 < lattice_.rows; ++k)
        for (uint32_t i : lattice_.row(k)) free_foil_.push_back(i);
}

MembraneDef DamperRun::membrane_def() const {
    // The paper's foil (E_f, t_f, r_f, rho_f, ks/kn) on bonds of 2 r_f, with the paper's 25% of
    // vacancies drawn at random (the lattice's odd-odd pattern has no analogue on a
    // triangulation), seeded by the sample's seed, and the MatchFoil rule: E t = E_f t_f on the
    // full network, times 2.05, which restores the biaxial stiffness the vacancies halve
    // (measured strain ratio 2.04-2.08 over 3 seeds, docs/membrane.md).
    constexpr double kVacancyStiffening = 2.05;  // [-]
    MembraneDef d;
    d.foil = config_.foil;
    d.stiffness = MembraneStiffness::MatchFoil;
    d.stiffness_factor = kVacancyStiffening;
    d.vacancies = true;
    d.vacancy_fraction = 0.25;
    d.seed = config_.simulation.seed;
    return d;
}

void DamperRun::warn(const std::string& what) {
    std::string w = what;
    for (char& ch : w)
        if (ch == '\n' || ch == '\r') ch = ' ';
    state_.warnings.push_back(w);
    // On stderr with --quiet too: a value that does not do what it seems must not go unseen
    // (summary.json keeps it as well).
    // A study's cases run quietly side by side: each names its folder.
    if (options_.quiet && !options_.out_dir.empty()) std::fprintf(stderr, "damper %s: warning: %s\n", options_.out_dir.c_str(), w.c_str());
    else std::fprintf(stderr, "damper: warning: %s\n", w.c_str());
}

double DamperRun::highest_grain_top() const {
    double top = 0;
    for (uint32_t i = first_grain_; i < end_grain_; ++i) top = std::max(top, world_.particles.pos[i].z + world_.particles.radius[i]);
    return top;
}

void DamperRun::add_grains(const std::vector<Vec3>& pos, const std::vector<double>& radii, uint64_t stream) {
    if (!clumps()) {
        for (std::size_t k = 0; k < pos.size(); ++k) {
            dem::SphereDef d;
            d.position = pos[k];
            d.radius = radii[k];
            d.material = kGrainMat;
            d.mask = kGrainMask;
            world_.add_sphere(d);
        }
        return;
    }
    // Uniform random orientations (Shoemake's unit quaternion from three uniform numbers), a
    // stream of their own (not the positions' nor the radii's), one per fill.
    std::mt19937_64 rng((config_.simulation.seed ^ 0x0C1A5E0F0A11ull) + stream * 0x9E3779B97F4A7C15ull);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t k = 0; k < pos.size(); ++k) {
        const double u1 = u(rng), u2 = 2.0 * std::numbers::pi * u(rng), u3 = 2.0 * std::numbers::pi * u(rng);
        const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
        dem::ClumpDef d;
        d.position = pos[k];
        d.orientation = {a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3)};
        d.material = kGrainMat;
        d.mask = kGrainMask;
        world_.add_clump(dem::scaled(shape_, radii[k]), d);
    }
}

std::vector<double> DamperRun::grain_radii() const {
    if (!clumps()) return std::vector<double>(world_.particles.radius.begin() + first_grain_, world_.particles.radius.begin() + end_grain_);
    std::vector<double> r;
    const double rho = world_.materials[kGrainMat].density;
    for (double m : world_.clumps().mass) r.push_back(std::cbrt(3.0 * m / (4.0 * std::numbers::pi * rho)));
    return r;
}

std::vector<double> DamperRun::grain_tops() const {
    const dem::Particles& p = world_.particles;
    if (!clumps()) {
        std::vector<double> tops;
        for (uint32_t i = first_grain_; i < end_grain_; ++i) tops.push_back(p.pos[i].z + p.radius[i]);
        return tops;
    }
    const dem::Clumps& c = world_.clumps();
    std::vector<double> tops(c.size(), -1e300);
    for (std::size_t k = 0; k < c.size(); ++k)
        for (uint32_t e = c.start[k]; e < c.start[k + 1]; ++e)
            tops[k] = std::max(tops[k], p.pos[c.member[e]].z + p.radius[c.member[e]]);
    return tops;
}

double DamperRun::grains_volume_now() const {
    if (clumps()) return grains_mass() / world_.materials[kGrainMat].density;
    double v = 0.0;
    for (uint32_t i = first_grain_; i < end_grain_; ++i) {
        const double r = world_.particles.radius[i];
        v += r * r * r;
    }
    return 4.0 / 3.0 * std::numbers::pi * v;
}

double DamperRun::grains_mass() const {
    double m = 0;
    if (clumps())
        for (double x : world_.clumps().mass) m += x;
    else
        for (uint32_t i = first_grain_; i < end_grain_; ++i) m += world_.particles.mass[i];
    return m;
}

// Level of the grains' top surface [m]: the mean top (z + r) of the highest layer, i.e. of the
// n_layer highest grains, n_layer the grains of one hexagonal layer across the foil (0.907
// (r_in / r_k)^2). The single highest grain would say little: one grain resting on the others
// stands a radius above the surface, and a cap that meets only it ends above the packing.
double DamperRun::fill_level() const {
    const double r_in = lattice_.radius - config_.foil.particle_radius, rk = config_.grains.radius;
    std::vector<double> tops = grain_tops();
    const std::size_t layer = std::clamp<std::size_t>(std::size_t(0.9069 * (r_in / rk) * (r_in / rk)), 1, tops.size());
    std::partial_sort(tops.begin(), tops.begin() + long(layer), tops.end(), std::greater<double>());
    double sum = 0;
    for (std::size_t k = 0; k < layer; ++k) sum += tops[k];
    return sum / double(layer);
}

// Grain volume over the cylinder of this inner radius and height: the packing fraction of
// summary.json ("preparation", "start_of_cycling").
double DamperRun::packing_fraction(double inner_radius, double height) const {
    double v = 0;
    if (clumps()) v = grains_volume_now();
    else
        for (uint32_t i = first_grain_; i < end_grain_; ++i) v += 4.0 / 3.0 * std::numbers::pi * std::pow(world_.particles.radius[i], 3);
    return v / (std::numbers::pi * inner_radius * inner_radius * height);
}

bool DamperRun::refill() {
    if (!config_.damper.refill) return false;
    // The level the grains must reach before the cap comes down: the damper height plus a
    // quarter of a grain radius, so that the cap meets the top layer, not a few grains that
    // stand out of it (kRefillMargin, measured: docs/damper.md "Preparation").
    constexpr double kRefillMargin = 0.25;  // [grain radii]
    constexpr int kMaxRefills = 8;
    const double rk = config_.grains.radius, r_in = lattice_.radius - config_.foil.particle_radius;
    const double target = z_top_ + kRefillMargin * rk, level = fill_level();
    const double v_k = sizes_.mean_volume();
    const double area = std::numbers::pi * r_in * r_in;
    const int done = state_.report.count("prepare.refills") ? int(state_.report.at("prepare.refills")) : 0;
    char msg[256];
    // With damper.packing_target the grains' volume decides, not their level: the grains missing
    // to the target (to the nearest grain), however high they then stand; the cap compresses them.
    std::size_t add = 0;
    const double phi_now = config_.damper.packing_target > 0.0 ? packing_fraction(r_in, z_top_) : 0.0;  // [-] before this re-fill
    if (config_.damper.packing_target > 0.0) {
        const double missing = std::round((config_.damper.packing_target - phi_now) * area * z_top_ / v_k);
        if (missing < 1.0) {
            if (done == 0 && missing < -0.5) {
                std::snprintf(msg, sizeof msg,
                              "prepare: the pour alone fills %.4f of the foil's interior, above damper.packing_target "
                              "= %.4g: lower grains.volume_fraction to reach the target",
                              phi_now, config_.damper.packing_target);
                warn(msg);
            }
            return false;
        }
        add = std::size_t(missing);
    } else if (level >= target) {
        return false;
    }
    if (done >= kMaxRefills) {
        if (config_.damper.packing_target > 0.0)
            std::snprintf(msg, sizeof msg,
                          "prepare: after %d re-fills the grains fill %.4f of the foil's interior, below "
                          "damper.packing_target = %.4g", done, phi_now,
                          config_.damper.packing_target);
        else
            std::snprintf(msg, sizeof msg,
                          "prepare: after %d re-fills the grains reach %.4g m, below the damper height %.4g m: the "
                          "cap compresses less than the top layer", done, level, z_top_);
        warn(msg);
        return false;
    }
    // Without a target: as many grains as fill the gap at the packing fraction of the bed below
    // (the grains settle to about the same packing), one more so that every re-fill adds one.
    if (add == 0) {
        const double phi_bed = double(grain_count_now()) * v_k / (area * level);
        add = std::size_t(std::ceil(phi_bed * area * (target - level) / v_k)) + 1;
    }
    // Written by the fill; a checkpoint of the fill stage without it (an older vppdem's, or an
    // edited one) cannot be re-filled: say so rather than fail with a bare map lookup.
    const auto funnel = state_.report.find("prepare.funnel_height");
    if (funnel == state_.report.end())
        throw std::runtime_error("checkpoint '" + options_.from + "' holds a sample in the fill stage without its funnel "
                                 "height (prepare.funnel_height): it cannot be re-filled; prepare a new sample (run "
                                 "without --from)");
    double funnel_h = funnel->second;
    if (sizes_.sieve_radius.empty() && sizes_.kind == scene::SizeDistribution::Kind::Sieve)
        throw std::runtime_error("checkpoint '" + options_.from + "' holds a sample drawn from a sieve curve in the fill stage: "
                                 "give grains.sieve_curve (the sample's curve) to re-fill it");
    if (clumps() && shape_.members.empty())
        throw std::runtime_error("checkpoint '" + options_.from + "' holds clumps of a template in the fill stage: give "
                                 "grains.clump_template (the sample's template) to re-fill it");
    const auto pos = generate_grains(config_, lattice_, add, z_top_, 1.6 * lattice_.radius, funnel_h, grain_reach(sizes_.max_radius()),
                                     highest_grain_top(), uint64_t(done + 1), true);
    if (pos.empty()) {
        warn("prepare: no room in the funnel for a re-fill; the grains stay below the damper height");
        return false;
    }
    add_grains(pos, draw_radii(pos.size(), uint64_t(done + 1)), uint64_t(done + 1));
    end_grain_ = uint32_t(world_.particles.size());
    state_.grains = grain_count_now();
    // A smaller grain than any before lowers the critical step (one radius: the same grains).
    if (sizes_.kind != scene::SizeDistribution::Kind::Single)
        world_.params.dt = std::min(world_.params.dt, resolve_dt(config_.simulation, world_));
    state_.report["prepare.refills"] = done + 1;
    world_.invalidate_candidates();
    if (config_.damper.packing_target > 0.0)
        log("[prepare] grains fill %.4f of the foil's interior, below the target %.4g: re-fill %d adds %zu grains (%u "
            "in all)\n", phi_now,
            config_.damper.packing_target, done + 1, pos.size(), grain_count_now());
    else
        log("[prepare] grains level %.4f m, below %.4f m: re-fill %d adds %zu grains (%u in all)\n", level, target,
            done + 1, pos.size(), grain_count_now());
    return true;
}

void DamperRun::apply_config_to_prepared() {
    // What may change between a preparation and a run from it: contact properties, foil
    // stiffness, process and simulation settings (geometry is checked by the caller).
    dem::Material& g = world_.materials[kGrainMat];
    g.young = config_.grains.young;
    g.stiffness_ratio = config_.grains.stiffness_ratio;
    g.friction = config_.grains.friction;
    g.restitution = config_.grains.restitution;  // pairs take the smaller: grain-foil and grain-cap too
    world_.materials[kCapMat].friction = config_.damper.cap_friction < 0 ? config_.grains.friction : config_.damper.cap_friction;
    world_.materials[kCapMat].young = config_.grains.young;
    dem::Material& f = world_.materials[kFoilMat];
    f.young = particle_modulus(config_.foil);
    f.stiffness_ratio = config_.foil.stiffness_ratio;
    f.friction = config_.foil.friction;
    if (mesh_foil()) {
        // Each bond's kn from its length and triangles' area, as the membrane builder gave it.
        const MembraneDef d = membrane_def();
        for (std::size_t k = 0; k < membrane_.bonds.size(); ++k) {
            const double kn = membrane_bond_stiffness(d, membrane_.bond_length[k], membrane_.bond_area[k]);
            world_.set_bond_stiffness(membrane_.bonds[k], kn, config_.foil.stiffness_ratio * kn);
        }
    } else {
        const double kn = bond_normal_stiffness(config_.foil);
        for (std::size_t b = 0; b < world_.bonds().size(); ++b) world_.set_bond_stiffness(uint32_t(b), kn, config_.foil.stiffness_ratio * kn);
    }
    world_.set_bond_arm(config_.foil.bond_arm);
    world_.invalidate_contact_physics();
    world_.params.local_damping = cycling_local_damping(config_);  // the preparation ran with simulation.local_damping
    world_.params.threads = config_.simulation.threads;
    world_.params.skin = config_.simulation.skin;
    state_.settings = values_of(config_, kRunKeys);  // from now on the run is bound to these
}

std::map<std::string, double> DamperRun::run_settings() const { return values_of(config_, kRunKeys); }


}  // namespace damper_detail

std::size_t grain_count(const Config& c) {
    if (c.grains.radius_distribution != 0)
        return std::size_t(std::llround(c.grains.volume_fraction * std::numbers::pi * c.damper.radius * c.damper.radius *
                                        c.damper.height / grain_sizes(c).mean_volume()));
    const double rk = c.grains.radius;
    return std::size_t(std::llround(c.grains.volume_fraction * std::numbers::pi * c.damper.radius * c.damper.radius *
                                    c.damper.height / (4.0 / 3.0 * std::numbers::pi * rk * rk * rk)));
}

double inertial_number(const Config& c, double height) {
    const double gamma_dot = peak_speed(c.process) / height;  // the stroke's fastest
    const double p = std::max(std::abs(c.process.underpressure), 1.0);
    return gamma_dot * 2.0 * c.grains.radius * std::sqrt(c.grains.density / p);
}


}  // namespace vpp
