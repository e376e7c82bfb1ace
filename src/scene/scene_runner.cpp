#include "scene/scene_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>

#include "scene/build_info.h"
#include "scene/clump_template.h"
#include "scene/config.h"
#include "scene/initial_overlaps.h"
#include "scene/progress.h"
#include "scene/scene_settings.h"
#include "scene/shared_keys.h"
#include "scene/time_step.h"
#include "dem/io/csv.h"
#include "dem/io/energy_columns.h"
#include "dem/io/json.h"
#include "dem/io/vtk.h"
#include "dem/walls/facet_sets.h"

namespace scene {

namespace fs = std::filesystem;
using cfg::ConfigError;
using cfg::Section;
using dem::Vec3;

namespace {

uint32_t material_index(SceneSection& s, const std::map<std::string, uint32_t>& by_name) {
    const std::string m = s.string("material");
    auto it = by_name.find(m);
    if (it == by_name.end()) {
        std::string known;
        for (const auto& [k, v] : by_name) known += (known.empty() ? "" : ", ") + k;
        s.fail("material", "unknown material (defined: " + (known.empty() ? std::string("none") : known) + ")");
    }
    return it->second;
}

uint32_t read_mask(SceneSection& s) { return uint32_t(s.integer("mask")); }

// velocity = [..] or displacement = [[t, dx, dy, dz], ...] (piecewise linear, t increasing).
dem::Motion read_motion(SceneSection& s) {
    dem::Motion m;
    m.velocity = s.vec3("velocity");
    if (const toml::node* n = s.node("displacement")) {
        if (s.has("velocity")) s.fail("displacement", "give either velocity or displacement, not both");
        const toml::array* a = n->as_array();
        if (!a || a->empty()) s.fail("displacement", "must be an array of [time, dx, dy, dz] rows");
        for (const auto& row : *a) {
            const toml::array* r = row.as_array();
            if (!r || r->size() != 4) s.fail("displacement", "each row must be [time, dx, dy, dz]");
            double v[4];
            for (int k = 0; k < 4; ++k) {
                auto x = r->get(k)->value<double>();
                if (!x) s.fail("displacement", "each row must hold 4 numbers");
                if (!std::isfinite(*x)) s.fail("displacement", "each row must hold 4 finite numbers");
                v[k] = *x;
            }
            if (!m.history.empty() && !(v[0] > m.history.back().time))
                s.fail("displacement", "times must increase strictly");
            m.history.push_back({v[0], {v[1], v[2], v[3]}});
        }
    }
    return m;
}

// The entries of an array of tables, each read through the table's rows for `key[]`.
std::vector<SceneSection> entries(Section& top, const std::string& key) {
    std::vector<SceneSection> out;
    for (Section& s : top.array_of_tables(key)) out.emplace_back(std::move(s), key + "[]");
    return out;
}

fs::path resolve(const std::string& base, const std::string& p) {
    fs::path q(p);
    return q.is_absolute() ? q : fs::path(base) / q;
}

// Name of World wall `wall` (planes, then facets) by its output wall.
std::string wall_name(const Scene& sc, uint32_t wall) {
    for (std::size_t k = 0; k < sc.wall_members.size(); ++k) {
        const auto& m = sc.wall_members[k];
        const auto it = std::find(m.begin(), m.end(), wall);
        if (it == m.end()) continue;
        if (m.size() == 1) return sc.wall_names[k];
        return sc.wall_names[k] + " triangle " + std::to_string(it - m.begin());
    }
    return "wall " + std::to_string(wall);
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// Refuses spheres that start inside each other or a wall (scene/initial_overlaps.h).
void check_initial_overlaps(const Scene& sc, double tolerance) {
    const OverlapReport ss = sphere_overlaps(sc.world, tolerance), sw = wall_overlaps(sc.world, tolerance);
    if (ss.count == 0 && sw.count == 0) return;
    const bool pair = ss.count > 0 && (sw.count == 0 || ss.worst.fraction >= sw.worst.fraction);
    const Overlap& o = pair ? ss.worst : sw.worst;
    const std::string other = o.wall ? wall_name(sc, o.b) : sphere_name(sc, o.b);
    std::string msg = "initial overlap: " + sphere_name(sc, o.a) + " and " + other + " overlap by " + number(o.overlap) +
                      " m (" + number(100.0 * o.fraction) + "% of " + (o.wall ? "its" : "the smaller") +
                      " radius; simulation.max_initial_overlap = " + number(tolerance) + " allows " +
                      number(100.0 * tolerance) + "%)";
    const std::size_t n = ss.count + sw.count;
    if (n > 1)
        msg += "; " + std::to_string(n) + " overlapping pairs in all (" + std::to_string(ss.count) +
               " sphere-sphere, " + std::to_string(sw.count) + " sphere-wall)";
    throw ConfigError(msg + ": an overlap starts as a contact force kn * overlap that throws the spheres out; move "
                            "them apart, or raise simulation.max_initial_overlap to start them so on purpose");
}

// The scene's parts, each from its array of tables in the order build_scene reads them; every key
// through the scene's settings table (scene/scene_settings.cpp): its default, its check.
using Materials = std::map<std::string, uint32_t>;  // the World's material index by name

// [[materials]]
Materials add_materials(Section& top, dem::World& w) {
    Materials by_name;
    for (SceneSection m : entries(top, "materials")) {
        dem::Material mat;
        mat.name = m.string("name");
        if (by_name.count(mat.name)) m.fail("name", "duplicate material name");
        mat.density = m.real("density");
        mat.young = m.real("young");
        mat.stiffness_ratio = m.real("stiffness_ratio");
        mat.friction = m.real("friction");
        mat.restitution = m.real("restitution");
        m.finish();
        by_name[mat.name] = w.add_material(mat);
    }
    return by_name;
}

// [[spheres]]: one sphere each, free, fixed or prescribed.
void add_spheres(Section& top, const Materials& by_name, Scene& sc) {
    dem::World& w = sc.world;
    for (SceneSection s : entries(top, "spheres")) {
        dem::SphereDef d;
        d.material = material_index(s, by_name);
        d.radius = s.real("radius");
        d.position = s.vec3("position");
        d.velocity = s.vec3("velocity");
        d.angular_velocity = s.vec3("angular_velocity");
        d.mask = read_mask(s);
        if (s.flag("fixed")) d.flags |= dem::kFixed;
        // Prescribed motion: `prescribed = true` keeps `velocity` constant whatever the forces;
        // a `displacement` history [[t, dx, dy, dz], ...] moves the sphere along it instead.
        const bool prescribed = s.flag("prescribed") || s.has("displacement");
        std::optional<dem::Motion> motion;
        if (prescribed) {
            if (d.flags & dem::kFixed) s.fail("prescribed", "a sphere cannot be both fixed and prescribed");
            motion = read_motion(s);
        }
        const bool track = s.flag("track");
        s.finish();
        const uint32_t id = w.add_sphere(d);
        if (motion) w.set_prescribed(id, w.add_motion(*motion));
        if (track) sc.tracked.push_back(id);
        sc.sphere_origin.push_back({-1, uint32_t(sc.sphere_origin.size())});
    }
}

// [[sphere_files]]: a sphere per row (x, y, z, r) of a CSV file.
void add_sphere_files(Section& top, const Materials& by_name, const std::string& base_dir, Scene& sc) {
    dem::World& w = sc.world;
    int32_t file_index = 0;
    for (SceneSection s : entries(top, "sphere_files")) {
        const fs::path path = resolve(base_dir, s.string("path"));
        dem::SphereDef d;
        d.material = material_index(s, by_name);
        d.velocity = s.vec3("velocity");
        d.mask = read_mask(s);
        if (s.flag("fixed")) d.flags |= dem::kFixed;
        const bool track = s.flag("track");
        s.finish();
        std::vector<std::vector<double>> rows;
        try {
            rows = dem::read_numeric_csv(path.string(), 4);
        } catch (const std::exception& e) {
            s.fail("path", e.what());
        }
        for (std::size_t k = 0; k < rows.size(); ++k) {
            d.position = {rows[k][0], rows[k][1], rows[k][2]};
            d.radius = rows[k][3];
            for (int c = 0; c < 4; ++c)
                if (!std::isfinite(rows[k][std::size_t(c)]))
                    s.fail("path", "row " + std::to_string(k + 1) + " of '" + path.string() + "' holds " +
                                       std::to_string(rows[k][std::size_t(c)]) + " in column " + "xyzr"[c] +
                                       ": must be a finite number");
            if (!(d.radius > 0.0))
                s.fail("path", "row " + std::to_string(k + 1) + " of '" + path.string() + "' has radius <= 0");
            const uint32_t id = w.add_sphere(d);
            if (track) sc.tracked.push_back(id);
            sc.sphere_origin.push_back({file_index, uint32_t(k)});
        }
        sc.sphere_file_paths.push_back(path.string());
        ++file_index;
    }
}

// [[clumps]]: a rigid clump each, of a built-in shape or a template file.
void add_clumps(Section& top, const Materials& by_name, const std::string& base_dir, Scene& sc) {
    dem::World& w = sc.world;
    uint32_t clump_entry = 0;
    for (SceneSection s : entries(top, "clumps")) {
        dem::ClumpDef d;
        d.material = material_index(s, by_name);
        const std::string shape = s.string("shape");
        std::optional<double> radius;
        if (s.has("radius")) radius = s.real("radius");
        dem::ClumpShape cs;
        try {
            if (shape == "template") {
                if (!s.has("template")) s.fail("template", "is required with shape = \"template\"");
                const fs::path path = resolve(base_dir, s.string("template"));
                try {
                    cs = read_clump_template(path.string());
                } catch (const std::exception& e) {
                    s.fail("template", e.what());
                }
                if (radius) cs = dem::scaled_to_radius(cs, *radius);
            } else {
                if (s.has("template")) s.fail("template", "is only read with shape = \"template\"");
                if (!radius) s.fail("radius", "is required with a built-in shape (the volume-equivalent radius)");
                cs = dem::builtin_clump_shape(shape, *radius);
            }
        } catch (const std::invalid_argument& e) {
            s.fail(shape == "template" ? "template" : "shape", e.what());
        }
        d.position = s.vec3("position");
        const dem::Vec3 rot = s.vec3("orientation");
        const double angle = norm(rot);
        if (angle > 0.0) {
            const dem::Vec3 u = rot / angle;
            const double sh = std::sin(0.5 * angle);
            d.orientation = {std::cos(0.5 * angle), u.x * sh, u.y * sh, u.z * sh};
        }
        d.velocity = s.vec3("velocity");
        d.angular_velocity = s.vec3("angular_velocity");
        d.mask = read_mask(s);
        s.finish();
        w.add_clump(cs, d);
        for (std::size_t m = 0; m < cs.members.size(); ++m) sc.sphere_origin.push_back({-2, clump_entry});
        ++clump_entry;
    }
}

// [[planes]]
void add_planes(Section& top, const Materials& by_name, Scene& sc) {
    dem::World& w = sc.world;
    for (SceneSection s : entries(top, "planes")) {
        dem::Plane p;
        p.material = material_index(s, by_name);
        p.point = s.vec3("point");
        p.normal = s.vec3("normal");
        if (dem::norm(p.normal) == 0.0) s.fail("normal", s.row("normal").limits.allowed);
        p.one_sided = s.flag("one_sided");
        p.mask = read_mask(s);
        p.motion = read_motion(s);
        s.finish();
        sc.wall_members.push_back({uint32_t(w.add_plane(p))});
        sc.wall_names.push_back(s.path());
    }
}

// [[facets]]: one triangle each, after every plane (the World numbers walls planes first).
void add_facets(Section& top, const Materials& by_name, Scene& sc) {
    dem::World& w = sc.world;
    const uint32_t nplanes = uint32_t(w.planes.size());
    for (SceneSection s : entries(top, "facets")) {
        dem::Facet f;
        f.material = material_index(s, by_name);
        const toml::node* n = s.node("vertices");
        const toml::array* a = n->as_array();
        if (!a || a->size() != 3) s.fail("vertices", "must be 3 points [[x,y,z],[x,y,z],[x,y,z]]");
        for (int v = 0; v < 3; ++v) {
            const toml::array* r = a->get(v)->as_array();
            if (!r || r->size() != 3) s.fail("vertices", "must be 3 points [[x,y,z],[x,y,z],[x,y,z]]");
            for (int k = 0; k < 3; ++k) {
                auto x = r->get(k)->value<double>();
                if (!x) s.fail("vertices", "coordinates must be numbers");
                if (!std::isfinite(*x)) s.fail("vertices", "coordinates must be finite numbers");
                f.vertices[v][k] = *x;
            }
        }
        if (dem::norm(dem::cross(f.vertices[1] - f.vertices[0], f.vertices[2] - f.vertices[0])) == 0.0)
            s.fail("vertices", "the triangle has zero area");
        f.one_sided = s.flag("one_sided");
        f.mask = read_mask(s);
        f.motion = read_motion(s);
        s.finish();
        sc.wall_members.push_back({nplanes + w.add_facet(f)});
        sc.wall_names.push_back(s.path());
    }
}

// [[facet_sets]]: triangles made (cylinder, funnel) or read (STL), one output wall each.
void add_facet_sets(Section& top, const Materials& by_name, const std::string& base_dir, Scene& sc) {
    dem::World& w = sc.world;
    const uint32_t nplanes = uint32_t(w.planes.size());
    for (SceneSection s : entries(top, "facet_sets")) {
        const std::string type = s.string("type");
        std::vector<dem::Facet> fs;
        try {
            // Arguments in the order of the calls' parameters (function arguments have no
            // order of evaluation, and a message should name the first bad key).
            if (type == "cylinder") {
                const Vec3 base = s.vec3("base");
                const double radius = s.real("radius"), height = s.real("height");
                const int segments = int(s.integer("segments"));
                fs = dem::make_cylinder_facets(base, radius, height, segments, s.flag("inward"));
            } else if (type == "funnel") {
                const Vec3 base = s.vec3("base");
                const double bottom = s.real("bottom_radius"), top_r = s.real("top_radius");
                const double height = s.real("height");
                const int segments = int(s.integer("segments"));
                fs = dem::make_funnel_facets(base, bottom, top_r, height, segments, s.flag("inward"));
            } else if (type == "stl") {
                const std::string path = resolve(base_dir, s.string("path")).string();
                fs = dem::read_stl(path, s.real("scale"));
            } else {
                s.fail("type", s.row("type").limits.allowed);
            }
        } catch (const std::invalid_argument& e) {
            s.fail("type", e.what());
        } catch (const std::runtime_error& e) {
            if (dynamic_cast<const ConfigError*>(&e)) throw;
            s.fail("path", e.what());
        }
        const uint32_t material = material_index(s, by_name);
        const bool one_sided = s.flag("one_sided");
        const uint32_t mask = read_mask(s);
        const dem::Motion motion = read_motion(s);
        s.finish();
        std::vector<uint32_t> members;
        for (dem::Facet f : fs) {
            f.material = material;
            f.one_sided = one_sided;
            f.mask = mask;
            f.motion = motion;
            members.push_back(nplanes + w.add_facet(f));
        }
        sc.wall_members.push_back(members);
        sc.wall_names.push_back(s.path());
    }
}

}  // namespace

std::string sphere_name(const Scene& sc, uint32_t id) {
    if (id >= sc.sphere_origin.size()) return "sphere " + std::to_string(id);
    const auto [file, k] = sc.sphere_origin[id];
    if (file == -2) return "a member of clumps[" + std::to_string(k) + "]";
    if (file < 0) return "spheres[" + std::to_string(k) + "]";
    return "sphere_files[" + std::to_string(file) + "] row " + std::to_string(k + 1) + " of '" +
           sc.sphere_file_paths[std::size_t(file)] + "'";
}

Scene build_scene(const toml::table& root, const std::string& base_dir) {
    Scene sc;
    dem::World& w = sc.world;
    Section top(&root, "");

    // Every key through the scene's settings table (scene/scene_settings.cpp): its default, its check.
    SceneSection sim(top.table("simulation"), "simulation");
    sim.record_into(&sc.inputs);
    const TimeStep step = read_dt(sim.section(), "dt", sim.row("dt").def);
    sc.dt_auto = step.automatic;
    if (!step.automatic) w.params.dt = step.dt;
    sim.record("dt", sc.dt_auto ? "\"auto\"" : dem::json_double(w.params.dt));
    sc.dt_safety = sim.real("dt_safety");
    sc.duration = sim.real("duration");
    w.params.gravity = sim.vec3("gravity");
    w.params.local_damping = sim.real("local_damping");
    w.params.threads = cfg::read_threads(sim.section(), "threads", int64_t(sim.row("threads").def));
    sim.record("threads", std::to_string(w.params.threads));
    sc.output_interval = sim.real("output_interval");
    w.params.skin = sim.real("skin");
    // [-] of the smaller radius; a packing written to a few digits touches by a little.
    const double max_overlap = sim.real("max_initial_overlap");
    sim.finish();

    SceneSection out(top.table("output"), "output");
    out.record_into(&sc.inputs);
    sc.vtk_interval = out.real("vtk_interval");
    // energy.csv: the World keeps its energy ledger (docs/energy.md).
    w.params.track_energy = out.flag("energy");
    out.finish();

    const Materials by_name = add_materials(top, w);
    add_spheres(top, by_name, sc);
    add_sphere_files(top, by_name, base_dir, sc);
    add_clumps(top, by_name, base_dir, sc);
    add_planes(top, by_name, sc);
    add_facets(top, by_name, sc);
    add_facet_sets(top, by_name, base_dir, sc);
    top.finish();
    if (w.particles.size() == 0) throw ConfigError("the scene has no spheres: add [[spheres]], [[sphere_files]] or [[clumps]]");
    check_initial_overlaps(sc, max_overlap);

    if (sc.dt_auto) {
        w.params.dt = time_step({.automatic = true, .safety = sc.dt_safety}, w);
        if (!std::isfinite(w.params.dt))  // no free sphere: nothing sets a critical step
            sim.fail("dt", "\"auto\" needs at least one sphere that is not fixed; give dt in seconds");
    }
    return sc;
}

void require_output_path(const std::string& dir, const std::string& what) {
    if (dir.find_first_not_of(" \t\r\n") != std::string::npos) return;
    throw ConfigError(what + " '" + dir + "': an empty or blank output folder is refused (it would be the current "
                      "folder, whose files the run would replace); give a folder's path, e.g. out/run1");
}

dem::FolderLock lock_output_dir(const std::string& dir) {
    require_output_path(dir, "--out");
    if (fs::exists(dir) && !fs::is_directory(dir)) throw ConfigError("--out '" + dir + "' exists and is not a directory");
    fs::create_directories(dir);
    dem::FolderLock lock(dir);
    if (!lock.warning().empty()) std::fprintf(stderr, "WARNING: %s\n", lock.warning().c_str());
    return lock;
}

std::string resume_checkpoint(const std::string& out_dir, const std::string& from, bool overwrite) {
    if (!from.empty() || overwrite || out_dir.empty()) return from;
    const fs::path own = fs::path(out_dir) / "run.ckpt";
    return fs::exists(own) ? own.string() : std::string();
}

dem::FolderLock prepare_output_dir(const std::string& dir, bool overwrite) {
    dem::FolderLock lock = lock_output_dir(dir);
    if (!overwrite)
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().filename() != dem::FolderLock::kFileName)
                throw ConfigError("--out '" + dir + "' exists and is not empty; pass --overwrite to replace its files");
    record_build(dir, true);  // a new run: this build made it
    return lock;
}

void run_scene(Scene& sc, const RunOptions& opt) {
    dem::World& w = sc.world;
    const dem::FolderLock lock = prepare_output_dir(opt.out_dir, opt.overwrite);
    const fs::path out(opt.out_dir);
    if (opt.overwrite && fs::is_directory(out / "vtk")) {  // no stale frames of an earlier run
        std::vector<fs::path> stale;
        for (const auto& e : fs::directory_iterator(out / "vtk")) {
            const std::string n = e.path().filename().string();
            if (e.is_regular_file() && e.path().extension() == ".vtk" &&
                (n.starts_with("particles_") || n.starts_with("walls_")))
                stale.push_back(e.path());
        }
        for (const auto& f : stale) fs::remove(f);
    }
    const double dt = w.params.dt;
    const uint64_t nsteps = uint64_t(std::llround(sc.duration / dt));
    if (!opt.quiet)
        std::fprintf(stderr, "scene: %zu spheres, %zu planes, %zu facets; dt = %.4g s%s (critical %.4g s); %llu steps\n",
                     w.particles.size(), w.planes.size(), w.facets.size(), dt,
                     sc.dt_auto ? " (auto)" : "", w.critical_dt(), (unsigned long long)nsteps);

    dem::CsvWriter tracked((out / "tracked.csv").string(), "time,id,x,y,z,vx,vy,vz,wx,wy,wz");
    dem::CsvWriter walls((out / "walls.csv").string(), "time,wall,fx,fy,fz,tx,ty,tz");
    // energy.csv (only with [output] energy = true): the ledger from t = 0 at the output times.
    const bool energy = w.params.track_energy;
    dem::CsvWriter energy_csv;
    if (energy) {
        energy_csv.open((out / "energy.csv").string(), dem::energy_csv_header());
        w.reset_energy();
    }
    auto energy_row = [&] {
        std::vector<double> row(dem::kEnergyColumns.size());
        dem::energy_csv_row(w.energy(), w.energy().time, row.data());
        energy_csv.row(row);
    };
    if (sc.vtk_interval > 0.0) fs::create_directories(out / "vtk");

    // Output times are multiples of the interval; a step records when it first reaches one.
    uint64_t next_out = 0, next_vtk = 0, vtk_frame = 0;
    const double eps = 0.5 * dt;
    // Any interval up to dt records every step, so a tiny one is clamped (same rows) and the
    // counters jump straight past t: no loop over a huge number of multiples.
    const double out_iv = std::max(sc.output_interval, 1e-3 * dt);
    const double vtk_iv = std::max(sc.vtk_interval, 1e-3 * dt);
    Progress progress("scene", nsteps, opt.quiet);
    const auto t0 = std::chrono::steady_clock::now();
    for (uint64_t s = 0; s <= nsteps; ++s) {
        w.compute_forces();
        const double t = w.time;
        bool output_row = false;
        if (t + eps >= double(next_out) * out_iv) {
            output_row = true;
            for (uint32_t id : sc.tracked) {
                const Vec3 x = w.particles.pos[id], v = w.velocity_at_time(id), om = w.angular_velocity_at_time(id);
                tracked.row({t, double(id), x.x, x.y, x.z, v.x, v.y, v.z, om.x, om.y, om.z});
            }
            for (std::size_t k = 0; k < sc.wall_members.size(); ++k) {
                Vec3 f, tq;
                for (uint32_t m : sc.wall_members[k]) {
                    f += w.wall_force(m);
                    tq += w.wall_torque(m);
                }
                walls.row({t, double(k), f.x, f.y, f.z, tq.x, tq.y, tq.z});
            }
            next_out = std::max(next_out, uint64_t(std::floor((t + eps) / out_iv)));
            while (t + eps >= double(next_out) * out_iv) ++next_out;
        }
        if (sc.vtk_interval > 0.0 && t + eps >= double(next_vtk) * vtk_iv) {
            char name[64];
            std::snprintf(name, sizeof name, "particles_%06llu.vtk", (unsigned long long)vtk_frame);
            dem::write_particles_vtk((out / "vtk" / name).string(), w);
            std::snprintf(name, sizeof name, "walls_%06llu.vtk", (unsigned long long)vtk_frame);
            dem::write_walls_vtk((out / "vtk" / name).string(), w, 0.05);
            ++vtk_frame;
            next_vtk = std::max(next_vtk, uint64_t(std::floor((t + eps) / vtk_iv)));
            while (t + eps >= double(next_vtk) * vtk_iv) ++next_vtk;
        }
        if (s == nsteps) {
            // The ledger at t needs v(t + dt/2): integrate the last step too (nothing after
            // this reads the World's positions).
            if (energy && output_row) {
                w.integrate();
                energy_row();
            }
            break;
        }
        w.integrate();
        if (energy && output_row) energy_row();
        progress.update(s + 1, w.time);
    }
    tracked.close();
    walls.close();
    if (energy) energy_csv.close();
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    progress.finish();

    dem::JsonObject js;
    js.num("dt", dt).boolean("dt_auto", sc.dt_auto).num("critical_dt", w.critical_dt()).num("steps", double(nsteps))
        .num("duration", sc.duration).num("particles", double(w.particles.size()))
        .num("planes", double(w.planes.size())).num("facets", double(w.facets.size()))
        .num("contacts_end", double(w.contact_count())).num("rebuilds", double(w.rebuild_count()))
        .num("threads", w.params.threads).num("wall_s", wall_s)
        .num("steps_per_s", double(nsteps) / std::max(wall_s, 1e-9))
        .raw("walls", dem::json_string_array(sc.wall_names));
    dem::JsonObject inputs;
    for (const auto& [key, value] : sc.inputs) inputs.raw(key, value);
    js.raw("inputs", inputs.value());
    dem::write_text_atomic((out / "summary.json").string(), js.text());
    if (!opt.quiet)
        std::fprintf(stderr, "done: %llu steps in %.2f s (%.0f steps/s); outputs in %s\n",
                     (unsigned long long)nsteps, wall_s, double(nsteps) / std::max(wall_s, 1e-9),
                     opt.out_dir.c_str());
}

}  // namespace scene
