#include "vpp/foil_checks/envelope.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "scene/progress.h"
#include "dem/io/csv.h"
#include "dem/io/json.h"
#include "dem/io/vtk.h"

namespace vpp {

namespace fs = std::filesystem;

EnvelopeResult run_envelope(const Config& c, const std::string& out_dir, bool quiet) {
    dem::World w;
    w.params.gravity = {0, 0, -9.81};
    w.params.local_damping = c.simulation.local_damping;
    w.params.threads = c.simulation.threads;
    w.params.skin = c.simulation.skin;
    FoilLattice L = build_cylinder(w, c.foil, c.damper.radius, c.damper.height, 0.0, c.damper.foil_exact_radius);
    for (int k : {0, L.rows - 1})
        for (uint32_t i : L.row(k)) w.set_fixed(i);
    w.pressure.nodes = cylinder_pressure_nodes(L);
    w.params.dt = resolve_dt(c.simulation, w);

    EnvelopeResult r;
    r.radius = L.radius;
    r.columns = L.cols;
    r.rows = L.rows;
    r.particles = L.particles.size();
    r.bonds = w.bonds().size();
    r.pressure_nodes = w.pressure.nodes.size();
    r.dt = w.params.dt;
    r.initial_volume = enclosed_volume(L, w.particles.pos);

    const double dp = c.process.underpressure, ramp = c.process.ramp_time;
    const double duration = ramp + c.process.hold_time;
    r.steps = uint64_t(std::ceil(duration / r.dt));
    const double out_dt = c.output.interval > 0 ? c.output.interval : duration / 400.0;
    const double vtk_dt = c.output.vtk_interval > 0 ? c.output.vtk_interval : duration / 20.0;
    if (!quiet)
        std::fprintf(stderr,
                     "envelope: %d columns (radius %.5g m, requested %.5g m), %d rows, %zu particles, %zu bonds, "
                     "%zu loaded nodes; dp -> %.4g Pa over %.4g s, held %.4g s; dt = %.4g s, %llu steps\n",
                     L.cols, L.radius, c.damper.radius, L.rows, r.particles, r.bonds, r.pressure_nodes, dp, ramp,
                     c.process.hold_time, r.dt, (unsigned long long)r.steps);

    std::unique_ptr<dem::CsvWriter> csv;
    if (!out_dir.empty()) {
        csv = std::make_unique<dem::CsvWriter>((fs::path(out_dir) / "envelope.csv").string(),
                                               "time,dp,volume,kinetic_energy,min_gap");
        fs::create_directories(fs::path(out_dir) / "vtk");
    }
    r.min_gap = min_nonbonded_gap(L, w);
    uint64_t next_out = 0, next_vtk = 0, frame = 0;
    const double eps = 0.5 * r.dt;
    scene::Progress progress("envelope", r.steps, quiet);
    for (uint64_t s = 0; s <= r.steps; ++s) {
        w.pressure.dp = dp * std::min(1.0, w.time / ramp);
        w.compute_forces();
        const double t = w.time;
        if (t + eps >= next_out * out_dt) {
            const double gap = min_nonbonded_gap(L, w);
            r.min_gap = std::min(r.min_gap, gap);
            const dem::KineticEnergy e = dem::kinetic_energy(w.particles, L.particles);
            const double ke = e.total();
            r.peak_kinetic_energy = std::max(r.peak_kinetic_energy, ke);
            r.peak_translational_energy = std::max(r.peak_translational_energy, e.translation);
            if (csv) csv->row({t, w.pressure.dp, enclosed_volume(L, w.particles.pos), ke, gap});
            while (t + eps >= next_out * out_dt) ++next_out;
        }
        if (!out_dir.empty() && t + eps >= next_vtk * vtk_dt) {
            char name[64];
            std::snprintf(name, sizeof name, "foil_%04llu.vtk", (unsigned long long)frame++);
            dem::write_particles_vtk((fs::path(out_dir) / "vtk" / name).string(), w, true);
            while (t + eps >= next_vtk * vtk_dt) ++next_vtk;
        }
        if (s == r.steps) break;
        w.integrate();
        progress.update(s + 1, w.time);
    }
    r.final_volume_ratio = enclosed_volume(L, w.particles.pos) / r.initial_volume;
    const dem::KineticEnergy e = dem::kinetic_energy(w.particles, L.particles);
    r.final_kinetic_energy = e.total();
    r.final_translational_energy = e.translation;
    for (uint32_t i : L.particles)
        r.max_radial_excursion = std::max(r.max_radial_excursion, std::hypot(w.particles.pos[i].x, w.particles.pos[i].y));
    if (csv) csv->close();

    if (!out_dir.empty()) {
        dem::JsonObject j;
        j.num("final_volume_ratio", r.final_volume_ratio)
            .num("min_gap", r.min_gap)
            .num("underpressure", dp)
            .num("radius", r.radius)
            .num("requested_radius", c.damper.radius)
            .num("height", (L.rows - 1) * L.spacing)
            .num("columns", L.cols)
            .num("rows", L.rows)
            .num("particles", double(r.particles))
            .num("bonds", double(r.bonds))
            .num("pressure_nodes", double(r.pressure_nodes))
            .num("particle_modulus", particle_modulus(c.foil))
            .num("bond_kn", bond_normal_stiffness(c.foil))
            .num("initial_volume", r.initial_volume)
            .num("final_kinetic_energy", r.final_kinetic_energy)
            .num("peak_kinetic_energy", r.peak_kinetic_energy)
            .num("final_translational_kinetic_energy", r.final_translational_energy)
            .num("final_rotational_kinetic_energy", r.final_kinetic_energy - r.final_translational_energy)
            .num("peak_translational_kinetic_energy", r.peak_translational_energy)
            .num("max_radial_excursion", r.max_radial_excursion)
            .num("dt", r.dt)
            .num("steps", double(r.steps));
        dem::write_text_atomic((fs::path(out_dir) / "summary.json").string(), j.text());
    }
    if (!quiet)
        std::fprintf(stderr,
                     "envelope: final volume ratio %.4f, min gap %.3f r_f, kinetic energy %.3g J (peak %.3g J), "
                     "of which translational %.3g J (peak %.3g J)\n",
                     r.final_volume_ratio, r.min_gap, r.final_kinetic_energy, r.peak_kinetic_energy,
                     r.final_translational_energy, r.peak_translational_energy);
    return r;
}

}  // namespace vpp
