// vppdem._core.World: the generic DEM World from Python: bodies, walls, bonds and motions added by
// hand, its parameters, stepping without the interpreter lock, its state as arrays, checkpoints.
#include "bindings.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/io/checkpoint.h"
#include "dem/walls/facet_sets.h"
#include "dem/world/world.h"

namespace bindings {

namespace {

// A wall's or particle's motion: a constant velocity [m/s] from now on, or a displacement history
// of rows (t [s], dx, dy, dz [m]) from the reference position. The core's constant velocity
// counts from t = 0 (displacement = v t), which would make a wall set moving mid-run jump; from
// Python a velocity starts where the wall stands now (`now` [s], displaced by `d_now` [m]).
dem::Motion make_motion(const std::vector<double>& velocity, const std::vector<std::vector<double>>& history,
                        double now, dem::Vec3 d_now) {
    if (!velocity.empty() && !history.empty()) throw std::invalid_argument("motion: give velocity or history, not both");
    dem::Motion m;
    if (!velocity.empty()) {
        const dem::Vec3 v = to_vec3(velocity, "velocity");
        if (now == 0.0 && d_now == dem::Vec3{}) {
            m.velocity = v;
        } else {
            constexpr double kHorizon = 1e3;  // [s] of simulated time the motion runs for
            m.history = {{now, d_now}, {now + kHorizon, d_now + v * kHorizon}};
        }
    }
    for (const auto& row : history) {
        if (row.size() != 4) throw std::invalid_argument("history: each row is (t, dx, dy, dz)");
        if (!m.history.empty() && !(row[0] > m.history.back().time))
            throw std::invalid_argument("history: times must increase");
        m.history.push_back({row[0], {row[1], row[2], row[3]}});
    }
    return m;
}

using WorldClass = py::class_<dem::World>;

// Materials, spheres and clumps.
void def_bodies(WorldClass& cls) {
    cls
        .def("add_material",
             [](dem::World& w, const std::string& name, double density, double young, double stiffness_ratio,
                double friction, double restitution) {
                 return w.add_material({name, density, young, stiffness_ratio, friction, restitution});
             },
             py::arg("name") = "", py::arg("density") = 2800.0, py::arg("young") = 4.8e10,
             py::arg("stiffness_ratio") = 0.5, py::arg("friction") = 0.35, py::arg("restitution") = 1.0,
             "Adds a material; returns its index. density [kg/m^3], young: particle modulus [Pa] (kn = E r for "
             "two equal spheres), stiffness_ratio ks/kn [-], friction: Coulomb coefficient [-], restitution: "
             "normal coefficient [-] (1: no viscous damping)")
        .def("add_sphere",
             [](dem::World& w, const std::vector<double>& position, double radius, uint32_t material,
                const std::vector<double>& velocity, const std::vector<double>& angular_velocity, uint32_t mask) {
                 if (material >= w.materials.size()) throw std::invalid_argument("add_sphere: no material " + std::to_string(material) + "; add_material first");
                 dem::SphereDef d;
                 d.position = to_vec3(position, "position");
                 d.radius = radius;
                 d.material = material;
                 d.velocity = to_vec3(velocity, "velocity");
                 d.angular_velocity = to_vec3(angular_velocity, "angular_velocity");
                 d.mask = mask;
                 return w.add_sphere(d);
             },
             py::arg("position"), py::arg("radius"), py::arg("material") = 0,
             py::arg("velocity") = std::vector<double>{0, 0, 0}, py::arg("angular_velocity") = std::vector<double>{0, 0, 0},
             py::arg("mask") = 1,
             "Adds a sphere; returns its index. position [m], radius [m], velocity [m/s], angular_velocity "
             "[rad/s]; mask: bodies interact when their masks share a bit")
        .def("add_clump",
             [](dem::World& w, const std::vector<double>& position, const py::object& shape, double radius,
                uint32_t material, const std::vector<double>& orientation, const std::vector<double>& velocity,
                const std::vector<double>& angular_velocity, uint32_t mask) {
                 if (material >= w.materials.size()) throw std::invalid_argument("add_clump: no material " + std::to_string(material) + "; add_material first");
                 dem::ClumpShape cs;
                 if (py::isinstance<py::str>(shape)) {
                     if (!(radius > 0)) throw std::invalid_argument("add_clump: a built-in shape needs radius > 0 (the volume-equivalent radius [m])");
                     cs = dem::builtin_clump_shape(shape.cast<std::string>(), radius);
                 } else {
                     // rows (x, y, z, r) [m] of the members in the grain's frame
                     std::vector<dem::ClumpMember> members;
                     for (const auto& row : shape.cast<std::vector<std::vector<double>>>()) {
                         if (row.size() != 4) throw std::invalid_argument("add_clump: each member is a row (x, y, z, r)");
                         members.push_back({{row[0], row[1], row[2]}, row[3]});
                     }
                     cs = dem::make_clump_shape(members);
                     if (radius > 0) cs = dem::scaled_to_radius(cs, radius);
                 }
                 dem::ClumpDef d;
                 d.position = to_vec3(position, "position");
                 if (orientation.size() != 4) throw std::invalid_argument("add_clump: orientation is a quaternion (w, x, y, z)");
                 d.orientation = {orientation[0], orientation[1], orientation[2], orientation[3]};
                 d.velocity = to_vec3(velocity, "velocity");
                 d.angular_velocity = to_vec3(angular_velocity, "angular_velocity");
                 d.material = material;
                 d.mask = mask;
                 const uint32_t first = uint32_t(w.particles.size());
                 const uint32_t k = w.add_clump(cs, d);
                 return py::make_tuple(k, first, cs.members.size());
             },
             py::arg("position"), py::arg("shape"), py::arg("radius") = 0.0, py::arg("material") = 0,
             py::arg("orientation") = std::vector<double>{1, 0, 0, 0}, py::arg("velocity") = std::vector<double>{0, 0, 0},
             py::arg("angular_velocity") = std::vector<double>{0, 0, 0}, py::arg("mask") = 1,
             "Adds a rigid clump; returns (clump index, first member's particle index, member count). shape: a "
             "built-in name (sphere, dimer, trimer, tetrahedron, pellet) scaled to the volume of a sphere of "
             "radius [m], or rows (x, y, z, r) [m] of member spheres (scaled likewise when radius > 0). "
             "position: centre of mass [m]; orientation: quaternion (w, x, y, z) of the principal frame; "
             "velocity [m/s], angular_velocity [rad/s] (world frame)")
        .def("clump_count", [](const dem::World& w) { return w.clumps().size(); })
        .def("clump_state",
             [](const dem::World& w, std::size_t k) {
                 const dem::Clumps& c = w.clumps();
                 if (k >= c.size()) throw std::out_of_range("clump_state: no clump " + std::to_string(k));
                 py::dict out;
                 const auto v3 = [](const dem::Vec3& v) { return py::make_tuple(v.x, v.y, v.z); };
                 out["position"] = v3(c.pos[k]);
                 out["velocity"] = v3(c.vel[k]);
                 out["orientation"] = py::make_tuple(c.q[k].w, c.q[k].x, c.q[k].y, c.q[k].z);
                 out["angular_velocity"] = v3(c.angvel[k]);
                 out["angular_momentum"] = v3(c.mom[k]);
                 out["mass"] = c.mass[k];
                 out["inertia"] = v3(c.inertia[k]);
                 out["kinetic_energy"] = w.clump_kinetic_energy(k);
                 return out;
             },
             py::arg("k"),
             "Clump k at the half step: position [m], velocity [m/s], orientation (w, x, y, z), angular_velocity "
             "[rad/s] and angular_momentum [kg m^2/s] (world frame), mass [kg], principal inertia [kg m^2], "
             "kinetic_energy [J]");
}

// Planes and triangles (by hand or from an STL file).
void def_walls(WorldClass& cls) {
    cls
        .def("add_plane",
             [](dem::World& w, const std::vector<double>& point, const std::vector<double>& normal, uint32_t material,
                bool one_sided, uint32_t mask) {
                 dem::Plane p;
                 p.point = to_vec3(point, "point");
                 p.normal = to_vec3(normal, "normal");
                 const double n = dem::norm(p.normal);
                 if (!(n > 0)) throw std::invalid_argument("add_plane: the normal must not be zero");
                 p.normal = p.normal / n;
                 p.material = material;
                 p.one_sided = one_sided;
                 p.mask = mask;
                 return w.add_plane(p);
             },
             py::arg("point"), py::arg("normal"), py::arg("material") = 0, py::arg("one_sided") = false, py::arg("mask") = 1,
             "Adds an infinite plane through point [m] with normal (normalised); returns its wall index")
        .def("add_facets",
             [](dem::World& w, py::array_t<double, py::array::c_style | py::array::forcecast> v, uint32_t material,
                bool one_sided, uint32_t mask) {
                 // (n, 3, 3): n triangles of three vertices [m]; returns the first facet's index
                 if (v.ndim() != 3 || v.shape(1) != 3 || v.shape(2) != 3)
                     throw std::invalid_argument("add_facets: expected an array of shape (n, 3, 3)");
                 auto a = v.unchecked<3>();
                 const uint32_t first = uint32_t(w.facets.size());
                 for (py::ssize_t k = 0; k < a.shape(0); ++k) {
                     dem::Facet f;
                     for (int j = 0; j < 3; ++j) f.vertices[std::size_t(j)] = {a(k, j, 0), a(k, j, 1), a(k, j, 2)};
                     f.material = material;
                     f.one_sided = one_sided;
                     f.mask = mask;
                     w.add_facet(f);
                 }
                 return first;
             },
             py::arg("vertices"), py::arg("material") = 0, py::arg("one_sided") = false, py::arg("mask") = 1,
             "Adds triangles from an (n, 3, 3) array of vertices [m] (normal (v1 - v0) x (v2 - v0)); returns the "
             "first facet's index (wall index: plane_count + facet index)")
        .def("add_stl",
             [](dem::World& w, const py::object& file, double scale, uint32_t material, bool one_sided, uint32_t mask) {
                 const std::string path = fspath(file);
                 // scale: to metres (1e-3 for a file in millimetres); returns (first facet, count)
                 const uint32_t first = uint32_t(w.facets.size());
                 std::vector<dem::Facet> fs = dem::read_stl(path, scale);
                 for (dem::Facet& f : fs) {
                     f.material = material;
                     f.one_sided = one_sided;
                     f.mask = mask;
                     w.add_facet(f);
                 }
                 return py::make_tuple(first, fs.size());
             },
             py::arg("path"), py::arg("scale") = 1.0, py::arg("material") = 0, py::arg("one_sided") = false,
             py::arg("mask") = 1,
             "Adds the triangles of a binary or ASCII STL file, coordinates times scale (1e-3 for millimetres); "
             "returns (first facet, count)");
}

// Bonds, fixed particles and prescribed motions of walls and particles.
void def_constraints(WorldClass& cls) {
    cls
        .def("add_bond", &dem::World::add_bond, py::arg("i"), py::arg("j"), py::arg("kn"), py::arg("ks"),
             py::arg("rest_length") = -1.0, "Permanent bond: kn, ks [N/m]; rest_length [m] (< 0: the current distance)")
        .def_property(
            "bond_arm", [](const dem::World& w) { return dem::bond_arm_name(w.bonds().arm); },
            [](dem::World& w, const std::string& a) {
                const std::optional<dem::BondArm> arm = dem::bond_arm_from_name(a);
                if (!arm) throw py::value_error("bond_arm: '" + a + "' is not allowed (\"radius\" or \"bond_point\")");
                w.set_bond_arm(*arm);
            },
            "Where the bonds' shear springs are driven from: \"radius\" (the full radii, the paper's convention) or "
            "\"bond_point\" (where the torques act: a rigid motion loads no spring)")
        .def("set_fixed", &dem::World::set_fixed, py::arg("i"))
        .def("set_plane_motion",
             [](dem::World& w, std::size_t k, const std::vector<double>& velocity,
                const std::vector<std::vector<double>>& history) {
                 if (k >= w.planes.size()) throw std::out_of_range("set_plane_motion: no plane " + std::to_string(k));
                 w.planes[k].motion = make_motion(velocity, history, w.time, w.planes[k].motion.displacement(w.time));
                 w.invalidate_candidates();
             },
             py::arg("plane"), py::arg("velocity") = std::vector<double>{}, py::arg("history") = std::vector<std::vector<double>>{},
             "Moves plane k: velocity [m/s] from where it stands now, or history rows (t [s], dx, dy, dz [m]) "
             "of displacement from its reference position")
        .def("set_facet_motion",
             [](dem::World& w, std::size_t first, std::size_t count, const std::vector<double>& velocity,
                const std::vector<std::vector<double>>& history) {
                 if (first + count > w.facets.size()) throw std::out_of_range("set_facet_motion: facets out of range");
                 const dem::Motion m = make_motion(velocity, history, w.time, w.facets[first].motion.displacement(w.time));
                 for (std::size_t k = first; k < first + count; ++k) w.facets[k].motion = m;
                 w.invalidate_candidates();
             },
             py::arg("first"), py::arg("count"), py::arg("velocity") = std::vector<double>{},
             py::arg("history") = std::vector<std::vector<double>>{})
        .def("set_particle_motion",
             [](dem::World& w, uint32_t i, const std::vector<double>& velocity, const std::vector<std::vector<double>>& history) {
                 // from its current position (World::set_prescribed); the particle checked before
                 // the motion is added, so that a refused call leaves the world as it was
                 w.require_particle("set_particle_motion", i);
                 w.set_prescribed(i, w.add_motion(make_motion(velocity, history, w.time, {})));
             },
             py::arg("i"), py::arg("velocity") = std::vector<double>{}, py::arg("history") = std::vector<std::vector<double>>{});
}

// The parameters of the step, the clock and stepping.
void def_stepping(WorldClass& cls) {
    cls
        .def_property("dt", [](const dem::World& w) { return w.params.dt; }, [](dem::World& w, double v) { w.params.dt = v; },
                      "[s] time step (e.g. 0.2 * critical_dt())")
        .def_property("gravity", [](const dem::World& w) { return std::vector<double>{w.params.gravity.x, w.params.gravity.y, w.params.gravity.z}; },
                      [](dem::World& w, const std::vector<double>& g) { w.params.gravity = to_vec3(g, "gravity"); },
                      "[m/s^2] (0, 0, -9.81) by default")
        .def_property("local_damping", [](const dem::World& w) { return w.params.local_damping; },
                      [](dem::World& w, double v) { w.params.local_damping = v; }, "[-] Yade's non-viscous damping")
        .def_property("threads", [](const dem::World& w) { return w.params.threads; },
                      [](dem::World& w, int v) { w.params.threads = v; })
        .def_property("skin", [](const dem::World& w) { return w.params.skin; }, [](dem::World& w, double v) {
                // The candidate lists were built for the old skin: a new one takes effect with a
                // rebuild at the next step (a checkpoint in between resumes the same way).
                w.params.skin = v;
                w.invalidate_candidates();
            },
                      "[m] Verlet distance; 0: half the smallest radius")
        .def_property("track_energy", [](const dem::World& w) { return w.params.track_energy; },
                      [](dem::World& w, bool v) { w.params.track_energy = v; })
        .def_property_readonly("time", [](const dem::World& w) { return w.time; })
        .def_property_readonly("steps", [](const dem::World& w) { return w.steps; })
        .def("critical_dt", &dem::World::critical_dt)
        .def(
            "step",
            [](dem::World& w, uint64_t n, py::object progress) {
                if (w.particles.size() == 0) throw std::invalid_argument("step: the world has no particles");
                const Hook hook = python_hook(progress);
                py::gil_scoped_release release;
                for (uint64_t s = 1; s <= n; ++s) {
                    w.step();
                    if (!(s & 255u) || s == n) hook("step", s, n, w.time);
                }
            },
            py::arg("n") = 1, py::arg("progress") = py::none(),
            "Advances n steps without the interpreter lock; progress(stage, done, total, time [s]) every 256 "
            "steps; Ctrl-C raises KeyboardInterrupt");
}

// The state as arrays and counts; checkpoints.
void def_state(WorldClass& cls) {
    cls
        .def("__len__", [](const dem::World& w) { return w.particles.size(); })
        .def_property_readonly("positions", [](const dem::World& w) { return vec3_array(w.particles.pos); })
        .def_property_readonly("velocities", [](const dem::World& w) {
            // v(t) = v(t - dt/2) + dt/2 a(t): at the same time as the positions (after a step)
            std::vector<dem::Vec3> v(w.particles.size());
            for (std::size_t i = 0; i < v.size(); ++i) v[i] = w.velocity_at_time(i);
            return vec3_array(v);
        })
        .def_property_readonly("half_step_velocities", [](const dem::World& w) { return vec3_array(w.particles.vel); })
        .def_property_readonly("angular_velocities", [](const dem::World& w) { return vec3_array(w.particles.angvel); })
        .def_property_readonly("forces", [](const dem::World& w) { return vec3_array(w.particles.force); })
        .def_property_readonly("radii", [](const dem::World& w) { return double_array(w.particles.radius); })
        .def_property_readonly("masses", [](const dem::World& w) { return double_array(w.particles.mass); })
        .def("wall_force", [](const dem::World& w, std::size_t k) {
                 if (k >= w.wall_count()) throw std::out_of_range("wall_force: no wall " + std::to_string(k));
                 const dem::Vec3 f = w.wall_force(k);
                 return std::vector<double>{f.x, f.y, f.z};
             }, py::arg("wall"), "[N] particles on wall k (planes first, then facets) at the last step")
        .def_property_readonly("plane_count", [](const dem::World& w) { return w.planes.size(); })
        .def_property_readonly("facet_count", [](const dem::World& w) { return w.facets.size(); })
        .def_property_readonly("bond_count", [](const dem::World& w) { return w.bonds().size(); })
        .def("contact_count", &dem::World::contact_count)
        .def("save", [](const dem::World& w, const py::object& path) { dem::save_checkpoint(fspath(path), w, ""); }, py::arg("path"))
        .def_static("load", [](const py::object& path) {
                auto w = std::make_unique<dem::World>();
                dem::load_checkpoint(fspath(path), *w);
                return w;
            }, py::arg("path"));
}

}  // namespace

void bind_world(py::module_& m) {
    WorldClass cls(m, "World");
    cls.def(py::init<>());
    def_bodies(cls);
    def_walls(cls);
    def_constraints(cls);
    def_stepping(cls);
    def_state(cls);
}

}  // namespace bindings
