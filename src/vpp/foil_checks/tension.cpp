#include "vpp/foil_checks/tension.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "scene/progress.h"
#include "dem/io/csv.h"
#include "dem/io/json.h"

namespace vpp {

TensionResult run_tension(const Config& c, const std::string& out_dir, bool quiet) {
    dem::World w;
    w.params.gravity = {0, 0, 0};  // a strip test on a table: no weight
    w.params.local_damping = c.simulation.local_damping;
    w.params.threads = c.simulation.threads;
    w.params.skin = c.simulation.skin;
    const int rows = int(c.tension.sites_across), cols = int(c.tension.sites_along);
    FoilLattice L = build_strip(w, c.foil, rows, cols);
    const double h = L.spacing;

    // First column fixed, last column pulled along +x at constant speed.
    for (uint32_t i : L.column(0)) w.set_fixed(i);
    dem::Motion pull;
    pull.velocity = {c.tension.speed, 0.0, 0.0};
    const uint32_t m = w.add_motion(pull);
    const std::vector<uint32_t> grip = L.column(cols - 1);
    for (uint32_t i : grip) w.set_prescribed(i, m);

    TensionResult r;
    r.length = (cols - 1) * h;
    r.width = rows * h;  // each site row stands for 2 r_f of width
    r.target_modulus = c.foil.young;
    r.particle_modulus = particle_modulus(c.foil);
    r.particles = L.particles.size();
    r.bonds = w.bonds().size();
    w.params.dt = resolve_dt(c.simulation, w);
    r.dt = w.params.dt;

    const double pull_time = c.tension.strain * r.length / c.tension.speed;
    const uint64_t pull_steps = uint64_t(std::ceil(pull_time / r.dt));
    const uint64_t rows_out = 200;
    const uint64_t every = std::max<uint64_t>(1, pull_steps / rows_out);

    std::unique_ptr<dem::CsvWriter> csv;
    if (!out_dir.empty()) csv = std::make_unique<dem::CsvWriter>((std::filesystem::path(out_dir) / "tension.csv").string(), "strain,force");
    // Least-squares slope over the last 80% of the pull (the first part carries the start-up
    // transient of a suddenly moved grip).
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    scene::Progress progress("tension", pull_steps, quiet);
    auto grip_force = [&] {
        double f = 0;  // force the strip exerts on the grip is along -x; tension positive
        for (uint32_t i : grip) f -= w.particles.force[i].x;
        return f;
    };
    for (uint64_t s = 0; s <= pull_steps; ++s) {
        w.compute_forces();
        const double strain = (w.particles.pos[grip[0]].x - (cols - 1) * h) / r.length;
        if (s % every == 0 || s == pull_steps) {
            const double f = grip_force();
            if (csv) csv->row({strain, f});
            if (strain >= 0.2 * c.tension.strain) {
                sx += strain; sy += f; sxx += strain * strain; sxy += strain * f; n += 1;
            }
        }
        if (s == pull_steps) break;
        w.integrate();
        progress.update(s + 1, w.time);
    }
    r.steps = pull_steps;
    r.stiffness = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    r.effective_modulus = r.stiffness / (c.foil.thickness * r.width);
    if (csv) csv->close();

    if (!out_dir.empty()) {
        dem::JsonObject j;
        j.num("effective_modulus", r.effective_modulus)
            .num("target_modulus", r.target_modulus)
            .num("particle_modulus", r.particle_modulus)
            .num("relative_error", r.effective_modulus / r.target_modulus - 1.0)
            .num("stiffness_N", r.stiffness)
            .num("bond_kn", bond_normal_stiffness(c.foil))
            .num("width", r.width)
            .num("length", r.length)
            .num("thickness", c.foil.thickness)
            .num("particle_radius", c.foil.particle_radius)
            .num("sites_along", double(cols))
            .num("sites_across", double(rows))
            .num("particles", double(r.particles))
            .num("bonds", double(r.bonds))
            .num("strain", c.tension.strain)
            .num("speed", c.tension.speed)
            .num("dt", r.dt)
            .num("steps", double(r.steps));
        dem::write_text_atomic((std::filesystem::path(out_dir) / "summary.json").string(), j.text());
    }
    if (!quiet)
        std::fprintf(stderr,
                     "tension: %zu particles, %zu bonds, w = %.4g m, L = %.4g m; E_s = %.5g Pa\n"
                     "  effective modulus %.5g Pa vs target %.5g Pa (%+.2f%%)\n",
                     r.particles, r.bonds, r.width, r.length, r.particle_modulus, r.effective_modulus,
                     r.target_modulus, 100.0 * (r.effective_modulus / r.target_modulus - 1.0));
    return r;
}

}  // namespace vpp
