// Shared helpers for the physics verification tests: small worlds, impact drivers and a
// uniform way to print measured error against tolerance.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>

#include "dem/world/world.h"

namespace dem::testing {

constexpr double kPi = std::numbers::pi;

inline double sphere_mass(double density, double r) { return density * 4.0 / 3.0 * kPi * r * r * r; }

inline Material make_material(double young, double friction = 0.0, double restitution = 1.0,
                              double density = 2800.0, double stiffness_ratio = 0.5) {
    Material m;
    m.name = "m";
    m.density = density;
    m.young = young;
    m.friction = friction;
    m.restitution = restitution;
    m.stiffness_ratio = stiffness_ratio;
    return m;
}

// Short number for test names ("0.2", "1e+08").
inline std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// Prints "[measure] name: got=... expected=... rel_err=... tol=..." and records it as a test
// property, so the verification report can be read off the test output. Returns rel. error.
inline double report_rel(const std::string& name, double got, double expected, double tol) {
    const double err = std::abs(got - expected) / std::abs(expected);
    std::ostringstream s;
    s << std::setprecision(6) << "got=" << got << " expected=" << expected
      << " rel_err=" << std::scientific << std::setprecision(3) << err << " tol=" << tol;
    std::cout << "[measure] " << name << ": " << s.str() << "\n";
    ::testing::Test::RecordProperty(name, s.str());
    return err;
}

inline void report_abs(const std::string& name, double err, double tol) {
    std::ostringstream s;
    s << std::scientific << std::setprecision(3) << "err=" << err << " tol=" << tol;
    std::cout << "[measure] " << name << ": " << s.str() << "\n";
    ::testing::Test::RecordProperty(name, s.str());
}

// Outcome of a single collision driven step by step until the bodies separate.
struct ImpactResult {
    uint64_t contact_steps = 0;  // steps at which compute_forces() saw a touching contact
    double duration = 0.0;       // contact_steps * dt [s]
    Vec3 vel_after[2];           // half-step velocities once separated (constant: no forces)
    Vec3 angvel_after[2];
    bool separated = false;
};

// Steps `w` until a contact has been seen and then has been absent for a few steps.
// Counts the steps with contact_count() > 0 right after compute_forces().
inline ImpactResult run_impact(World& w, uint64_t max_steps) {
    ImpactResult r;
    bool seen = false;
    int quiet = 0;
    for (uint64_t s = 0; s < max_steps; ++s) {
        w.compute_forces();
        const bool touching = w.contact_count() > 0;
        if (touching) {
            ++r.contact_steps;
            seen = true;
            quiet = 0;
        } else if (seen && ++quiet > 5) {
            r.separated = true;
            break;
        }
        w.integrate();
    }
    r.duration = double(r.contact_steps) * w.params.dt;
    for (std::size_t i = 0; i < std::min<std::size_t>(2, w.particles.size()); ++i) {
        r.vel_after[i] = w.particles.vel[i];
        r.angvel_after[i] = w.particles.angvel[i];
    }
    return r;
}

// Two equal spheres of material `m`, radius r, approaching head-on along x with speeds +-v,
// starting a few steps apart. dt is chosen as the analytic contact duration / steps_per_contact
// using the reduced mass m/2 and kn = E r (Yade convention for equal spheres).
inline World two_sphere_world(const Material& mat, double r, double v, double steps_per_contact) {
    World w;
    w.params.gravity = {0, 0, 0};
    w.params.local_damping = 0.0;
    w.add_material(mat);
    const double m = sphere_mass(mat.density, r);
    const double kn = mat.young * r;
    const double tc = kPi * std::sqrt(0.5 * m / kn);
    w.params.dt = tc / steps_per_contact;
    const double gap = 4.0 * v * w.params.dt;  // each closes gap/2 in 2 steps: touch after ~2 steps
    SphereDef a, b;
    a.radius = b.radius = r;
    a.position = {-r - 0.5 * gap, 0, 0};
    b.position = {r + 0.5 * gap, 0, 0};
    a.velocity = {v, 0, 0};
    b.velocity = {-v, 0, 0};
    w.add_sphere(a);
    w.add_sphere(b);
    return w;
}

// One sphere falling along -z (no gravity) with speed v onto the fixed plane z = 0 of the
// same material. dt = (pi sqrt(m/kn)) / steps_per_contact, kn = E r.
inline World sphere_plane_world(const Material& mat, double r, double v, double steps_per_contact,
                                Vec3 velocity_dir = {0, 0, -1}) {
    World w;
    w.params.gravity = {0, 0, 0};
    w.params.local_damping = 0.0;
    w.add_material(mat);
    const double m = sphere_mass(mat.density, r);
    const double kn = mat.young * r;
    const double tc = kPi * std::sqrt(m / kn);
    w.params.dt = tc / steps_per_contact;
    const double vn = -velocity_dir.z * v;
    SphereDef s;
    s.radius = r;
    s.position = {0, 0, r + 2.5 * vn * w.params.dt};
    s.velocity = velocity_dir * v;
    w.add_sphere(s);
    Plane p;
    p.point = {0, 0, 0};
    p.normal = {0, 0, 1};
    p.material = 0;
    w.add_plane(p);
    return w;
}

}  // namespace dem::testing
