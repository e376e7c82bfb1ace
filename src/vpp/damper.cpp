#include "vpp/damper.h"

#include <algorithm>
#include <cstdarg>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include "scene/progress.h"
#include "scene/scene_runner.h"
#include "dem/io/checkpoint.h"
#include "dem/io/csv.h"
#include "dem/io/json.h"
#include "dem/io/vtk.h"
#include "dem/walls/facet_sets.h"
#include "vpp/plot.h"
#include "vpp/settings.h"

namespace vpp {

namespace fs = std::filesystem;
using dem::Vec3;

namespace {

// Material indices in the damper world (the foil is built first, so its material is 0).
constexpr uint32_t kFoilMat = 0, kGrainMat = 1, kCapMat = 2, kFunnelMat = 3;
constexpr uint32_t kBottomCap = 0, kTopCap = 1;  // plane indices

enum class Stage : int { Fill = 0, Compress = 1, Prepared = 2, Vacuum = 3, Cycling = 4, Done = 5 };
const char* stage_name(Stage s) {
    static const char* n[] = {"fill", "compress", "prepared", "vacuum", "cycle", "done"};
    return n[int(s)];
}

struct Sample {
    double time, displacement, grains, foil;
};

// One row of energy.csv (the ledger at a forces.csv sample; docs/energy.md).
constexpr int kEnergyColumns = 11;
constexpr const char* kEnergyHeader =
    "time,boundary_work,pressure_work,gravity_work,kinetic,elastic_contacts,elastic_bonds,"
    "friction_dissipation,damping_dissipation,viscous_dissipation,residual";
struct EnergyRow {
    double v[kEnergyColumns];
};

EnergyRow energy_row(const dem::EnergyLedger& L, double time) {
    return {{time, L.boundary_work, L.pressure_work, L.gravity_work, L.kinetic, L.elastic_contacts, L.elastic_bonds,
             L.friction_dissipation(), L.damping_dissipation, L.viscous_dissipation, L.residual()}};
}

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

    std::string save() const {
        std::ostringstream os;
        os.precision(17);
        os << "stage " << int(stage) << "\nstage_t0 " << stage_t0 << "\ncap_d0 " << cap_d0 << "\ncycle_t0 "
           << cycle_t0 << "\nwindow " << window_grains << " " << window_foil << " " << window_n << "\n";
        for (const auto& [k, v] : geometry) os << "geometry " << k << " " << v << "\n";
        for (const auto& [k, v] : settings) os << "setting " << k << " " << v << "\n";
        if (grains > 0) os << "grains " << grains << "\n";
        for (const auto& [k, v] : report) os << "report " << k << " " << v << "\n";
        for (const std::string& w : warnings) os << "warning " << w << "\n";  // one line each (warn() strips newlines)
        for (const Sample& s : samples)
            os << "sample " << s.time << " " << s.displacement << " " << s.grains << " " << s.foil << "\n";
        for (const EnergyRow& e : energy) {
            os << "energy";
            for (double v : e.v) os << " " << v;
            os << "\n";
        }
        return os.str();
    }
    static RunState load(const std::string& text) {
        RunState r;
        std::istringstream is(text);
        std::string key;
        int stage = 0;
        while (is >> key) {
            if (key == "stage") is >> stage;
            else if (key == "stage_t0") is >> r.stage_t0;
            else if (key == "cap_d0") is >> r.cap_d0;
            else if (key == "cycle_t0") is >> r.cycle_t0;
            else if (key == "window") is >> r.window_grains >> r.window_foil >> r.window_n;
            else if (key == "geometry") {
                std::string k;
                double v;
                is >> k >> v;
                r.geometry[k] = v;
            } else if (key == "setting") {
                std::string k;
                double v;
                is >> k >> v;
                r.settings[k] = v;
            } else if (key == "grains") {
                is >> r.grains;
            } else if (key == "report") {
                std::string k;
                double v;
                is >> k >> v;
                r.report[k] = v;
            } else if (key == "warning") {
                std::string w;
                std::getline(is, w);
                r.warnings.push_back(w.empty() ? w : w.substr(1));  // the space after the key
            } else if (key == "sample") {
                Sample s;
                is >> s.time >> s.displacement >> s.grains >> s.foil;
                r.samples.push_back(s);
            } else if (key == "energy") {
                EnergyRow e;
                for (double& v : e.v) is >> v;
                r.energy.push_back(e);
            } else throw std::runtime_error("damper checkpoint: unknown state entry '" + key + "'");
        }
        r.stage = Stage(stage);
        return r;
    }
};

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

std::map<std::string, double> values_of(const Config& c, const auto& keys) {
    std::map<std::string, double> m;
    for (const StoredKey& k : keys) m[k.key] = k.get(c);
    return m;
}

bool same_value(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

// A stored value as the config file writes it, for messages.
std::string show(const std::string& key, double v) {
    if (key == "process.direction") return v == 0.0 ? "\"compression\"" : "\"extension\"";
    if (key == "output.energy" || key == "damper.refill") return v != 0.0 ? "true" : "false";
    if (key == "simulation.dt" && v == 0.0) return "\"auto\"";
    if (key == "damper.cap_friction" && v < 0.0) return "(unset: the grains' friction)";
    std::string out;
    dem::append_number(out, v);
    return out;
}

// Everything a damper run writes into its folder (docs/damper.md, "Outputs"). --overwrite
// removes all of it before a new run starts, so nothing of the previous run (an energy.csv the
// new run does not write, a prepared.ckpt of another sample) is left beside the new results.
// Other files in the folder (notes, a sweep's case.toml) are left alone.
const char* const kDamperFiles[] = {"forces.csv",   "cycles.csv", "energy.csv",      "summary.json",
                                    "prepared.ckpt", "run.ckpt",  "loops.png",       "loops_total.png",
                                    "loops_foil.png", "loops_grains.png", "energy_split.png"};

void remove_previous_outputs(const fs::path& dir, const std::string& spare) {
    std::error_code ec;
    auto remove = [&](const fs::path& p) {
        if (!fs::exists(p)) return;
        if (!spare.empty() && fs::equivalent(p, spare, ec)) return;  // the checkpoint this run starts from
        fs::remove(p);
    };
    for (const char* f : kDamperFiles) {
        remove(dir / f);
        remove(dir / (std::string(f) + ".part"));
    }
    if (!fs::is_directory(dir / "vtk")) return;
    std::vector<fs::path> frames;
    for (const auto& e : fs::directory_iterator(dir / "vtk")) {
        const std::string n = e.path().filename().string();
        if (e.is_regular_file() && n.starts_with("damper_") && (n.ends_with(".vtk") || n.ends_with(".vtk.part")))
            frames.push_back(e.path());
    }
    for (const fs::path& f : frames) fs::remove(f);
}

// Grain positions: a jittered cubic lattice inside the foil and the funnel above it, filled
// from the bottom up, so the grains never overlap each other, the foil or the funnel.
// A re-fill (refill = true) places its grains the same way above z_floor (the top of the grains
// already in) in the funnel that is there, as many of n as fit, with its own random stream.
std::vector<Vec3> generate_grains(const Config& c, const FoilLattice& L, std::size_t n, double z_top,
                                  double funnel_top_radius, double& funnel_height, double z_floor = 0.0,
                                  uint64_t stream = 0, bool refill = false) {
    const double rk = c.grains.radius, rf = c.foil.particle_radius;
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

double grains_kinetic_energy(const dem::World& w, uint32_t g0, uint32_t g1) {
    double e = 0;
    for (uint32_t i = g0; i < g1; ++i) e += 0.5 * w.particles.mass[i] * norm2(w.particles.vel[i]);
    return e;
}

// Yade's unbalanced force: mean net force on free particles over mean contact force.
double unbalanced_force(const dem::World& w) {
    const auto& p = w.particles;
    double net = 0;
    std::size_t nfree = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.inv_mass[i] == 0.0) continue;
        const dem::Vec3 fx = p.ext_force.empty() ? dem::Vec3{} : p.ext_force[i];
        net += norm(p.force[i] + fx + w.params.gravity * p.mass[i]);
        ++nfree;
    }
    double fc = 0;
    std::size_t nc = 0;
    w.for_each_touching([&](const dem::TouchingContact& c) {
        if (c.wall) return;
        fc += norm(c.force);
        ++nc;
    });
    if (nc == 0 || nfree == 0) return 1.0;
    return (net / double(nfree)) / (fc / double(nc));
}

}  // namespace

std::size_t grain_count(const Config& c) {
    const double rk = c.grains.radius;
    return std::size_t(std::llround(c.grains.volume_fraction * std::numbers::pi * c.damper.radius * c.damper.radius *
                                    c.damper.height / (4.0 / 3.0 * std::numbers::pi * rk * rk * rk)));
}

double inertial_number(const Config& c, double height) {
    const double gamma_dot = c.process.velocity / height;
    const double p = std::max(std::abs(c.process.underpressure), 1.0);
    return gamma_dot * 2.0 * c.grains.radius * std::sqrt(c.grains.density / p);
}

// ------------------------------------------------------------------------------------------

namespace {

class DamperRun {
public:
    DamperRun(const Config& c, const DamperOptions& o) : c_(c), o_(o), out_(o.out_dir) {}
    DamperResult run();

private:
    void adopt_checkpoint_settings();
    void check_grains_fit(std::size_t n);
    void start_output_dir();
    void build();
    void apply_config_to_prepared();
    void stage_fill();
    void stage_compress();
    void stage_vacuum();
    void stage_cycle();
    void finish();
    void checkpoint(bool force);
    void save_prepared();
    void write_forces();
    void write_energy();
    void vtk_frame(const char* tag);
    double top_ring_force_z() const;
    void next_stage(Stage s);
    // Re-fill (damper.refill): adds grains above the settled ones when their level is below the
    // damper height; returns false when the level is reached (or re-filling is off or exhausted).
    bool refill();
    double fill_level() const;
    double highest_grain_top() const;
    double packing_fraction(double inner_radius, double height) const;
    void record_start_of_cycling(const Sample& first);
    // Logs a warning and keeps it for summary.json (and the checkpoints, so branches and
    // resumed runs report it too).
    void warn(const std::string& what);
    // Settling checks fall at fixed times after the stage start (every `check` seconds), so a
    // resumed run takes its decisions at the same steps as an uninterrupted one.
    double next_check_after(double t, double check) const {
        return st_.stage_t0 + check * (std::floor((t - st_.stage_t0) / check) + 1.0);
    }
    // Energy scale of the rest criteria [J]: every grain lifted by one diameter, N m g 2 r_k.
    double settle_energy_scale() const {
        return double(g1_ - g0_) * w_.particles.mass[g0_] * 9.81 * 2.0 * c_.grains.radius;
    }
    void log(const char* fmt, ...) const;

    Config c_;
    DamperOptions o_;
    fs::path out_;
    dem::World w_;
    FoilLattice L_;
    RunState st_;
    uint32_t g0_ = 0, g1_ = 0;  // grain index range
    double z_top_ = 0;          // [m] top ring / cap height after preparation
    std::vector<uint32_t> top_ring_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_ckpt_ = start_;
    int vtk_count_ = 0;
    double next_vtk_ = 0.0;
    std::vector<std::string> pending_warnings_;  // found before the checkpoint's state is loaded
    std::size_t ckpt_grains_ = 0;               // grains stored in the --from checkpoint (0: unknown)

public:
    const RunState& state() const { return st_; }
};

void DamperRun::log(const char* fmt, ...) const {
    if (o_.quiet) return;
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stderr, fmt, ap);
    va_end(ap);
}

void DamperRun::adopt_checkpoint_settings() {
    dem::World scratch;  // only the app state is needed here; run() loads the World itself
    const RunState ck = RunState::load(dem::load_checkpoint(o_.from, scratch));
    // Geometry: a key the config gives must match the sample's; the others take its values.
    std::string diffs;
    std::map<std::string, double> geometry = ck.geometry;
    for (const StoredKey& k : kGeometryKeys)
        if (!geometry.count(k.key) && std::isfinite(k.legacy)) geometry[k.key] = k.legacy;
    for (const StoredKey& k : kGeometryKeys) {
        const auto it = geometry.find(k.key);
        const double value = k.get(c_);
        if (it != geometry.end() && !c_.given.count(k.key)) {
            k.set(c_, it->second);
        } else if (it == geometry.end() || !same_value(it->second, value)) {
            diffs += (diffs.empty() ? "" : ", ") + std::string(k.key) + " = " +
                     (it == geometry.end() ? std::string("?") : show(k.key, it->second)) +
                     " (the config asks for " + show(k.key, value) + ")";
        }
    }
    ckpt_grains_ = ck.grains;
    if (!diffs.empty())
        throw std::runtime_error("checkpoint '" + o_.from + "' was prepared with another geometry: " + diffs +
                                 "; prepare a new sample (run without --from)");
    if (ck.settings.empty()) {
        // A prepared sample (or a run stopped before its settings were applied) takes the
        // config's settings. Only a checkpoint of an older vppdem can be past that point
        // without them: it is run with the config's settings, as that vppdem did.
        if (ck.stage > Stage::Prepared) {
            pending_warnings_.push_back("resume: the checkpoint (an older vppdem's) stores no run settings; the "
                                        "config's are used");
            log("damper: warning: checkpoint '%s' (an older vppdem's) stores no process settings: the config's are "
                "used; give the ones the run started with\n", o_.from.c_str());
        }
        return;
    }
    // A run that started: it continues with its own settings, whatever the command line says;
    // a key given with another value is refused rather than spliced into the record.
    std::string conflicts;
    for (const StoredKey& k : kRunKeys) {
        const auto it = ck.settings.find(k.key);
        if (it == ck.settings.end()) continue;
        if (c_.given.count(k.key) && !same_value(k.get(c_), it->second))
            conflicts += (conflicts.empty() ? "" : ", ") + std::string(k.key) + " = " + show(k.key, it->second) +
                         " in the checkpoint, " + show(k.key, k.get(c_)) + " given";
        else
            k.set(c_, it->second);
    }
    if (!conflicts.empty())
        throw std::runtime_error("checkpoint '" + o_.from + "' continues a run with other settings: " + conflicts +
                                 "; a resumed run keeps the settings it started with: leave these keys out (or give "
                                 "the checkpoint's values), or start a new run from the sample's prepared.ckpt");
}

void DamperRun::check_grains_fit(std::size_t n) {
    const double rk = c_.grains.radius;
    const double r_in = L_.radius - c_.foil.particle_radius;  // [m] inner surface of the foil
    if (rk > r_in / 3.0)
        throw std::runtime_error("config key 'grains.radius' = " + show("", rk) +
                                 ": too large for the damper; at most a third of the foil's inner radius (" +
                                 show("", r_in / 3.0) + " m)");
    // Fewest grains: one layer across the foil. A VPP damper is a packing that the vacuum
    // jams; grains that do not even cover the bottom once lie loose on the lower cap, the
    // cap never loads them and the "loop" is the foil's alone (0 grains gave a negative W).
    // A hexagonal layer of circles of radius r_k covers pi / (2 sqrt 3) = 0.907 of the area.
    const double v_grain = 4.0 / 3.0 * std::numbers::pi * rk * rk * rk;
    const std::size_t n_layer = std::size_t(std::max(1.0, std::floor(0.9069 * (r_in / rk) * (r_in / rk))));
    if (n < n_layer) {
        const double phi_min = double(n_layer) * v_grain /
                               (std::numbers::pi * c_.damper.radius * c_.damper.radius * c_.damper.height);
        throw std::runtime_error("config key 'grains.volume_fraction' = " + show("", c_.grains.volume_fraction) +
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
        throw std::runtime_error("config key 'grains.volume_fraction' = " + show("", c_.grains.volume_fraction) +
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

void DamperRun::start_output_dir() {
    cli::prepare_output_dir(o_.out_dir, o_.overwrite);
    if (o_.overwrite) remove_previous_outputs(out_, o_.from);
}

void DamperRun::build() {
    // Foil first: its particles are 0 .. n_f - 1 and its material index 0.
    w_.params.gravity = {0, 0, -9.81};
    w_.params.local_damping = c_.simulation.local_damping;
    w_.params.threads = c_.simulation.threads;
    w_.params.skin = c_.simulation.skin;
    L_ = build_cylinder(w_, c_.foil, c_.damper.radius, c_.damper.height);
    z_top_ = (L_.rows - 1) * L_.spacing;
    top_ring_ = L_.row(L_.rows - 1);
}

void DamperRun::next_stage(Stage s) {
    st_.stage = s;
    st_.stage_t0 = w_.time;
    st_.cap_d0 = w_.planes[kTopCap].motion.displacement(w_.time).z;
    checkpoint(true);
    vtk_frame(stage_name(s));
}

double DamperRun::top_ring_force_z() const {
    double f = 0;
    for (uint32_t i : top_ring_) f += w_.particles.force[i].z;
    return f;
}

void DamperRun::checkpoint(bool force) {
    const auto now = std::chrono::steady_clock::now();
    if (!force && std::chrono::duration<double>(now - last_ckpt_).count() < o_.checkpoint_every) return;
    last_ckpt_ = now;
    dem::save_checkpoint((out_ / "run.ckpt").string(), w_, st_.save());
    if (st_.stage == Stage::Cycling || st_.stage == Stage::Done) {
        write_forces();
        write_energy();
    }
}

void DamperRun::save_prepared() {
    dem::save_checkpoint((out_ / "prepared.ckpt").string(), w_, st_.save());
}

void DamperRun::vtk_frame(const char* tag) {
    fs::create_directories(out_ / "vtk");
    char name[96];
    std::snprintf(name, sizeof name, "damper_%04d_%s.vtk", vtk_count_++, tag);
    dem::write_particles_vtk((out_ / "vtk" / name).string(), w_, true);
}

void DamperRun::warn(const std::string& what) {
    std::string w = what;
    for (char& ch : w)
        if (ch == '\n' || ch == '\r') ch = ' ';
    st_.warnings.push_back(w);
    log("damper: warning: %s\n", w.c_str());
}

double DamperRun::highest_grain_top() const {
    double top = 0;
    for (uint32_t i = g0_; i < g1_; ++i) top = std::max(top, w_.particles.pos[i].z + w_.particles.radius[i]);
    return top;
}

// Level of the grains' top surface [m]: the mean top (z + r) of the highest layer, i.e. of the
// n_layer highest grains, n_layer the grains of one hexagonal layer across the foil (0.907
// (r_in / r_k)^2). The single highest grain would say little: one grain resting on the others
// stands a radius above the surface, and a cap that meets only it ends above the packing.
double DamperRun::fill_level() const {
    const double r_in = L_.radius - c_.foil.particle_radius, rk = c_.grains.radius;
    std::vector<double> tops;
    for (uint32_t i = g0_; i < g1_; ++i) tops.push_back(w_.particles.pos[i].z + w_.particles.radius[i]);
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
    for (uint32_t i = g0_; i < g1_; ++i) v += 4.0 / 3.0 * std::numbers::pi * std::pow(w_.particles.radius[i], 3);
    return v / (std::numbers::pi * inner_radius * inner_radius * height);
}

bool DamperRun::refill() {
    if (!c_.damper.refill) return false;
    // The level the grains must reach before the cap comes down: the damper height plus a
    // quarter of a grain radius, so that the cap meets the top layer, not a few grains that
    // stand out of it (kRefillMargin, measured: docs/damper.md "Preparation").
    constexpr double kRefillMargin = 0.25;  // [grain radii]
    constexpr int kMaxRefills = 8;
    const double rk = c_.grains.radius, r_in = L_.radius - c_.foil.particle_radius;
    const double target = z_top_ + kRefillMargin * rk, level = fill_level();
    if (level >= target) return false;
    const int done = st_.report.count("prepare.refills") ? int(st_.report.at("prepare.refills")) : 0;
    char msg[256];
    if (done >= kMaxRefills) {
        std::snprintf(msg, sizeof msg,
                      "prepare: after %d re-fills the grains reach %.4g m, below the damper height %.4g m: the cap "
                      "compresses less than the top layer", done, level, z_top_);
        warn(msg);
        return false;
    }
    // As many grains as fill the gap at the packing fraction of the bed below (the grains
    // settle to about the same packing), one more so that every re-fill adds at least one.
    const double v_k = 4.0 / 3.0 * std::numbers::pi * rk * rk * rk;
    const double area = std::numbers::pi * r_in * r_in;
    const double phi_bed = double(g1_ - g0_) * v_k / (area * level);
    const std::size_t add = std::size_t(std::ceil(phi_bed * area * (target - level) / v_k)) + 1;
    double funnel_h = st_.report.at("prepare.funnel_height");
    const auto pos = generate_grains(c_, L_, add, z_top_, 1.6 * L_.radius, funnel_h, highest_grain_top(),
                                     uint64_t(done + 1), true);
    if (pos.empty()) {
        warn("prepare: no room in the funnel for a re-fill; the grains stay below the damper height");
        return false;
    }
    for (const Vec3& p : pos) {
        dem::SphereDef d;
        d.position = p;
        d.radius = rk;
        d.material = kGrainMat;
        d.mask = kGrainMask;
        w_.add_sphere(d);
    }
    g1_ += uint32_t(pos.size());
    st_.grains = g1_ - g0_;
    st_.report["prepare.refills"] = done + 1;
    w_.invalidate_candidates();
    log("[prepare] grains level %.4f m, below %.4f m: re-fill %d adds %zu grains (%u in all)\n", level, target,
        done + 1, pos.size(), g1_ - g0_);
    return true;
}

void DamperRun::stage_fill() {
    const double max_time = 1.5;  // [s] of falling; a column of 20 cm settles in well under 1 s
    const double check = 2e-3;    // [s] between settling checks
    cli::Progress prog("prepare: fill", uint64_t(max_time / w_.params.dt), o_.quiet);
    double next_check = next_check_after(w_.time, check);
    for (;;) {
        w_.step();
        prog.update(uint64_t((w_.time - st_.stage_t0) / w_.params.dt), w_.time);
        checkpoint(false);
        if (w_.time < next_check) continue;
        next_check = next_check_after(w_.time, check);
        const double t = w_.time - st_.stage_t0;
        const double ke = grains_kinetic_energy(w_, g0_, g1_);
        // The grains start at rest: a minimum time lets them fall first (a re-fill's grains
        // start just above the others and fall less far).
        const bool refilled = st_.report.count("prepare.refills") > 0;
        bool settled = false;
        if (t > (refilled ? 0.1 : 0.15) && ke < 1e-4 * settle_energy_scale()) {
            log("[prepare] grains settled after %.3f s (kinetic energy %.3g J)\n", t, ke);
            settled = true;
        } else if (t > max_time) {
            warn("prepare: grains not fully settled after 1.5 s of filling");
            settled = true;
        }
        if (!settled) continue;
        if (!refill()) break;
        // A re-fill starts the stage again: a checkpoint with the new grains, the settling clock.
        next_stage(Stage::Fill);
        next_check = next_check_after(w_.time, check);
    }
}

void DamperRun::stage_compress() {
    // Bring the cap just above the highest grain (nothing touches it on the way), then move it
    // down to the top ring at 0.1 m/s and let the grains rearrange; the re-filled grains stand
    // above the top ring, so the cap meets them and pushes them down to the damper height.
    const double top = highest_grain_top(), level = fill_level();
    const double z_cap0 = w_.planes[kTopCap].point.z;
    const double z_start = std::max(z_top_, top + 1e-4);
    const double speed = 0.1, hold = 0.02, window = 0.005;  // [m/s], [s], [s] (cap force averaged over the window)
    const double t0 = w_.time, t1 = t0 + (z_start - z_top_) / speed;
    dem::Motion m;
    m.history = {{t0 - 1e-12, {0, 0, z_start - z_cap0}}, {t1 + 1e-12, {0, 0, z_top_ - z_cap0}}};
    w_.planes[kTopCap].motion = m;
    w_.invalidate_candidates();
    log("[prepare] cap from %.4f m down to %.4f m (grains top %.4f m, level of the top layer %.4f m)\n", z_start,
        z_top_, top, level);
    const uint64_t n = uint64_t((t1 + hold - w_.time) / w_.params.dt) + 1;
    cli::Progress prog("prepare: compress", n, o_.quiet);
    double f_max = 0, f_sum = 0;
    long f_n = 0;
    for (uint64_t s = 0; s < n; ++s) {
        w_.step();
        prog.update(s + 1, w_.time);
        const double f = w_.wall_force(kTopCap).z;  // [N] grains on the cap, pushing it up
        f_max = std::max(f_max, f);
        if (w_.time > t1 + hold - window) {
            f_sum += f;
            ++f_n;
        }
    }
    w_.clear_facets();  // the funnel goes
    const double r_in = L_.radius - c_.foil.particle_radius;
    const double cap_force = f_n ? f_sum / double(f_n) : 0.0;
    auto& r = st_.report;
    r["prepare.grains"] = double(g1_ - g0_);
    r["prepare.grain_top"] = top;
    r["prepare.fill_level"] = level;
    r["prepare.cap_travel"] = std::max(0.0, top - z_top_);
    r["prepare.cap_force"] = cap_force;
    r["prepare.cap_force_max"] = f_max;
    r["prepare.packing_fraction"] = packing_fraction(r_in, z_top_);
    r["prepare.packing_fraction_nominal"] =
        packing_fraction(c_.damper.radius, c_.damper.height);
    log("[prepare] cap travel %.3g mm on the grains, cap force %.4g N at the end (%.4g N at most), packing "
        "fraction %.4f of the foil's interior\n", 1e3 * r["prepare.cap_travel"], cap_force, f_max,
        r["prepare.packing_fraction"]);
    if (!(cap_force > 0)) {
        char msg[320];
        std::snprintf(msg, sizeof msg,
                      "prepare: the cap ends above the grains (no force on it at the damper height %.4g m; their "
                      "top layer is at %.4g m): the first part of every compression meets no grains%s",
                      z_top_, level, c_.damper.refill ? "" : "; damper.refill = true fills the foil up to the cap");
        warn(msg);
    }
}

void DamperRun::apply_config_to_prepared() {
    // What may change between a preparation and a run from it: contact properties, foil
    // stiffness, process and simulation settings (geometry is checked by the caller).
    dem::Material& g = w_.materials[kGrainMat];
    g.young = c_.grains.young;
    g.stiffness_ratio = c_.grains.stiffness_ratio;
    g.friction = c_.grains.friction;
    w_.materials[kCapMat].friction = c_.damper.cap_friction < 0 ? c_.grains.friction : c_.damper.cap_friction;
    w_.materials[kCapMat].young = c_.grains.young;
    dem::Material& f = w_.materials[kFoilMat];
    f.young = particle_modulus(c_.foil);
    f.stiffness_ratio = c_.foil.stiffness_ratio;
    f.friction = c_.foil.friction;
    const double kn = bond_normal_stiffness(c_.foil);
    for (std::size_t b = 0; b < w_.bonds().size(); ++b) w_.set_bond_stiffness(uint32_t(b), kn, c_.foil.stiffness_ratio * kn);
    w_.invalidate_contact_physics();
    w_.params.local_damping = c_.simulation.local_damping;
    w_.params.threads = c_.simulation.threads;
    w_.params.skin = c_.simulation.skin;
    st_.settings = values_of(c_, kRunKeys);  // from now on the run is bound to these
}

void DamperRun::stage_vacuum() {
    const double ramp = c_.process.ramp_time, min_hold = 0.02, max_hold = 0.5, check = 2e-3;
    w_.pressure.nodes = cylinder_pressure_nodes(L_);
    const double dp = c_.process.underpressure;
    cli::Progress prog("vacuum", uint64_t((ramp + max_hold) / w_.params.dt), o_.quiet);
    double next_check = next_check_after(w_.time, check);
    const double ke_ref = settle_energy_scale();
    for (;;) {
        const double t = w_.time - st_.stage_t0;
        w_.pressure.dp = dp * std::min(1.0, t / ramp);
        w_.step();
        prog.update(uint64_t(t / w_.params.dt), w_.time);
        checkpoint(false);
        if (w_.time < next_check) continue;
        next_check = next_check_after(w_.time, check);
        if (t < ramp + min_hold) continue;
        // Forces of the step just taken (computing them again would advance the shear springs).
        const double ke = grains_kinetic_energy(w_, g0_, g1_);
        const double ub = unbalanced_force(w_);
        if (ke < 1e-4 * ke_ref && ub < 0.05) {
            log("[vacuum] at rest %.3f s after the ramp: kinetic energy %.3g J, unbalanced force %.3g\n",
                t - ramp, ke, ub);
            break;
        }
        if (t > ramp + max_hold) {
            char msg[160];
            std::snprintf(msg, sizeof msg, "vacuum: sample not at rest %.2f s after the ramp (kinetic energy %.3g J, "
                          "unbalanced force %.3g)", t - ramp, ke, ub);
            warn(msg);
            break;
        }
    }
}

// The sample as cycling starts (after the vacuum and the start offset): the cap's height and
// force, the packing fraction in the foil as the vacuum has drawn it in (its mean radius over the
// free rows; the end rings stay at the build radius), and the cap's travel on the grains since it
// first met them in the preparation.
void DamperRun::record_start_of_cycling(const Sample& first) {
    double sum = 0;
    std::size_t cnt = 0;
    for (int k = 1; k + 1 < L_.rows; ++k)
        for (uint32_t i : L_.row(k)) {
            sum += std::hypot(w_.particles.pos[i].x, w_.particles.pos[i].y);
            ++cnt;
        }
    const double r_foil = cnt ? sum / double(cnt) : L_.radius;
    const double cap_z = w_.plane_point(kTopCap).z;
    auto& r = st_.report;
    r["cycle.foil_mean_radius"] = r_foil;
    r["cycle.cap_height"] = cap_z;
    r["cycle.cap_force"] = first.grains;
    r["cycle.packing_fraction"] = packing_fraction(r_foil - c_.foil.particle_radius, cap_z);
    if (r.count("prepare.grain_top")) r["cycle.cap_travel"] = std::max(0.0, r.at("prepare.grain_top") - cap_z);
}

void DamperRun::stage_cycle() {
    const double A = c_.process.amplitude, v = c_.process.velocity;
    const double T = 2.0 * A / v;
    const int S = int(c_.process.samples_per_cycle), ncyc = int(c_.process.cycles);
    const double win = c_.process.sample_window;
    if (st_.samples.empty() && st_.window_n == 0 && st_.cycle_t0 == 0.0) {
        // Start of cycling: cap and top ring follow one history: an optional offset move, then
        // `cycles` triangles of the amplitude (down first for compression, up for extension).
        const double d0 = w_.planes[kTopCap].motion.displacement(w_.time).z;
        const double off = c_.process.start_offset;
        const double t_off = std::abs(off) / v;
        const double sign = c_.process.compression_first ? -1.0 : 1.0;  // z direction of the first leg
        dem::Motion cap, ring;
        cap.history.push_back({w_.time, {0, 0, d0}});
        ring.history.push_back({w_.time, {0, 0, 0}});
        st_.cycle_t0 = w_.time + t_off;
        for (int k = 0; k <= ncyc; ++k) {
            if (k > 0 || t_off > 0) {
                cap.history.push_back({st_.cycle_t0 + k * T, {0, 0, d0 - off}});
                ring.history.push_back({st_.cycle_t0 + k * T, {0, 0, -off}});
            }
            if (k < ncyc) {
                cap.history.push_back({st_.cycle_t0 + (k + 0.5) * T, {0, 0, d0 - off + sign * A}});
                ring.history.push_back({st_.cycle_t0 + (k + 0.5) * T, {0, 0, -off + sign * A}});
            }
        }
        w_.planes[kTopCap].motion = cap;
        const uint32_t m = w_.add_motion(ring);
        for (uint32_t i : top_ring_) w_.set_prescribed(i, m);
        st_.cap_d0 = d0 - off;  // displacements are recorded from the cycling start position
        // Energy ledger (energy.csv); restarted at the first sample, the start of cycling.
        w_.params.track_energy = c_.output.energy;
        if (c_.output.energy) w_.reset_energy();
    } else if (!w_.params.track_energy && c_.output.energy) {
        warn("energy: resumed from a checkpoint without an energy ledger (an older vppdem's); no energy.csv");
    }
    const bool energy = w_.params.track_energy;
    const double t_end = st_.cycle_t0 + ncyc * T;
    const uint64_t total = uint64_t(std::ceil((t_end - w_.time) / w_.params.dt));
    cli::Progress prog("cycle", total, o_.quiet);
    uint64_t done = 0;
    auto sample_time = [&](std::size_t s) { return st_.cycle_t0 + double(s) * T / S; };
    w_.profile().enable(o_.profile);
    w_.profile().reset();
    while (w_.time < t_end - 0.5 * w_.params.dt) {
        w_.compute_forces();
        const std::size_t s = st_.samples.size();
        bool sampled = false;
        if (s < std::size_t(ncyc) * S) {
            const double ts = sample_time(s);
            if (w_.time > ts - win - 0.5 * w_.params.dt) {
                st_.window_grains += w_.wall_force(kTopCap).z;
                st_.window_foil += top_ring_force_z();
                ++st_.window_n;
            }
            if (w_.time >= ts - 0.5 * w_.params.dt) {
                Sample smp;
                smp.time = w_.time;
                smp.displacement = st_.cap_d0 - w_.planes[kTopCap].motion.displacement(w_.time).z;
                smp.grains = st_.window_grains / double(st_.window_n);
                smp.foil = st_.window_foil / double(st_.window_n);
                st_.samples.push_back(smp);
                st_.window_grains = st_.window_foil = 0;
                st_.window_n = 0;
                sampled = true;
                // The ledger counts from the first sample: works and dissipations are 0 there.
                if (energy && s == 0) w_.reset_energy();
                if (s == 0) record_start_of_cycling(smp);
            }
        }
        w_.profile().lap(dem::Phase::kOutput);
        w_.integrate();
        // The ledger at this sample's time is complete once the step is integrated.
        if (energy && sampled) st_.energy.push_back(energy_row(w_.energy(), w_.energy().time - st_.cycle_t0));
        prog.update(++done, w_.time);
        checkpoint(false);
        if (c_.output.vtk_interval > 0 && w_.time >= next_vtk_) {
            vtk_frame("cycle");
            next_vtk_ = w_.time + c_.output.vtk_interval;
        }
        w_.profile().lap(dem::Phase::kOutput);
    }
    if (o_.profile && done > 0) {
        const dem::PhaseProfile& pr = w_.profile();
        std::fprintf(stderr, "[cycle] time per phase over %llu steps (%d threads):\n", (unsigned long long)done, w_.params.threads);
        for (int k = 0; k < int(dem::Phase::kCount); ++k) {
            const auto ph = dem::Phase(k);
            std::fprintf(stderr, "  %-18s %10.3f s %9.2f us/step %6.1f%%\n", dem::phase_name(ph), pr.seconds(ph),
                1e6 * pr.seconds(ph) / double(done), 100.0 * pr.seconds(ph) / std::max(pr.total(), 1e-300));
        }
        std::fprintf(stderr, "  %-18s %10.3f s %9.2f us/step\n", "total", pr.total(), 1e6 * pr.total() / double(done));
    }
    w_.profile().enable(false);
}

void DamperRun::write_energy() {
    if (st_.energy.empty()) return;
    dem::CsvWriter csv((out_ / "energy.csv").string(), kEnergyHeader);
    for (const EnergyRow& e : st_.energy) csv.row(std::vector<double>(e.v, e.v + kEnergyColumns));
    csv.close();
}

void DamperRun::write_forces() {
    dem::CsvWriter csv((out_ / "forces.csv").string(), "time,displacement,force_total,force_grains,force_foil,force_zeroed,cycle");
    const int S = int(c_.process.samples_per_cycle);
    const double f0 = st_.samples.empty() ? 0.0 : st_.samples[0].grains + st_.samples[0].foil;
    for (std::size_t k = 0; k < st_.samples.size(); ++k) {
        const Sample& s = st_.samples[k];
        const double total = s.grains + s.foil;
        csv.row({s.time - st_.cycle_t0, s.displacement, total, s.grains, s.foil, total - f0, double(k / S + 1)});
    }
    csv.close();
}

DamperResult DamperRun::run() {
    // From a checkpoint: its geometry (and, for a run that started, its settings) first, since
    // the foil is built from the config.
    if (!o_.from.empty()) adopt_checkpoint_settings();
    build();
    const std::size_t n_foil = L_.particles.size();
    // The pour's grains; a checkpoint holds those and its re-fills' (an older one: the pour's).
    const std::size_t n = ckpt_grains_ > 0 ? ckpt_grains_ : grain_count(c_);
    g0_ = uint32_t(n_foil);
    g1_ = uint32_t(n_foil + n);
    if (o_.from.empty()) check_grains_fit(n);  // a checkpoint's sample was checked when it was prepared

    if (o_.from.empty()) {
        // Materials in fixed order: grain (frictionless while filling), cap, funnel.
        dem::Material g{"grain", c_.grains.density, c_.grains.young, c_.grains.stiffness_ratio, 0.0, 1.0};
        w_.add_material(g);
        dem::Material cap{"cap", c_.grains.density, c_.grains.young, c_.grains.stiffness_ratio, 0.0, 1.0};
        w_.add_material(cap);
        dem::Material fun{"funnel", c_.grains.density, c_.grains.young, c_.grains.stiffness_ratio, 0.0, 1.0};
        w_.add_material(fun);
        for (int k : {0, L_.rows - 1})
            for (uint32_t i : L_.row(k)) w_.set_fixed(i);
        double funnel_h = 0;
        const double funnel_top_r = 1.6 * L_.radius;
        const auto pos = generate_grains(c_, L_, n, z_top_, funnel_top_r, funnel_h);
        double zmax = 0;
        for (const Vec3& p : pos) {
            dem::SphereDef d;
            d.position = p;
            d.radius = c_.grains.radius;
            d.material = kGrainMat;
            d.mask = kGrainMask;
            w_.add_sphere(d);
            zmax = std::max(zmax, p.z);
        }
        dem::Plane bottom;
        bottom.point = {0, 0, 0};
        bottom.normal = {0, 0, 1};
        bottom.material = kCapMat;
        bottom.mask = kMaskCap;
        w_.add_plane(bottom);
        dem::Plane top = bottom;
        top.point = {0, 0, std::max(zmax + c_.grains.radius + 1e-3, z_top_)};
        top.normal = {0, 0, -1};
        w_.add_plane(top);
        for (dem::Facet f : dem::make_funnel_facets({0, 0, z_top_}, L_.radius, funnel_top_r, funnel_h, 72, true)) {
            f.material = kFunnelMat;
            f.mask = kMaskCap;
            w_.add_facet(f);
        }
        st_.geometry = values_of(c_, kGeometryKeys);
        st_.grains = n;
        st_.report["prepare.grains_poured"] = double(n);
        st_.report["prepare.funnel_height"] = funnel_h;
        w_.params.dt = resolve_dt(c_.simulation, w_);
        start_output_dir();  // only now: bad input writes nothing
        log("damper: %zu grains (r_k = %.4g m), foil %d x %d = %zu particles (radius %.5g m), height %.5g m, "
            "dt = %.4g s, %d thread(s)\n", n, c_.grains.radius, L_.cols, L_.rows, n_foil, L_.radius, z_top_,
            w_.params.dt, c_.simulation.threads);
        next_stage(Stage::Fill);
    } else {
        const std::string blob = dem::load_checkpoint(o_.from, w_);
        st_ = RunState::load(blob);
        if (w_.particles.size() != n_foil + n)
            throw std::runtime_error("checkpoint '" + o_.from + "' does not hold this damper's particles");
        st_.grains = n;
        st_.warnings.insert(st_.warnings.end(), pending_warnings_.begin(), pending_warnings_.end());
        // Resuming continues the run whose run.ckpt lives in --out; anything else (a branch from
        // a prepared sample, even into its own folder) starts a new run there.
        std::error_code ec;
        const bool resuming = fs::exists(out_ / "run.ckpt") && fs::equivalent(o_.from, out_ / "run.ckpt", ec);
        if (!resuming) start_output_dir();
        log("damper: starting from %s at stage '%s', t = %.4g s, %d thread(s)\n", o_.from.c_str(),
            stage_name(st_.stage), w_.time, c_.simulation.threads);
        // A prepared sample takes the config's contact and process settings; a resumed run keeps
        // its own (adopt_checkpoint_settings), but for the thread count (set below for every path).
        if (st_.stage == Stage::Prepared) {
            apply_config_to_prepared();
            w_.params.dt = resolve_dt(c_.simulation, w_);
        }
    }
    w_.params.threads = c_.simulation.threads;

    if (st_.stage == Stage::Fill) {
        stage_fill();
        next_stage(Stage::Compress);
    }
    if (st_.stage == Stage::Compress) {
        stage_compress();
        next_stage(Stage::Prepared);
        save_prepared();
        apply_config_to_prepared();
    }
    if (st_.stage == Stage::Prepared) next_stage(Stage::Vacuum);
    if (st_.stage == Stage::Vacuum) {
        stage_vacuum();
        next_stage(Stage::Cycling);
    }
    if (st_.stage == Stage::Cycling) {
        stage_cycle();
        next_stage(Stage::Done);
    }
    finish();

    DamperResult r;
    r.grains = g1_ - g0_;
    r.foil_particles = n_foil;
    r.bonds = w_.bonds().size();
    r.foil_columns = L_.cols;
    r.foil_rows = L_.rows;
    r.foil_radius = L_.radius;
    r.height = z_top_;
    r.dt = w_.params.dt;
    r.inertial_number = inertial_number(c_, z_top_);
    LoopSeries ls;
    const int S = int(c_.process.samples_per_cycle);
    for (std::size_t k = 0; k < st_.samples.size(); ++k) {
        ls.time.push_back(st_.samples[k].time);
        ls.displacement.push_back(st_.samples[k].displacement);
        ls.force.push_back(st_.samples[k].grains + st_.samples[k].foil);
        ls.cycle.push_back(int(k / S) + 1);
    }
    r.cycles = analyze_cycles(ls, c_.damper.radius);
    // Energy per cycle: ledger differences between the first samples of consecutive cycles;
    // the last cycle ends at the last step of cycling (one step before the cycle's end).
    if (!st_.energy.empty() && st_.energy.size() == st_.samples.size()) {
        const EnergyRow last = energy_row(w_.energy(), w_.energy().time - st_.cycle_t0);
        for (CycleResult& cr : r.cycles) {
            const std::size_t a = std::size_t(cr.cycle - 1) * std::size_t(S), b = a + std::size_t(S);
            if (a >= st_.energy.size()) continue;
            const EnergyRow& e0 = st_.energy[a];
            const EnergyRow& e1 = b < st_.energy.size() ? st_.energy[b] : last;
            auto d = [&](int k) { return e1.v[k] - e0.v[k]; };
            cr.has_energy = true;
            cr.boundary_work = d(1);
            cr.friction_dissipation = d(7);
            cr.damping_dissipation = d(8);
            cr.viscous_dissipation = d(9);
            cr.energy_residual = d(10);
        }
    }
    r.settling = mark_settled(r.cycles, c_.analysis.settle_tolerance);
    r.report = st_.report;
    r.warnings = st_.warnings;
    r.run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    r.config = c_;
    return r;
}

void DamperRun::finish() {
    write_forces();
    write_energy();
}

}  // namespace

DamperResult run_damper(const Config& config, const DamperOptions& opt) {
    DamperRun run(config, opt);
    DamperResult r = run.run();
    const Config& c = r.config;  // what the run used: a resumed run's settings are its checkpoint's
    const fs::path out(opt.out_dir);
    write_cycles_csv((out / "cycles.csv").string(), r.cycles);

    const double I = r.inertial_number;
    const bool quasi_static = I < 1e-3;
    char msg[320];
    if (!quasi_static) {
        std::snprintf(msg, sizeof msg, "not quasi-static: inertial number %.2g >= 1e-3; lower process.velocity", I);
        r.warnings.push_back(msg);
    }
    if (r.settling.count == 0 && !r.cycles.empty()) {
        std::string changes;
        for (std::size_t k = 1; k < r.cycles.size(); ++k) {
            char b[32];
            std::snprintf(b, sizeof b, "%s%.1f%%", changes.empty() ? "" : ", ",
                          100.0 * std::abs(r.cycles[k].W - r.cycles[k - 1].W) / std::abs(r.cycles[k - 1].W));
            changes += b;
        }
        std::snprintf(msg, sizeof msg,
                      "no cycle settled: W must change by at most %g%% from cycle to cycle in two consecutive cycles "
                      "(changes: %s); run more cycles (process.cycles) or widen analysis.settle_tolerance",
                      100.0 * r.settling.tolerance, changes.empty() ? "one cycle only" : changes.c_str());
        r.warnings.push_back(msg);
    }
    std::string cycles_json = "[";
    for (std::size_t k = 0; k < r.cycles.size(); ++k) {
        const CycleResult& cr = r.cycles[k];
        dem::JsonObject j;
        j.num("cycle", cr.cycle).num("dissipated_energy", cr.dissipated_energy).num("W", cr.W)
            .num("peak_force", cr.peak_force).num("min_force", cr.min_force);
        if (cr.has_energy)
            j.num("boundary_work", cr.boundary_work).num("friction_dissipation", cr.friction_dissipation)
                .num("damping_dissipation", cr.damping_dissipation).num("viscous_dissipation", cr.viscous_dissipation)
                .num("energy_residual", cr.energy_residual);
        j.boolean("settled", cr.settled);
        const std::string t = j.value();
        cycles_json += (k ? ", " : "") + t;
    }
    cycles_json += "]";
    dem::JsonObject inputs;
    for (const Setting& k : summary_inputs())
        k.type == SettingType::Boolean ? (void)inputs.boolean(k.key, k.get(c) != 0.0) : (void)inputs.num(k.key, k.get(c));
    const std::string in = inputs.value();
    // The report's entries with this prefix, without it (absent ones are left out: a sample of
    // an older vppdem did not measure them).
    auto report_json = [&](const std::string& prefix) {
        dem::JsonObject o;
        for (const auto& [k, v] : r.report)
            if (k.starts_with(prefix) && k != "prepare.funnel_height") o.num(k.substr(prefix.size()), v);
        return o.value();
    };
    std::string warnings_json = "[";
    for (std::size_t k = 0; k < r.warnings.size(); ++k)
        warnings_json += (k ? ", " : "") + dem::JsonObject::quote(r.warnings[k]);
    warnings_json += "]";
    dem::JsonObject j;
    j.raw("inputs", in)
        .num("underpressure", c.process.underpressure)
        .num("grains", double(r.grains))
        .num("foil_particles", double(r.foil_particles))
        .num("foil_bonds", double(r.bonds))
        .num("foil_columns", r.foil_columns)
        .num("foil_rows", r.foil_rows)
        .num("foil_radius", r.foil_radius)
        .num("height", r.height)
        .num("particle_modulus", particle_modulus(c.foil))
        .num("bond_kn", bond_normal_stiffness(c.foil))
        .num("dt", r.dt)
        .num("cycle_steps", 2.0 * c.process.amplitude / c.process.velocity / r.dt)
        .num("inertial_number", I)
        .boolean("quasi_static", quasi_static)
        .raw("cycles", cycles_json)
        .num("settle_tolerance", r.settling.tolerance)
        .raw("first_settled_cycle", r.settling.first > 0 ? std::to_string(r.settling.first) : "null")
        .num("settled_cycles", double(r.settling.count))
        .num("W_settled", r.settling.W_mean)
        .num("inner_radius", r.foil_radius - c.foil.particle_radius)
        .raw("preparation", report_json("prepare."))
        .raw("start_of_cycling", report_json("cycle."))
        .raw("warnings", warnings_json)
        .num("run_seconds", r.run_seconds)
        .str("from", opt.from);
    dem::write_text_atomic((out / "summary.json").string(), j.text());

    if (!opt.quiet) {
        std::fprintf(stderr, "\n=== vppdem damper: %s ===\n", opt.out_dir.c_str());
        std::fprintf(stderr, "grains %zu, foil %zu particles (%d x %d, radius %.4g mm), height %.4g mm, dt %.3g s\n",
                     r.grains, r.foil_particles, r.foil_columns, r.foil_rows, 1e3 * r.foil_radius, 1e3 * r.height, r.dt);
        std::fprintf(stderr, "dp %.4g MPa, amplitude %.3g mm, velocity %.4g m/s, inertial number %.2g%s\n",
                     c.process.underpressure * 1e-6, c.process.amplitude * 1e3, c.process.velocity, I,
                     quasi_static ? " (quasi-static)" : "  WARNING: not quasi-static (I >= 1e-3); lower process.velocity");
        std::fprintf(stderr, "cycle  dissipated [J]   W [J/m^2]   peak [N]   min [N]\n");
        for (const auto& cr : r.cycles)
            std::fprintf(stderr, "%5d  %13.5g  %10.5g  %9.4g  %8.4g\n", cr.cycle, cr.dissipated_energy, cr.W,
                         cr.peak_force, cr.min_force);
        if (!r.cycles.empty() && r.cycles[0].has_energy) {
            std::fprintf(stderr, "cycle  boundary work [J]  friction [J]  damping [J]  viscous [J]  residual [%% of work]\n");
            for (const auto& cr : r.cycles)
                std::fprintf(stderr, "%5d  %16.5g  %12.5g  %11.5g  %11.5g  %10.3g\n", cr.cycle, cr.boundary_work,
                             cr.friction_dissipation, cr.damping_dissipation, cr.viscous_dissipation,
                             cr.boundary_work != 0 ? 100.0 * cr.energy_residual / std::abs(cr.boundary_work) : 0.0);
        }
        if (r.settling.count > 0)
            std::fprintf(stderr, "W settled (changes <= %g%%) from cycle %d: W_settled = %.5g J/m^2 over %zu cycle(s)\n",
                         100.0 * r.settling.tolerance, r.settling.first, r.settling.W_mean, r.settling.count);
        for (const std::string& w : r.warnings) std::fprintf(stderr, "WARNING: %s\n", w.c_str());
        std::fprintf(stderr, "run time %.1f s; outputs: forces.csv energy.csv cycles.csv summary.json prepared.ckpt run.ckpt vtk/%s\n",
                     r.run_seconds, opt.plot ? " loops*.png" : "");
    }
    if (opt.plot) plot_damper_dir(opt.out_dir, opt.quiet);
    return r;
}

}  // namespace vpp
