// The device run (vpp/device/run.h): the device's world from its file, the stages, the records
// and the checkpoints. Built the way the damper's run is (vpp/damper_*.cpp): a run object that
// owns the World and a run state that the checkpoint carries (DeviceState), stages that step
// until their end, records written under a temporary name and renamed.
#include "vpp/device/run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "dem/io/archive.h"
#include "dem/io/checkpoint.h"
#include "dem/io/csv.h"
#include "dem/io/energy_columns.h"
#include "dem/io/folder_lock.h"
#include "dem/io/json.h"
#include "dem/io/vtk.h"
#include "dem/world/tool.h"
#include "dem/world/world.h"
#include "scene/build_info.h"
#include "scene/config.h"
#include "scene/progress.h"
#include "scene/setting.h"
#include "scene/scene_runner.h"
#include "scene/time_step.h"
#include "vpp/membrane/foil.h"

namespace vpp {

namespace {

namespace fs = std::filesystem;
using dem::Vec3;

constexpr const char* kCheckpointName = "run.ckpt";
// The pour's opening (grains.fill_mode = "pour"): until the seal its membrane particles carry this
// bit alone, the rest of the membrane this bit and kFoilMask, the grains kGrainMask. So the grains
// pass through the opening (no bit shared) while the opening stays in contact with the rest of the
// membrane and the tools do not see it. Bit 2: the foil's masks use bits 0 and 1 (vpp/membrane/foil.h).
constexpr uint32_t kMaskOpening = 1u << 2;
constexpr int kToolColumns = 4;  // z, fx, fy, fz
constexpr int kAirColumns = 5;   // time, stage, enclosed, gas, dp
constexpr std::size_t kEnergyRowSize = dem::kEnergyColumns.size();  // energy.csv (dem/io/energy_columns.h)

// ---- geometry of the fill

// Distance from p to triangle (a, b, c) [m] (the closest point by region, Ericson's
// "Real-Time Collision Detection" 5.1.5).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return norm(p - a);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return norm(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + ab * (d1 / (d1 - d3))));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return norm(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return norm(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double den = 1.0 / (va + vb + vc);
    return norm(p - (a + ab * (vb * den) + ac * (vc * den)));
}

// Whether p lies inside the closed, outward surface m: its winding number, the triangles' solid
// angles summed (van Oosterom and Strackee), is 1 inside and 0 outside; robust for any shape.
bool inside(const dem::SurfaceMesh& m, const Vec3& p) {
    double omega = 0.0;
    for (const auto& t : m.triangles) {
        const Vec3 a = m.vertices[t[0]] - p, b = m.vertices[t[1]] - p, c = m.vertices[t[2]] - p;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double num = dot(a, cross(b, c));
        const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        omega += 2.0 * std::atan2(num, den);
    }
    return omega > 2.0 * std::numbers::pi;  // winding > 1/2
}

// Whether p lies inside the membrane's closed triangulation of its particles at `pos` (the winding
// number, as inside() above): the surface the seal closes.
bool inside_membrane(const Membrane& m, const std::vector<Vec3>& pos, const Vec3& p) {
    double omega = 0.0;
    for (const auto& t : m.triangles) {
        const Vec3 a = pos[t[0]] - p, b = pos[t[1]] - p, c = pos[t[2]] - p;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double num = dot(a, cross(b, c));
        const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        omega += 2.0 * std::atan2(num, den);
    }
    return omega > 2.0 * std::numbers::pi;
}

double distance_to_surface(const dem::SurfaceMesh& m, const Vec3& p) {
    double d = 1e300;
    for (const auto& t : m.triangles)
        d = std::min(d, point_triangle_distance(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
    return d;
}

// A uniform double in [0, 1) from 53 bits of the generator: the same draw on every platform
// (std::uniform_real_distribution is left to the library).
double uniform(uint64_t& s) {
    // splitmix64
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
}

// ---- the run state the checkpoint carries

struct DeviceState {
    int32_t stage = 0;                 // DeviceStage: the stage to run next
    double stage_t0 = 0;               // [s] its start
    int32_t sealed = 0;                // pressure fans and air on
    std::vector<dem::ToolState> tools;
    MembraneGas gas;
    std::vector<double> window;        // [N] per tool: sums of fx, fy, fz over the sample window
    int64_t window_n = 0;              // steps in the window
    std::vector<double> rows;          // tools.csv, row after row (2 + 4 per tool columns)
    std::vector<double> air;           // air.csv, row after row (kAirColumns)
    std::vector<double> energy;        // energy.csv, row after row (kEnergyRowSize each)
    std::map<std::string, double> report;  // "volume_seal", "volume_vacuum", "fill_settled", "fill_time"
    std::vector<std::string> warnings;
    std::string inputs;                // the device's inputs (device_inputs) the run was started with
    // Where the running stage stands (a checkpoint within a stage resumes from it); reset by
    // next_stage().
    double next_check = 0;             // [s] the fill's next rest check (0: not set)
    int64_t free_steps = 0;            // load: steps the object has been free
    int32_t tools_done = 0;            // vacuum: the tools' segments were done at the last step
    int64_t vtk_frames = 0;            // frames written at output.vtk_interval

    template <class A, class S> static void fields(A& a, S& r) {
        a.section("DEVS", [&](A& s) {
            s.pod(r.stage);
            s.pod(r.stage_t0);
            s.pod(r.sealed);
            s.vec(r.tools);
            s.pod(r.gas);
            s.vec(r.window);
            s.pod(r.window_n);
            s.vec(r.rows);
            s.vec(r.air);
            s.vec(r.energy);
            s.numbers(r.report);
            s.strings(r.warnings);
            s.str(r.inputs);
            s.pod(r.next_check);
            s.pod(r.free_steps);
            s.pod(r.tools_done);
            s.pod(r.vtk_frames);
        });
    }
    std::string save() const {
        dem::io::Writer w;
        fields(w, *this);
        return w.buf;
    }
    static DeviceState load(const std::string& blob, const std::string& path) {
        DeviceState r;
        dem::io::Reader rd(blob.data(), blob.size(), path);
        fields(rd, r);
        if (!rd.done()) dem::io::corrupt(path, "unread bytes after the device's run state");
        if (r.stage < 0 || r.stage > int32_t(DeviceStage::Done)) dem::io::corrupt(path, "stage out of range");
        return r;
    }
};

std::string inputs_text(const DeviceDef& d) {
    std::string s;
    for (const auto& [k, v] : device_inputs(d))
        if (k != "file") s += k + "=" + v + "\n";  // the same device from another folder resumes
    return s;
}

class DeviceRun {
public:
    DeviceRun(const DeviceDef& d, const DeviceOptions& o);
    void run();
    DeviceResult result() const;
    void write_records() const;

private:
    void build();
    void add_grains(const dem::SurfaceMesh& surface, uint32_t material);
    // The pour: the opening's membrane particles (opening_) and their masks, the seal plane, the
    // column's axis and radius; refuses an opening with no room for a grain.
    void open_membrane();
    // The pour's start: a lattice column above the opening (lowest pour_count sites).
    std::vector<Vec3> pour_sites(const std::vector<dem::SurfaceMesh>& tool_surfaces, double a,
                                 const std::vector<Vec3>& basis, double jit) const;
    // Takes grain i out of the run: it interacts with nothing (mask 0) and stands still (fixed). The
    // World has no removal of particles; a retired grain stays in its arrays, left out of the
    // counts, the grains' volume and the VTK frames.
    void retire_grain(uint32_t i);
    bool active_grain(uint32_t i) const { return world_.particles.mask[i] != 0; }
    std::size_t active_grains() const;
    double active_grain_volume() const;
    // The pour's seal: the grains outside the membrane or overlapping the opening are retired,
    // the opening's masks restored; returns how many were retired.
    std::size_t strike_off();
    // [m] The largest overlap of a grain with a membrane particle now (0: none touches).
    double largest_membrane_overlap() const;
    void start_output(const std::string& resumed_from);
    void checkpoint();
    // VTK frame DIR/vtk/NAME.vtk (particles and bonds) and NAME_tools.vtk (the tools' facets).
    void vtk_frame(const std::string& name) const;
    // Before each step within a stage: a checkpoint every options_.checkpoint_every seconds of wall
    // clock, and the stop that options_.stop_at_time asks for (checkpoint, records; true: stop now).
    bool pause_point();
    // One step of `stage` with the regulator at dp_set [Pa]; true when the tools' segments of the
    // stage are done.
    bool step(DeviceStage stage, double dp_set);
    void stage_fill();
    void stage_seal();
    void stage_tools(DeviceStage stage);
    void stage_vacuum();
    void next_stage();
    double grains_kinetic_energy() const;
    double enclosed() const { return enclosed_volume(membrane_, world_.particles.pos); }
    void warn(const std::string& what);
    void log(const std::string& what) const {
        if (!options_.quiet) std::fprintf(stderr, "[device] %s\n", what.c_str());
    }

    DeviceDef def_;
    DeviceOptions options_;
    std::string base_;
    dem::World world_;
    Membrane membrane_;
    std::vector<dem::Tool> tools_;
    uint32_t first_grain_ = 0, end_grain_ = 0;  // the grains' particle range
    uint32_t grain_mat_ = 0;
    double grain_volume_ = 0;   // [m^3] of the active grains (a pour's struck-off grains left out)
    bool pour_ = false;         // grains.fill_mode = "pour"
    std::vector<uint32_t> opening_;  // pour: the opening's membrane particles
    double z_seal_ = 0;         // [m] pour: the membrane's top less opening_height (at the build)
    double axis_x_ = 0, axis_y_ = 0, column_radius_ = 0;  // [m] pour: the column's axis and radius
    DeviceState state_;
    fs::path out_;
    dem::FolderLock lock_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_ckpt_ = start_;
    bool stopped_ = false;
};

DeviceRun::DeviceRun(const DeviceDef& d, const DeviceOptions& o) : def_(d), options_(o) {
    base_ = fs::path(d.path).parent_path().string();
    build();
    const std::string from = scene::resume_checkpoint(o.out_dir, o.from, o.overwrite);
    if (!from.empty()) {
        const std::string blob = dem::load_checkpoint(from, world_);
        state_ = DeviceState::load(blob, from);
        if (state_.inputs != inputs_text(def_))
            throw std::runtime_error("checkpoint '" + from + "' was made with another device file (its inputs differ from '" +
                                     def_.path + "'): run into a new --out, or give the device file it was made with");
        if (state_.sealed) world_.pressure.fans = membrane_pressure_fans(membrane_);
        if (pour_) grain_volume_ = active_grain_volume();  // the struck-off grains are in the World's masks
        world_.params.threads = def_.threads;  // this machine's, not the checkpoint's (the results do not depend on it)
        char at[64];
        std::snprintf(at, sizeof at, "t = %.6g s", world_.time);
        log("resuming from " + from + " at " + at + " in the stage '" + device_stage_name(DeviceStage(state_.stage)) + "'");
    } else {
        state_.inputs = inputs_text(def_);
        state_.tools.assign(tools_.size(), dem::ToolState{});
        state_.window.assign(3 * tools_.size(), 0.0);
    }
    start_output(from);
}

void DeviceRun::start_output(const std::string& resumed_from) {
    if (options_.out_dir.empty()) return;
    out_ = options_.out_dir;
    const bool own = !resumed_from.empty() && fs::exists(out_ / kCheckpointName) &&
                     fs::equivalent(fs::path(resumed_from), out_ / kCheckpointName);
    lock_ = own ? scene::lock_output_dir(options_.out_dir) : scene::prepare_output_dir(options_.out_dir, options_.overwrite);
    if (own) scene::record_build(options_.out_dir, false);  // another build resuming the run is listed
}

void DeviceRun::build() {
    const dem::SurfaceMesh surface = device_surface(def_.membrane_shape, "membrane", base_);
    MembraneDef md = def_.membrane;
    md.seed = def_.seed == 0 ? 1 : def_.seed;
    membrane_ = build_membrane(world_, md, surface);  // the foil's material is 0

    dem::Material gm;
    gm.name = "grains";
    gm.density = def_.grain_density;
    gm.young = def_.grain_young;
    gm.friction = def_.fill_friction;  // grains.friction from the seal on
    gm.stiffness_ratio = def_.grain_stiffness_ratio;
    const uint32_t grain_mat = world_.add_material(gm);
    grain_mat_ = grain_mat;

    for (std::size_t k = 0; k < def_.tools.size(); ++k) {
        const DeviceTool& t = def_.tools[k];
        dem::Tool tool;
        tool.name = t.name;
        tool.program = t.program;
        if (t.shape.kind != "none") {
            dem::Material tm;
            tm.name = "tool " + t.name;
            tm.young = t.young;
            tm.friction = t.friction;
            tm.stiffness_ratio = t.stiffness_ratio;
            const uint32_t mat = world_.add_material(tm);
            const dem::SurfaceMesh s = device_surface(t.shape, "tools[" + std::to_string(k) + "]", base_);
            std::vector<dem::Facet> facets;
            for (const auto& tri : s.triangles) {
                dem::Facet f;
                f.vertices = {s.vertices[tri[0]], s.vertices[tri[1]], s.vertices[tri[2]]};
                f.material = mat;
                f.mask = kMaskGrainFoil;  // grains and membrane; the grains' mask shares the bit
                facets.push_back(f);
            }
            dem::add_tool_facets(world_, tool, facets);
        }
        tools_.push_back(std::move(tool));
    }
    if (!def_.clamp_tool.empty()) {
        double z_top = -1e300;
        for (uint32_t i : membrane_.particles) z_top = std::max(z_top, world_.particles.pos[i].z);
        std::vector<uint32_t> clamp;
        for (uint32_t i : membrane_.particles)
            if (world_.particles.pos[i].z >= z_top - def_.clamp_height) clamp.push_back(i);
        for (dem::Tool& t : tools_)
            if (t.name == def_.clamp_tool) dem::clamp_to_tool(world_, t, clamp);
    }

    pour_ = def_.fill_mode == "pour";
    if (pour_) open_membrane();
    first_grain_ = uint32_t(world_.particles.size());
    add_grains(surface, grain_mat);
    end_grain_ = uint32_t(world_.particles.size());
    grain_volume_ = active_grain_volume();

    world_.params.gravity = def_.gravity;
    world_.params.local_damping = def_.local_damping;
    world_.params.threads = def_.threads;
    world_.params.dt = scene::time_step({.automatic = def_.dt == 0.0, .dt = def_.dt, .safety = def_.dt_safety}, world_);
    if (!(world_.params.dt > 0.0) || !std::isfinite(world_.params.dt))
        throw std::runtime_error("device: no usable time step (" + std::to_string(world_.params.dt) + " s)");
}

void DeviceRun::add_grains(const dem::SurfaceMesh& surface, uint32_t material) {
    const double r = def_.grain_radius, h = def_.lattice_spacing * r;
    // The grains' surfaces clear the membrane particles' (their centres sit on the surface) by a
    // tenth of a radius, and the tools'.
    const double clear = r + def_.membrane.foil.particle_radius + 0.1 * r;
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3& v : surface.vertices) {
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    std::vector<dem::SurfaceMesh> tool_surfaces;
    for (std::size_t k = 0; k < def_.tools.size(); ++k)
        if (def_.tools[k].shape.kind != "none")
            tool_surfaces.push_back(device_surface(def_.tools[k].shape, "tools[" + std::to_string(k) + "]", base_));
    std::vector<Vec3> sites;
    // cubic: a cell of edge h, one site; fcc: a cell of edge h sqrt(2), four sites (nearest
    // neighbours h apart along face diagonals).
    const bool fcc = def_.lattice == "fcc";
    const double a = fcc ? h * std::numbers::sqrt2 : h;
    const std::vector<Vec3> basis = fcc ? std::vector<Vec3>{{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}}
                                        : std::vector<Vec3>{{0, 0, 0}};
    // A jitter of up to 0.9 (h - 2r) / 2 per axis (fcc: / sqrt 2, as its neighbours lie along face
    // diagonals): loose, random, never overlapping.
    const double jit = 0.5 * (h - 2.0 * r) * 0.9 / (fcc ? std::numbers::sqrt2 : 1.0);
    if (pour_) sites = pour_sites(tool_surfaces, a, basis, jit);
    // The lattice's first site: half a spacing in from the surface's bounding box (cubic); fcc:
    // at the clearance (and a hundredth of a radius), so that a box is filled up to its faces
    // on its low sides (and on its high sides too where its edges are 2 clear + 0.01 r + a
    // multiple of h / sqrt 2).
    const double off = fcc ? (clear + 0.01 * r) / a : 0.5 * h / a;
    const int nx = int((hi.x - lo.x) / a) + 1, ny = int((hi.y - lo.y) / a) + 1, nz = int((hi.z - lo.z) / a) + 1;
    for (int k = 0; k < nz && !pour_; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (const Vec3& b : basis) {
                    const Vec3 p = lo + a * Vec3{i + off + b.x, j + off + b.y, k + off + b.z};
                    if (!inside(surface, p) || distance_to_surface(surface, p) < clear) continue;
                    bool free = true;
                    for (const dem::SurfaceMesh& ts : tool_surfaces)
                        if (inside(ts, p) || distance_to_surface(ts, p) < r + 0.1 * r) free = false;
                    if (free) sites.push_back(p);
                }
    if (sites.empty())
        throw cfg::ConfigError("config key 'grains.radius' = " + cfg::number_text(r) +
                               ": no grain fits inside the membrane (a clearance of " + cfg::number_text(clear) +
                               " m from it is needed)");
    // Lowest first (poured), lattice order within a layer; n of them (the pour's column: its own).
    if (!pour_) {
        const std::size_t n = std::max<std::size_t>(1, std::size_t(std::llround(def_.fill * double(sites.size()))));
        std::stable_sort(sites.begin(), sites.end(), [](const Vec3& a, const Vec3& b) { return a.z < b.z; });
        sites.resize(std::min(n, sites.size()));
    }
    uint64_t rng = 0x5eed0000ull + def_.seed;
    dem::SphereDef s;
    s.radius = r;
    s.material = material;
    s.mask = kGrainMask;
    world_.reserve(world_.particles.size() + sites.size());
    for (const Vec3& p : sites) {
        const Vec3 j{(2 * uniform(rng) - 1) * jit, (2 * uniform(rng) - 1) * jit, (2 * uniform(rng) - 1) * jit};
        s.position = p + j;
        world_.add_sphere(s);
    }
}

void DeviceRun::open_membrane() {
    const double r = def_.grain_radius, rf = def_.membrane.foil.particle_radius;
    const double clear = r + rf + 0.1 * r;  // as the lattice's
    const std::vector<Vec3>& pos = world_.particles.pos;
    double z_top = -1e300, z_bottom = 1e300;
    for (uint32_t i : membrane_.particles) {
        z_top = std::max(z_top, pos[i].z);
        z_bottom = std::min(z_bottom, pos[i].z);
    }
    const std::string key = "config key 'grains.opening_height' = " + cfg::number_text(def_.opening_height);
    auto mm = [](double v) {  // [m], three digits: a message's lengths
        char b[32];
        std::snprintf(b, sizeof b, "%.3g", v);
        return std::string(b);
    };
    if (def_.opening_height >= z_top - z_bottom)
        throw cfg::ConfigError(key + ": must be less than the membrane's height, " + mm(z_top - z_bottom) +
                               " m (its particles' centres from the lowest to the top): the opening is a part of its top");
    z_seal_ = z_top - def_.opening_height;
    double sx = 0, sy = 0;
    for (uint32_t i : membrane_.particles)
        if (pos[i].z >= z_seal_) {
            opening_.push_back(i);
            sx += pos[i].x;
            sy += pos[i].y;
        }
    axis_x_ = sx / double(opening_.size());
    axis_y_ = sy / double(opening_.size());
    // The aperture: the nearest membrane particle to the axis, of those in the band a grain
    // diameter and a membrane particle's below the seal plane (the rim the grains pass).
    double ra = 1e300;
    for (uint32_t i : membrane_.particles)
        if (pos[i].z < z_seal_ && pos[i].z >= z_seal_ - 2.0 * (r + rf))
            ra = std::min(ra, std::hypot(pos[i].x - axis_x_, pos[i].y - axis_y_));
    if (ra == 1e300)  // no membrane below the opening: it would be the whole membrane
        throw cfg::ConfigError(key + ": leaves no membrane within " + mm(2.0 * (r + rf)) +
                               " m below the opening's edge (the rim the grains pass); a smaller opening_height is needed");
    // A grain passes the rim when the aperture, clear of the membrane particles, is wider than a
    // grain's diameter and a tenth of its radius.
    if (!(ra - rf >= 2.1 * r))
        throw cfg::ConfigError(key + ": the opening's radius clear of the membrane particles is " +
                               mm(std::max(0.0, ra - rf)) + " m, less than a grain's diameter plus a tenth of its radius (" +
                               mm(2.1 * r) + " m): no room for a grain to pass; a larger opening_height (less than the "
                               "membrane's height, " + mm(z_top - z_bottom) + " m) or smaller grains are needed");
    column_radius_ = ra - clear;
    // Until the seal the grains pass through the opening; the rest of the membrane touches it.
    for (uint32_t i : membrane_.particles) world_.particles.mask[i] = kFoilMask | kMaskOpening;
    for (uint32_t i : opening_) world_.particles.mask[i] = kMaskOpening;
}

std::vector<Vec3> DeviceRun::pour_sites(const std::vector<dem::SurfaceMesh>& tool_surfaces, double a,
                                        const std::vector<Vec3>& basis, double jit) const {
    const double r = def_.grain_radius, rf = def_.membrane.foil.particle_radius;
    const double clear = r + rf + 0.1 * r;
    // Sites above the seal plane by the clearance and the jitter: no membrane particle but the
    // opening's (which the grains pass through) lies there, so no grain starts in contact. The
    // column's radius keeps the jittered grains the clearance inside the rim.
    const double z0 = z_seal_ + clear + jit * std::numbers::sqrt2;
    const double rc = std::max(0.0, column_radius_ - jit * std::numbers::sqrt2);
    const int n = int(rc / a) + 1;
    const std::size_t want = std::size_t(def_.pour_count);
    std::vector<Vec3> sites;
    int empty_rows = 0;
    for (int k = 0; sites.size() < want; ++k) {
        const std::size_t before = sites.size();
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i)
                for (const Vec3& b : basis) {
                    const Vec3 p{axis_x_ + a * (i + b.x), axis_y_ + a * (j + b.y), z0 + a * (k + b.z)};
                    if (std::hypot(p.x - axis_x_, p.y - axis_y_) > rc) continue;
                    bool free = true;
                    for (const dem::SurfaceMesh& ts : tool_surfaces)
                        if (inside(ts, p) || distance_to_surface(ts, p) < r + 0.1 * r) free = false;
                    if (free) sites.push_back(p);
                }
        empty_rows = sites.size() == before ? empty_rows + 1 : 0;
        if (empty_rows > 100)
            throw cfg::ConfigError("config key 'grains.pour_count' = " + std::to_string(def_.pour_count) +
                                   ": the column above the opening has room for " + std::to_string(sites.size()) +
                                   " grains only (a tool fills it)");
    }
    // Lowest first, lattice order within a layer.
    std::stable_sort(sites.begin(), sites.end(), [](const Vec3& p, const Vec3& q) { return p.z < q.z; });
    sites.resize(want);
    return sites;
}

void DeviceRun::retire_grain(uint32_t i) {
    world_.set_fixed(i);
    world_.particles.mask[i] = 0;
}

std::size_t DeviceRun::active_grains() const {
    std::size_t n = 0;
    for (uint32_t i = first_grain_; i < end_grain_; ++i) n += active_grain(i);
    return n;
}

double DeviceRun::active_grain_volume() const {
    double v = 0.0;
    for (uint32_t i = first_grain_; i < end_grain_; ++i)
        if (active_grain(i)) v += 4.0 / 3.0 * std::numbers::pi * std::pow(world_.particles.radius[i], 3);
    return v;
}

double DeviceRun::largest_membrane_overlap() const {
    const dem::Particles& p = world_.particles;
    double worst = 0.0;
    for (uint32_t i = first_grain_; i < end_grain_; ++i) {
        if (!active_grain(i)) continue;
        for (uint32_t k : membrane_.particles)
            worst = std::max(worst, p.radius[i] + p.radius[k] - norm(p.pos[i] - p.pos[k]));
    }
    return worst;
}

std::size_t DeviceRun::strike_off() {
    const dem::Particles& p = world_.particles;
    std::vector<uint32_t> out;
    for (uint32_t i = first_grain_; i < end_grain_; ++i) {
        if (!active_grain(i)) continue;
        // Outside the membrane that the seal closes (above the opening, or spilled beside the bag).
        bool off = !inside_membrane(membrane_, p.pos, p.pos[i]);
        // Overlapping an opening particle: its contact would start deep, with a kick.
        for (std::size_t k = 0; k < opening_.size() && !off; ++k)
            off = norm(p.pos[i] - p.pos[opening_[k]]) < p.radius[i] + p.radius[opening_[k]];
        if (off) out.push_back(i);
    }
    for (uint32_t i : out) retire_grain(i);
    for (uint32_t i : membrane_.particles) world_.particles.mask[i] = kFoilMask;
    // The pairs of the opening and the grains become candidates, the retired grains' contacts go:
    // the next step's broad phase rebuilds the lists from the masks (ContactSet::reattach).
    world_.invalidate_candidates();
    return out.size();
}

void DeviceRun::warn(const std::string& what) {
    state_.warnings.push_back(what);
    if (!options_.quiet) std::fprintf(stderr, "[device] warning: %s\n", what.c_str());
}

double DeviceRun::grains_kinetic_energy() const {
    return dem::kinetic_energy(world_.particles, first_grain_, end_grain_).translation;
}

bool DeviceRun::step(DeviceStage stage, double dp_set) {
    bool done = true;
    for (std::size_t k = 0; k < tools_.size(); ++k) done = dem::drive_tool(world_, tools_[k], state_.tools[k], int32_t(stage)) && done;
    if (state_.sealed) membrane_air_step(world_, membrane_, grain_volume_, dp_set, def_.air, state_.gas);
    world_.compute_forces();
    for (std::size_t k = 0; k < tools_.size(); ++k) {
        const Vec3 f = dem::tool_force(world_, tools_[k]);
        state_.window[3 * k] += f.x;
        state_.window[3 * k + 1] += f.y;
        state_.window[3 * k + 2] += f.z;
    }
    ++state_.window_n;
    const std::size_t cols = 2 + kToolColumns * tools_.size();
    const std::size_t taken = state_.rows.size() / cols;
    const bool sample = world_.time >= double(taken + 1) * def_.sample_interval - 0.5 * world_.params.dt;
    if (sample) {
        state_.rows.push_back(world_.time);
        state_.rows.push_back(double(int(stage)));
        for (std::size_t k = 0; k < tools_.size(); ++k) {
            state_.rows.push_back(dem::tool_displacement(world_, tools_[k], world_.time));
            for (int c = 0; c < 3; ++c) state_.rows.push_back(state_.window[3 * k + c] / double(state_.window_n));
        }
        std::fill(state_.window.begin(), state_.window.end(), 0.0);
        state_.window_n = 0;
        const double v = enclosed();
        state_.air.insert(state_.air.end(), {world_.time, double(int(stage)), v, v - grain_volume_, world_.pressure.dp});
    }
    world_.integrate();
    if (def_.vtk_interval > 0.0 && world_.time >= double(state_.vtk_frames + 1) * def_.vtk_interval - 0.5 * world_.params.dt) {
        ++state_.vtk_frames;
        char name[32];
        std::snprintf(name, sizeof name, "frame_%06lld", (long long)state_.vtk_frames);
        vtk_frame(name);
    }
    if (sample && world_.params.track_energy) {
        double row[kEnergyRowSize];
        dem::energy_csv_row(world_.energy(), world_.energy().time, row);
        state_.energy.insert(state_.energy.end(), row, row + kEnergyRowSize);
    }
    return done;
}

void DeviceRun::stage_fill() {
    const double check = 2e-3;  // [s] between the rest checks, at fixed times from the stage start
    // The grains' weight lifted by a diameter (with g = 9.81 m/s^2 where the device has no gravity).
    const double g = norm(def_.gravity) > 0.0 ? norm(def_.gravity) : 9.81;
    const double scale = double(active_grains()) * world_.particles.mass[first_grain_] * g * 2.0 * def_.grain_radius;
    scene::Progress prog("fill", uint64_t(def_.fill_time / world_.params.dt), options_.quiet);
    uint64_t n = 0;
    if (state_.next_check == 0) state_.next_check = state_.stage_t0 + check;
    for (;;) {
        if (pause_point()) return;
        step(DeviceStage::Fill, 0.0);
        prog.update(++n, world_.time);
        if (world_.time < state_.next_check) continue;
        state_.next_check += check;
        if (pour_) {
            // Grains that missed the bag (or spilled over its rim) and fell below it would fall for
            // ever and keep the pour from coming to rest: retired here, counted.
            double z_min = 1e300;
            for (uint32_t i : membrane_.particles) z_min = std::min(z_min, world_.particles.pos[i].z);
            bool any = false;
            for (uint32_t i = first_grain_; i < end_grain_; ++i)
                if (active_grain(i) && world_.particles.pos[i].z < z_min - 2.0 * def_.grain_radius) {
                    retire_grain(i);
                    state_.report["grains_spilled"] += 1.0;
                    any = true;
                }
            if (any) world_.invalidate_candidates();
        }
        const double t = world_.time - state_.stage_t0;
        const double ke = grains_kinetic_energy();
        if (t >= def_.fill_min_time && ke < 1e-4 * scale) {
            state_.report["fill_settled"] = 1.0;
            break;
        }
        if (t >= def_.fill_time) {
            state_.report["fill_settled"] = 0.0;
            char msg[320];
            std::snprintf(msg, sizeof msg, "fill: the grains are not at rest after stages.fill_time = %g s (kinetic energy %.3g J; "
                          "at rest below %.3g J, 1e-4 N m g 2r): the next stage starts on moving grains",
                          def_.fill_time, ke, 1e-4 * scale);
            warn(msg);
            break;
        }
    }
    state_.report["fill_time"] = world_.time - state_.stage_t0;
    char msg[160];
    std::snprintf(msg, sizeof msg, "fill: %u grains settled in %.4g s", unsigned(active_grains()), world_.time - state_.stage_t0);
    log(msg);
}

void DeviceRun::stage_seal() {
    if (pour_) {
        const std::size_t n = strike_off();
        state_.report["grains_removed_at_seal"] = double(n);
        grain_volume_ = active_grain_volume();
        char msg[200];
        std::snprintf(msg, sizeof msg, "seal: the opening closed; %zu grains struck off (outside the membrane or overlapping "
                      "the opening), %zu in the bag", n, active_grains());
        log(msg);
    }
    state_.report["seal_max_overlap"] = largest_membrane_overlap();
    if (world_.materials[grain_mat_].friction != def_.grain_friction) {  // the fill's friction ends with the fill
        world_.materials[grain_mat_].friction = def_.grain_friction;
        world_.invalidate_contact_physics();
    }
    world_.pressure.fans = membrane_pressure_fans(membrane_);
    world_.pressure.dp = 0.0;
    state_.sealed = 1;
    state_.gas = MembraneGas{};
    state_.report["volume_seal"] = enclosed();
    if (def_.energy) {
        world_.params.track_energy = true;
        world_.reset_energy();
    }
    char msg[160];
    std::snprintf(msg, sizeof msg, "seal: enclosed volume %.6g m^3 (grains %.6g m^3)", enclosed(), grain_volume_);
    log(msg);
}

void DeviceRun::stage_tools(DeviceStage stage) {
    double longest = 0;
    for (const dem::Tool& t : tools_)
        longest = std::max(longest, dem::program_duration(t, int32_t(stage), dem::tool_displacement(world_, t, world_.time)));
    scene::Progress prog(device_stage_name(stage), uint64_t(longest / world_.params.dt) + 1, options_.quiet);
    uint64_t n = 0;
    const double dp = state_.sealed && stage > DeviceStage::Vacuum ? def_.underpressure : 0.0;
    // The load stage ends early once the object has carried no force for result.release_time
    // (it has let go: the rest of the lift would record zeros).
    const dem::Tool* obj = nullptr;
    for (const dem::Tool& t : tools_)
        if (t.name == def_.object && stage == DeviceStage::Load && def_.release_time > 0) obj = &t;
    // The cycle tool's first load-stage cycle segment: where and when it starts is the cycle
    // analysis's origin (recorded once it has started; kept over a resume).
    std::size_t ck = tools_.size();
    int32_t cseg = -1;
    for (std::size_t k = 0; k < tools_.size(); ++k)
        if (stage == DeviceStage::Load && tools_[k].name == def_.cycle_tool)
            for (std::size_t s = 0; s < tools_[k].program.size() && cseg < 0; ++s)
                if (tools_[k].program[s].stage == int32_t(stage) && tools_[k].program[s].kind == dem::SegmentKind::Cycle) {
                    ck = k;
                    cseg = int32_t(s);
                }
    auto note_cycle = [&] {
        if (ck == tools_.size() || state_.report.count("cycle_t0")) return;
        const dem::ToolState& ts = state_.tools[ck];
        if (ts.segment != cseg || !ts.started) return;
        state_.report["cycle_t0"] = ts.t0;
        state_.report["cycle_d0"] = ts.d0;
    };
    for (;;) {
        if (pause_point()) return;
        const bool done = step(stage, dp);
        note_cycle();
        if (done) break;
        prog.update(++n, world_.time);
        if (!obj) continue;
        state_.free_steps = dem::tool_force(world_, *obj) == Vec3{} ? state_.free_steps + 1 : 0;
        if (double(state_.free_steps) * world_.params.dt >= def_.release_time) {
            char msg[160];
            std::snprintf(msg, sizeof msg, "load: the object '%s' let go; the load stage ends at t = %.6g s",
                          def_.object.c_str(), world_.time);
            log(msg);
            state_.report["released"] = 1.0;
            break;
        }
    }
}

void DeviceRun::stage_vacuum() {
    const double t_end = def_.ramp_time + def_.vacuum_hold;
    if (!state_.report.count("volume_press")) state_.report["volume_press"] = enclosed();  // the vacuum's start
    scene::Progress prog("vacuum", uint64_t(t_end / world_.params.dt) + 1, options_.quiet);
    uint64_t n = 0;
    for (;;) {
        const double t = world_.time - state_.stage_t0;
        if (t >= t_end - 0.5 * world_.params.dt && state_.tools_done) break;
        if (pause_point()) return;
        state_.tools_done = step(DeviceStage::Vacuum, def_.underpressure * std::min(1.0, t / def_.ramp_time));
        prog.update(++n, world_.time);
    }
    state_.report["volume_vacuum"] = enclosed();
    double z_min = 1e300;
    for (uint32_t i : membrane_.particles) z_min = std::min(z_min, world_.particles.pos[i].z);
    state_.report["membrane_z_min"] = z_min;
    char msg[160];
    std::snprintf(msg, sizeof msg, "vacuum: dp %.6g Pa, enclosed volume %.6g m^3, the membrane's lowest point at z = %.6g m",
                  world_.pressure.dp, enclosed(), z_min);
    log(msg);
}

bool DeviceRun::pause_point() {
    if (options_.stop_at_time >= 0.0 && world_.time >= options_.stop_at_time) {
        checkpoint();
        write_records();
        stopped_ = true;
        return true;
    }
    const auto now = std::chrono::steady_clock::now();
    if (!out_.empty() && std::chrono::duration<double>(now - last_ckpt_).count() >= options_.checkpoint_every) {
        checkpoint();
        last_ckpt_ = now;
    }
    return false;
}

void DeviceRun::vtk_frame(const std::string& name) const {
    if (out_.empty()) return;
    fs::create_directories(out_ / "vtk");
    // The retired grains (a pour's struck off) are left out; without any, every particle.
    std::vector<uint32_t> shown;
    if (pour_)
        for (uint32_t i = 0; i < uint32_t(world_.particles.size()); ++i)
            if (i < first_grain_ || i >= end_grain_ || active_grain(i)) shown.push_back(i);
    dem::write_particles_vtk((out_ / "vtk" / (name + ".vtk")).string(), world_, true, pour_ ? &shown : nullptr);
    if (!world_.facets.empty()) dem::write_walls_vtk((out_ / "vtk" / (name + "_tools.vtk")).string(), world_, 0.0);
}

void DeviceRun::next_stage() {
    if (def_.vtk) vtk_frame("stage_" + std::to_string(state_.stage) + "_" + device_stage_name(DeviceStage(state_.stage)));
    ++state_.stage;
    state_.stage_t0 = world_.time;
    state_.next_check = 0;
    state_.free_steps = 0;
    state_.tools_done = 0;
    checkpoint();
    write_records();
}

void DeviceRun::checkpoint() {
    if (out_.empty()) return;
    // The fans follow from the membrane, which the device file rebuilds: restored on load.
    save_checkpoint_without_fans((out_ / kCheckpointName).string(), world_, state_.save());
}

void DeviceRun::run() {
    while (state_.stage < int32_t(DeviceStage::Done)) {
        const DeviceStage s = DeviceStage(state_.stage);
        if (int32_t(s) > int32_t(options_.stop_after)) break;
        switch (s) {
        case DeviceStage::Fill: stage_fill(); break;
        case DeviceStage::Seal: stage_seal(); break;
        case DeviceStage::Press: stage_tools(s); break;
        case DeviceStage::Vacuum: stage_vacuum(); break;
        case DeviceStage::Load: stage_tools(s); break;
        case DeviceStage::Done: break;
        }
        if (stopped_) return;
        next_stage();
    }
}

DeviceResult DeviceRun::result() const {
    DeviceResult r;
    r.stage = device_stage_name(DeviceStage(state_.stage));
    r.grains = active_grains();
    r.grains_placed = end_grain_ - first_grain_;
    r.grains_spilled = std::size_t(state_.report.count("grains_spilled") ? state_.report.at("grains_spilled") : 0.0);
    r.grains_removed_at_seal =
        std::size_t(state_.report.count("grains_removed_at_seal") ? state_.report.at("grains_removed_at_seal") : 0.0);
    r.seal_max_overlap = state_.report.count("seal_max_overlap") ? state_.report.at("seal_max_overlap") : 0.0;
    r.membrane_particles = membrane_.particles.size();
    r.bonds = membrane_.bonds.size();
    r.dt = world_.params.dt;
    const std::size_t cols = 2 + kToolColumns * tools_.size();
    r.samples = state_.rows.size() / cols;
    std::size_t obj = tools_.size();
    for (std::size_t k = 0; k < tools_.size(); ++k)
        if (tools_[k].name == def_.object) obj = k;
    if (obj < tools_.size())
        for (std::size_t s = 0; s < r.samples; ++s) {
            const double* row = &state_.rows[s * cols];
            const double fz = row[2 + kToolColumns * obj + 3];
            if (int(row[1]) == int(DeviceStage::Load) && fz > r.holding_force) {
                r.holding_force = fz;
                r.holding_time = row[0];
            }
            if (int(row[1]) < int(DeviceStage::Load)) r.press_force = std::max(r.press_force, -fz);
        }
    auto rep = [&](const char* k) { return state_.report.count(k) ? state_.report.at(k) : 0.0; };
    // The cycle tool's loops: P = -sign(a) F_z, the load it puts on the sample along the cycle's
    // first leg, against u = sign(a) (z - z0), the displacement along it. Rows are assigned to
    // cycles by time (period 2 |a| / speed from the load stage's start); each cycle's loop is
    // closed by the row before it (or u = 0, P = its first row's at the start).
    for (std::size_t k = 0; k < tools_.size(); ++k) {
        if (tools_[k].name != def_.cycle_tool || !state_.report.count("cycle_t0")) continue;
        const dem::ToolSegment* seg = nullptr;
        for (const dem::ToolSegment& s : tools_[k].program)
            if (!seg && s.stage == int32_t(DeviceStage::Load) && s.kind == dem::SegmentKind::Cycle) seg = &s;
        if (!seg) break;
        const double sg = seg->amplitude < 0 ? -1.0 : 1.0, amp = std::abs(seg->amplitude);
        const double period = 2.0 * amp / seg->speed, t0 = rep("cycle_t0"), z0 = rep("cycle_d0");
        std::vector<std::vector<std::pair<double, double>>> loops(std::size_t(seg->cycles));
        std::pair<double, double> prev{0.0, 0.0};
        bool have_prev = false;
        for (std::size_t s = 0; s < r.samples; ++s) {
            const double* row = &state_.rows[s * cols];
            if (int(row[1]) != int(DeviceStage::Load)) continue;
            const double t = row[0] - t0;
            const long c = t <= 0.0 ? -1 : long(std::floor((t - 1e-12) / period));
            const std::pair<double, double> up{sg * (row[2 + kToolColumns * k] - z0), -sg * row[2 + kToolColumns * k + 3]};
            if (c >= 0 && c < long(loops.size())) {
                auto& L = loops[std::size_t(c)];
                if (L.empty()) L.push_back(have_prev ? prev : std::pair<double, double>{0.0, up.second});
                L.push_back(up);
            }
            prev = up;
            have_prev = true;
        }
        for (const auto& L : loops) {
            if (L.size() < 4) continue;
            double w = 0, peak = 0;
            double su = 0, sp = 0, suu = 0, sup = 0;
            int n = 0;
            for (std::size_t i = 1; i < L.size(); ++i) {
                w += 0.5 * (L[i].second + L[i - 1].second) * (L[i].first - L[i - 1].first);
                peak = std::max(peak, L[i].second);
            }
            // The loading branch: the first leg (u rising to its largest).
            std::size_t top = 0;
            for (std::size_t i = 0; i < L.size(); ++i)
                if (L[i].first > L[top].first) top = i;
            for (std::size_t i = 0; i <= top; ++i) {
                su += L[i].first;
                sp += L[i].second;
                suu += L[i].first * L[i].first;
                sup += L[i].first * L[i].second;
                ++n;
            }
            const double den = double(n) * suu - su * su;
            r.cycle_stiffness.push_back(n >= 2 && den > 0 ? (double(n) * sup - su * sp) / den : 0.0);
            r.cycle_work.push_back(w);
            r.cycle_peak_force.push_back(peak);
        }
    }
    r.volume_seal = rep("volume_seal");
    r.volume_vacuum = rep("volume_vacuum");
    r.volume_press = rep("volume_press");
    if (r.volume_seal > 0 && r.volume_vacuum > 0) r.volume_change = (r.volume_vacuum - r.volume_seal) / r.volume_seal;
    if (r.volume_press > 0 && r.volume_vacuum > 0) r.volume_change_vacuum = (r.volume_vacuum - r.volume_press) / r.volume_press;
    r.fill_settled = rep("fill_settled") != 0.0;
    r.packing_seal = r.volume_seal > 0 ? grain_volume_ / r.volume_seal : 0.0;
    // The scale: the largest term of any row (every column but the time and the residual).
    const std::size_t first = dem::energy_column("boundary_work"), res = dem::energy_column("residual");
    for (std::size_t s = 0; s + kEnergyRowSize <= state_.energy.size(); s += kEnergyRowSize)
        for (std::size_t c = first; c < kEnergyRowSize; ++c)
            if (c != res) r.energy_scale = std::max(r.energy_scale, std::abs(state_.energy[s + c]));
    if (!state_.energy.empty()) r.energy_residual = state_.energy.back();
    r.run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    r.warnings = state_.warnings;
    return r;
}

// A JSON array of numbers on one line.
std::string number_array(const std::vector<double>& v) {
    std::string out = "[";
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + dem::json_double(v[k]);
    return out + "]";
}

void DeviceRun::write_records() const {
    if (out_.empty()) return;
    std::string header = "time,stage";
    for (const dem::Tool& t : tools_) header += "," + t.name + "_z," + t.name + "_fx," + t.name + "_fy," + t.name + "_fz";
    const std::size_t cols = 2 + kToolColumns * tools_.size();
    {
        dem::CsvWriter csv((out_ / "tools.csv").string(), header);
        for (std::size_t s = 0; s + cols <= state_.rows.size(); s += cols)
            csv.row(std::vector<double>(state_.rows.begin() + long(s), state_.rows.begin() + long(s + cols)));
        csv.close();
    }
    {
        dem::CsvWriter csv((out_ / "air.csv").string(), "time,stage,enclosed_volume,gas_volume,dp");
        for (std::size_t s = 0; s + kAirColumns <= state_.air.size(); s += kAirColumns)
            csv.row(std::vector<double>(state_.air.begin() + long(s), state_.air.begin() + long(s + kAirColumns)));
        csv.close();
    }
    if (def_.energy) {
        dem::CsvWriter csv((out_ / "energy.csv").string(), dem::energy_csv_header());
        for (std::size_t s = 0; s + kEnergyRowSize <= state_.energy.size(); s += kEnergyRowSize)
            csv.row(std::vector<double>(state_.energy.begin() + long(s), state_.energy.begin() + long(s + kEnergyRowSize)));
        csv.close();
    }
    const DeviceResult r = result();
    dem::JsonObject inputs;
    for (const auto& [k, v] : device_inputs(def_)) inputs.raw(k, v);
    std::vector<std::string> names;
    for (const dem::Tool& t : tools_) names.push_back(t.name);
    dem::JsonObject j;
    j.str("stage", r.stage)
        .str("object", def_.object)
        .num("holding_force", r.holding_force)
        .num("holding_time", r.holding_time)
        .num("press_force", r.press_force)
        .num("underpressure", def_.underpressure)
        .num("volume_seal", r.volume_seal)
        .num("volume_vacuum", r.volume_vacuum)
        .num("volume_change", r.volume_change)
        .num("volume_press", r.volume_press)
        .num("volume_change_vacuum", r.volume_change_vacuum)
        .boolean("fill_settled", r.fill_settled)
        .boolean("released", state_.report.count("released") > 0)
        .num("membrane_z_min", state_.report.count("membrane_z_min") ? state_.report.at("membrane_z_min") : 0.0)
        .num("fill_time", state_.report.count("fill_time") ? state_.report.at("fill_time") : 0.0)
        .num("grains", double(r.grains))
        .str("fill_mode", def_.fill_mode)
        .num("grains_placed", double(end_grain_ - first_grain_))
        .num("grains_spilled", state_.report.count("grains_spilled") ? state_.report.at("grains_spilled") : 0.0)
        .num("grains_removed_at_seal", state_.report.count("grains_removed_at_seal") ? state_.report.at("grains_removed_at_seal") : 0.0)
        .num("seal_max_overlap", state_.report.count("seal_max_overlap") ? state_.report.at("seal_max_overlap") : 0.0)
        .num("grain_volume", grain_volume_)
        .num("membrane_particles", double(r.membrane_particles))
        .num("bonds", double(r.bonds))
        .raw("tools", dem::json_string_array(names))
        .num("dt", r.dt)
        .num("steps", double(world_.steps))
        .num("time", world_.time)
        .num("samples", double(r.samples))
        .str("cycle_tool", def_.cycle_tool)
        .num("stiffness", r.cycle_stiffness.empty() ? 0.0 : r.cycle_stiffness.back())
        .num("work_per_cycle", r.cycle_work.empty() ? 0.0 : r.cycle_work.back())
        .num("peak_force", r.cycle_peak_force.empty() ? 0.0 : r.cycle_peak_force.back())
        .raw("cycle_stiffness", number_array(r.cycle_stiffness))
        .raw("cycle_work", number_array(r.cycle_work))
        .raw("cycle_peak_force", number_array(r.cycle_peak_force))
        .num("packing_seal", r.volume_seal > 0 ? grain_volume_ / r.volume_seal : 0.0)
        .num("packing_vacuum", r.volume_vacuum > 0 ? grain_volume_ / r.volume_vacuum : 0.0)
        .num("energy_residual", r.energy_residual)
        .num("energy_scale", r.energy_scale)
        .raw("warnings", dem::json_string_array(r.warnings))
        .raw("inputs", inputs.value());
    dem::write_text_atomic((out_ / "summary.json").string(), j.text());
}

}  // namespace

DeviceResult run_device(const DeviceDef& d, const DeviceOptions& o) {
    DeviceRun run(d, o);
    run.run();
    run.write_records();
    const DeviceResult r = run.result();
    if (!o.quiet)
        std::fprintf(stderr, "[device] %s: holding force %.6g N, volume change %.4g%% from the seal, %.4g%% in the vacuum stage, %.1f s\n",
                     r.stage.c_str(), r.holding_force, 100.0 * r.volume_change, 100.0 * r.volume_change_vacuum, r.run_seconds);
    return r;
}

}  // namespace vpp
