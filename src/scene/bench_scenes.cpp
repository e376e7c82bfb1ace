#include "scene/bench_scenes.h"

#include <memory>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <sys/resource.h>

#include "dem/kernels/kernels.h"
#include "dem/world/world.h"
#include "dem/batch/batch_systems.h"
#include "dem/batch/device_batch.h"
#include "dem/io/checkpoint.h"
#include "dem/io/csv.h"
#include "dem/walls/facet_sets.h"

namespace scene {

namespace {

// Materials and contact model shared by both scenes (bench README, 'Materials').
dem::Material grain_material() {
    dem::Material m;
    m.name = "grain";
    m.density = 2689.639;    // [kg/m^3]
    m.young = 2300e6;        // [Pa]
    m.stiffness_ratio = 0.5;
    m.friction = 0.6;
    m.restitution = 1.0;
    return m;
}

dem::Material foil_material() {
    dem::Material m;
    m.name = "foil";
    m.density = 151.77;      // [kg/m^3]
    m.young = 18.545e6;      // [Pa] E_s
    m.stiffness_ratio = 0.5;
    m.friction = 0.0;
    m.restitution = 1.0;
    return m;
}

void configure(dem::World& w, int threads) {
    w.params.dt = 2e-6;              // [s]
    w.params.gravity = {0, 0, -9.81};
    w.params.local_damping = 0.2;
    w.params.threads = threads;
}

struct Timing {
    double wall_s = 0;
    std::size_t contacts_start = 0, contacts_end = 0;
    uint64_t rebuilds = 0;
};

Timing run(dem::World& w, const BenchOptions& opt) {
    const long steps = opt.steps;
    const bool profile = opt.profile;
    // --state FILE: the state after the warm-up is kept in FILE (a checkpoint), so repeated
    // timings (and slow instruction-counting runs) skip the warm-up.
    if (!opt.state.empty() && std::filesystem::exists(opt.state)) {
        const int threads = w.params.threads;
        dem::load_checkpoint(opt.state, w);
        w.params.threads = threads;
    } else {
        for (long s = 0; s < opt.warmup; ++s) w.step();
        if (!opt.state.empty()) dem::save_checkpoint(opt.state, w, "bench " + opt.scene);
    }
    if (opt.energy) {
        w.params.track_energy = true;
        w.reset_energy();
    }
    w.compute_forces();  // count contacts at the start of the timed window
    Timing t;
    t.contacts_start = w.contact_count();
    const uint64_t r0 = w.rebuild_count();
    w.profile().enable(profile);
    const auto t0 = std::chrono::steady_clock::now();
    w.integrate();
    w.profile().reset();  // the timed window's first integrate() is outside the phases
    for (long s = 1; s < steps; ++s) w.step();
    t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    w.profile().enable(false);
    w.compute_forces();
    t.contacts_end = w.contact_count();
    t.rebuilds = w.rebuild_count() - r0;
    return t;
}

// Peak resident memory of the process so far [bytes].
long peak_rss_bytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return long(u.ru_maxrss) * 1024;  // Linux reports KiB
}

// The per-phase table (to stdout, before the JSON line) and its JSON object.
std::string report_profile(const dem::World& w, long steps) {
    const dem::PhaseProfile& pr = w.profile();
    const double total = pr.total();
    std::printf("%-18s %12s %10s %8s\n", "phase", "seconds", "us/step", "share");
    std::string json = "{";
    for (int k = 0; k < int(dem::Phase::kCount); ++k) {
        const auto ph = dem::Phase(k);
        const double s = pr.seconds(ph);
        std::printf("%-18s %12.4f %10.2f %7.1f%%\n", dem::phase_name(ph), s, 1e6 * s / double(steps - 1),
                    total > 0 ? 100.0 * s / total : 0.0);
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s\"%s\": %.6g", k ? ", " : "", dem::phase_name(ph), s);
        json += buf;
    }
    std::printf("%-18s %12.4f %10.2f\n", "total", total, 1e6 * total / double(steps - 1));
    return json + "}";
}

void print_result(const BenchOptions& opt, const dem::World& w, const Timing& t) {
    const double sps = double(opt.steps) / t.wall_s;
    const std::string profile = opt.profile ? ", \"profile\": " + report_profile(w, opt.steps) : "";
    std::printf(
        "{\"scene\": \"%s\", \"particles\": %zu, \"steps\": %ld, \"warmup\": %ld, \"threads\": %d, "
        "\"wall_s\": %.6g, \"steps_per_s\": %.6g, \"particle_steps_per_s\": %.6g, \"contacts\": %zu, "
        "\"contacts_start\": %zu, \"particle_contacts\": %zu, \"candidates\": %zu, \"bonds\": %zu, "
        "\"rebuilds\": %llu, \"underpressure\": %g, \"peak_rss_bytes\": %ld, \"simd\": \"%s\", \"energy\": %s, "
        "\"clumps\": %zu, \"dt\": %.6g%s}\n",
        opt.scene.c_str(), w.particles.size(), opt.steps, opt.warmup, opt.threads, t.wall_s, sps,
        sps * double(w.particles.size()), t.contacts_end, t.contacts_start, w.particle_contact_count(),
        w.candidate_count(), w.bonds().size(),
        (unsigned long long)t.rebuilds, opt.underpressure, peak_rss_bytes(),
        dem::kernels::target_name(dem::kernels::available_targets().front()).c_str(), opt.energy ? "true" : "false",
        w.clumps().size(), w.params.dt, profile.c_str());
    std::fflush(stdout);
}

// --batch B: B copies of the saved World stepped as one batch by the host backend (each copy
// its own system; `threads` share the systems). The copies stay identical, so the time is that
// of B independent systems of the same size.
void batch_of_copies(dem::World& w, const BenchOptions& opt) {
    dem::load_checkpoint(opt.state, w);
    w.params.track_energy = opt.energy;
    if (opt.energy) w.reset_energy();
    std::vector<dem::World> copies(std::size_t(opt.batch), w);
    dem::batch::BatchSystems b;
    for (dem::World& c : copies) b.add(c);
    std::unique_ptr<dem::batch::DeviceBatch> dev;
    if (opt.backend == "cuda") dev = std::make_unique<dem::batch::DeviceBatch>(dem::batch::dev::cuda_device(), opt.threads);
    if (opt.backend == "emulated") dev = std::make_unique<dem::batch::DeviceBatch>(dem::batch::dev::emulated_device(), opt.threads);
    if (opt.chunk > 0 && !dev) throw std::invalid_argument("--chunk " + std::to_string(opt.chunk) + ": chunks are the device backend's (--backend cuda or emulated)");
    const auto steps = [&](uint64_t n) {
        if (dev && opt.chunk > 0) dev->run(b, n, opt.chunk);
        else if (dev) dev->step(b, n);
        else dem::batch::step_host(b, opt.threads, n);
    };
    if (dev) dev->load(b);
    steps(1);  // untimed: the first rebuild
    const uint64_t up0 = dev ? dev->bytes_up() : 0, down0 = dev ? dev->bytes_down() : 0, calls0 = dev ? dev->exchanges() : 0;
    const double host0 = dev ? dev->host_seconds() : 0.0, device0 = dev ? dev->device_seconds() : 0.0;
    const double kernel0 = dev ? dev->kernel_seconds() : 0.0;
    double part0[4] = {0, 0, 0, 0};
    if (dev) std::copy(dev->host_part_seconds(), dev->host_part_seconds() + 4, part0);
    const uint64_t relayouts0 = dev ? dev->relayouts() : 0, waits0 = dev ? dev->waits() : 0;
    const uint64_t chunks0 = dev ? dev->chunks() : 0;
    const auto t0 = std::chrono::steady_clock::now();
    steps(uint64_t(opt.steps));
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double sps = double(opt.steps) / wall;
    const double up = dev ? double(dev->bytes_up() - up0) / double(opt.steps) : 0.0;
    const double down = dev ? double(dev->bytes_down() - down0) / double(opt.steps) : 0.0;
    const double calls = dev ? double(dev->exchanges() - calls0) / double(opt.steps) : 0.0;
    // Where a step's time goes: the host's per-system parts and the rest (copies, launches, kernels).
    const double host_us = dev ? 1e6 * (dev->host_seconds() - host0) / double(opt.steps) : 0.0;
    const double device_us = dev ? 1e6 * (dev->device_seconds() - device0) / double(opt.steps) : 0.0;
    const double kernel_us = dev ? 1e6 * (dev->kernel_seconds() - kernel0) / double(opt.steps) : 0.0;
    double part_us[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4 && dev; ++k) part_us[k] = 1e6 * (dev->host_part_seconds()[k] - part0[k]) / double(opt.steps);
    const uint64_t relayouts = dev ? dev->relayouts() - relayouts0 : 0;
    const double waits = dev ? double(dev->waits() - waits0) / double(opt.steps) : 0.0;
    std::printf("{\"scene\": \"checkpoint\", \"backend\": \"batch-%s\", \"device\": \"%s\", \"systems\": %d, "
                "\"particles\": %zu, \"steps\": %ld, \"threads\": %d, \"wall_s\": %.6g, \"steps_per_s\": %.6g, "
                "\"system_steps_per_s\": %.6g, \"bytes_up_per_step\": %.6g, \"bytes_down_per_step\": %.6g, "
                "\"exchanges_per_step\": %.6g, \"host_us_per_step\": %.6g, \"device_us_per_step\": %.6g, "
                "\"waits_per_step\": %.6g, \"kernel_us_per_step\": %.6g, \"host_parts_us_per_step\": [%.4g, %.4g, %.4g, %.4g], \"relayouts\": %llu, "
                "\"relayouts_per_1000_system_steps\": %.4g, \"chunk\": %d, \"chunks\": %llu, \"energy\": %s, \"dt\": %.6g}\n",
                opt.backend.c_str(), dev ? dev->device_name() : "host", opt.batch, w.particles.size(), opt.steps,
                opt.threads, wall, sps, sps * opt.batch, up, down, calls, host_us, device_us, waits, kernel_us, part_us[0],
                part_us[1], part_us[2], part_us[3], static_cast<unsigned long long>(relayouts),
                1000.0 * double(relayouts) / (double(opt.steps) * double(opt.batch)), opt.chunk,
                static_cast<unsigned long long>(dev ? dev->chunks() - chunks0 : 0), opt.energy ? "true" : "false", w.params.dt);
    std::fflush(stdout);
}

void grains_in_cylinder(const BenchOptions& opt) {
    dem::World w;
    configure(w, opt.threads);
    const uint32_t grain = w.add_material(grain_material());
    double top = 0;
    {
        const auto rows = dem::read_numeric_csv(opt.grains, 4);  // freed before the run
        w.reserve(rows.size());
        for (const auto& r : rows) {
            dem::SphereDef d;
            d.position = {r[0], r[1], r[2]};
            d.radius = r[3];
            d.material = grain;
            w.add_sphere(d);
            top = std::max(top, r[2] + r[3]);
        }
    }
    // As Yade's geom.facetCylinder(radius=0.0255, height=H_wall, segmentsNumber=72) and a
    // floor utils.wall(0, axis=2).
    const double h_wall = top + 0.01;  // [m]
    for (dem::Facet f : dem::make_cylinder_facets({0, 0, 0}, 0.0255, h_wall, 72, true)) {
        f.material = grain;
        w.add_facet(f);
    }
    dem::Plane floor;
    floor.point = {0, 0, 0};
    floor.normal = {0, 0, 1};
    floor.material = grain;
    w.add_plane(floor);
    // Yade's default Verlet distance: half the smallest radius.
    const Timing t = run(w, opt);
    print_result(opt, w, t);
}

void foil_plus_grains(const BenchOptions& opt) {
    namespace fs = std::filesystem;
    const fs::path dir(opt.scene_dir);
    dem::World w;
    configure(w, opt.threads);
    const uint32_t grain = w.add_material(grain_material());
    const uint32_t foil = w.add_material(foil_material());
    // Masks: bit 0 = grains and foil meet each other; bit 1 = grains and caps. Caps never
    // touch the foil (Yade: body masks).
    constexpr uint32_t kGrainMask = 0b11, kFoilMask = 0b01, kCapMask = 0b10;
    const auto nodes = dem::read_numeric_csv((dir / "foil_nodes.csv").string(), 8);
    double ztop = 0;
    for (const auto& r : nodes) {
        dem::SphereDef d;
        d.position = {r[0], r[1], r[2]};
        d.radius = r[3];
        d.material = foil;
        d.mask = kFoilMask;
        if (r[5] != 0.0) d.flags |= dem::kFixed;
        w.add_sphere(d);
        ztop = std::max(ztop, r[2]);
    }
    const double r_f = nodes.at(0)[3];
    const double kn_bond = foil_material().young * r_f;  // Yade sphere convention (bench README)
    for (const auto& r : dem::read_numeric_csv((dir / "foil_bonds.csv").string(), 2))
        w.add_bond(uint32_t(r[0]), uint32_t(r[1]), kn_bond, 0.5 * kn_bond);
    for (const auto& r : dem::read_numeric_csv((dir / "foil_grains_1010.csv").string(), 4)) {
        dem::SphereDef d;
        d.position = {r[0], r[1], r[2]};
        d.radius = r[3];
        d.material = grain;
        d.mask = kGrainMask;
        w.add_sphere(d);
    }
    for (double z : {0.0, ztop}) {
        dem::Plane cap;
        cap.point = {0, 0, z};
        cap.normal = {0, 0, 1};
        cap.material = grain;
        cap.mask = kCapMask;
        w.add_plane(cap);
    }
    if (opt.underpressure != 0.0) {
        for (const auto& r : dem::read_numeric_csv((dir / "foil_pressure.csv").string(), 5))
            w.pressure.nodes.push_back({uint32_t(r[0]), {uint32_t(r[1]), uint32_t(r[2]), uint32_t(r[3]), uint32_t(r[4])}});
        w.pressure.dp = opt.underpressure;
    }
    const Timing t = run(w, opt);
    print_result(opt, w, t);
}

}  // namespace

void run_bench(const BenchOptions& opt) {
    if (opt.steps < 1) throw std::invalid_argument("--steps must be >= 1");
    if (opt.warmup < 0) throw std::invalid_argument("--warmup must be >= 0");
    if (opt.threads < 1) throw std::invalid_argument("--threads must be >= 1");
    if (!opt.simd.empty()) {
        std::string names;
        for (int64_t t : dem::kernels::available_targets()) {
            if (dem::kernels::target_name(t) == opt.simd) {
                dem::kernels::restrict_to_target(t);
                names.clear();
                break;
            }
            names += (names.empty() ? "" : ", ") + dem::kernels::target_name(t);
        }
        if (!names.empty())
            throw std::invalid_argument("--simd '" + opt.simd + "' is not available here (allowed: " + names + ")");
    }
    if (opt.scene == "grains-in-cylinder") {
        if (opt.grains.empty()) throw std::invalid_argument("grains-in-cylinder needs --grains FILE");
        grains_in_cylinder(opt);
    } else if (opt.scene == "foil-plus-grains") {
        if (opt.scene_dir.empty()) throw std::invalid_argument("foil-plus-grains needs --scene-dir DIR");
        foil_plus_grains(opt);
    } else if (opt.scene == "checkpoint") {
        // Any saved World (a damper's run.ckpt or prepared.ckpt, a scene's): its steps timed
        // as it stands, e.g. the cost per step of grain shapes (bench/grain_shapes.sh).
        if (opt.state.empty() || !std::filesystem::exists(opt.state))
            throw std::invalid_argument("checkpoint needs --state FILE, an existing checkpoint");
        dem::World w;
        w.params.threads = opt.threads;
        if (opt.batch > 0) {
            batch_of_copies(w, opt);
            return;
        }
        const Timing t = run(w, opt);
        print_result(opt, w, t);
    } else {
        throw std::invalid_argument("unknown bench scene '" + opt.scene +
                                    "' (allowed: grains-in-cylinder, foil-plus-grains, checkpoint)");
    }
}

}  // namespace scene
