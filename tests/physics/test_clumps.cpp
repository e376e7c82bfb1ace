// Clumps as rigid bodies (World::add_clump, dem/clumps) against closed forms:
//  - free rotation of an asymmetric body: energy kept over 1e6 steps, the body-frame angular
//    velocity against Euler's equations integrated finely (RK4), |L| exact;
//  - torque-free precession of a symmetric body: the symmetry axis turns about L at |L| / I_t;
//  - a dimer lying on a plane carries its weight, at rest;
//  - a dimer falling end-on onto a plane: the contact duration of its whole mass, pi sqrt(M / kn),
//    and the material's restitution (the reduced mass is the clump's, not the member's);
//  - determinism (any thread count, a checkpoint in the middle) and the ledger's balance.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>

#include "dem/clumps/rigid_rotation.h"
#include "dem/io/checkpoint.h"
#include "helpers.h"

using namespace dem;
using namespace dem::testing;

namespace {

// Euler's equations of a free body in its principal frame with the orientation, by RK4.
struct Reference {
    Vec3 w;  // body frame [rad/s]
    Quat q;
};
Reference euler_rk4(Vec3 w, Quat q, const Vec3& I, double dt, uint64_t steps) {
    const auto dw = [&](const Vec3& v) {
        return Vec3{(I.y - I.z) / I.x * v.y * v.z, (I.z - I.x) / I.y * v.z * v.x, (I.x - I.y) / I.z * v.x * v.y};
    };
    const auto dq = [](const Quat& a, const Vec3& v) {
        const Quat r = a * Quat{0.0, v.x, v.y, v.z};
        return Quat{0.5 * r.w, 0.5 * r.x, 0.5 * r.y, 0.5 * r.z};
    };
    const auto add = [](const Quat& a, const Quat& b, double s) {
        return Quat{a.w + s * b.w, a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
    };
    for (uint64_t s = 0; s < steps; ++s) {
        const Vec3 k1 = dw(w), k2 = dw(w + k1 * (0.5 * dt)), k3 = dw(w + k2 * (0.5 * dt)), k4 = dw(w + k3 * dt);
        const Quat l1 = dq(q, w), l2 = dq(add(q, l1, 0.5 * dt), w + k1 * (0.5 * dt)),
                   l3 = dq(add(q, l2, 0.5 * dt), w + k2 * (0.5 * dt)), l4 = dq(add(q, l3, dt), w + k3 * dt);
        w += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
        q = normalized(add(add(add(add(q, l1, dt / 6.0), l2, dt / 3.0), l3, dt / 3.0), l4, dt / 6.0));
    }
    return {w, q};
}

// A free world (no gravity, no walls, no damping) with one clump.
World free_clump_world(const ClumpShape& shape, const Vec3& w0, double dt) {
    World w;
    w.params.gravity = {0, 0, 0};
    w.params.dt = dt;
    w.add_material(make_material(1e7));
    ClumpDef d;
    d.angular_velocity = w0;
    d.orientation = normalized(Quat{0.9, 0.1, -0.3, 0.2});
    w.add_clump(shape, d);
    return w;
}

// An asymmetric tetrahedral clump: unequal spheres (1.0, 0.8, 0.7, 0.6 mm) at the corners of a
// tetrahedron stretched along x (alternate corners of a 1.26 x 0.9 x 0.9 mm box).
ClumpShape asymmetric_shape() {
    const double x = 0.63e-3, a = 0.45e-3;
    return make_clump_shape({{{x, a, a}, 1.0e-3}, {{x, -a, -a}, 0.8e-3}, {{-x, a, -a}, 0.7e-3}, {{-x, -a, a}, 0.6e-3}});
}

}  // namespace

// The asymmetric tetrahedral clump, 1e6 steps at omega dt ~ 2e-3 rad, tumbling near the unstable
// middle axis: the splitting's energy error is bounded, O((omega dt)^2) ~ 1e-6, without drift
// (measured: 1.5e-7 at worst), checked at 1e-6; the momentum L is the state and is not touched
// without torque, and the body-frame momentum keeps |L| to round-off. The body-frame angular
// velocity after 1e6 steps (about 300 turns) against RK4 at dt / 4 (Euler's equations):
// measured 2.8e-4 of |omega|, checked at 1e-3 (a first-order scheme, or a turn of the wrong
// sense, is off by order 1).
TEST(Clumps, FreeRotationOfAnAsymmetricBodyKeepsItsEnergy) {
    const ClumpShape s = asymmetric_shape();
    ASSERT_LT(s.inertia_per_density.x * 1.1, s.inertia_per_density.y);
    ASSERT_LT(s.inertia_per_density.y * 1.1, s.inertia_per_density.z);
    const Vec3 w0{3.0, 40.0, 1.0};  // near the middle axis: the unstable, tumbling case
    const double dt = 5e-5;
    const uint64_t n = 1000000;
    World w = free_clump_world(s, w0, dt);
    const Clumps& c = w.clumps();
    const Vec3 L0 = c.mom[0], I = c.inertia[0];
    const double e0 = rigid::rotational_energy(c.q[0], L0, I);
    const Quat q0 = c.q[0];
    double worst = 0.0;
    for (uint64_t k = 0; k < n; ++k) {
        w.step();
        if (k % 1000 == 999) worst = std::max(worst, std::abs(rigid::rotational_energy(c.q[0], c.mom[0], I) / e0 - 1.0));
    }
    report_abs("free_rotation_energy_drift_1e6_steps", worst, 1e-6);
    EXPECT_LT(worst, 1e-6);
    EXPECT_EQ(c.mom[0], L0);  // no torque: the momentum is not touched
    // The body-frame momentum keeps |L| (the orientation stays a rotation): to round-off.
    EXPECT_NEAR(norm(rotate_back(c.q[0], L0)) / norm(L0), 1.0, 1e-12);
    EXPECT_EQ(c.pos[0], Vec3{});
    // The body-frame angular velocity against Euler's equations.
    const Reference ref = euler_rk4(rotate_back(q0, w0), q0, I, dt / 4.0, 4 * n);
    const Vec3 wb = rotate_back(c.q[0], rigid::angular_velocity(c.q[0], c.mom[0], I));
    const double err = norm(wb - ref.w) / norm(ref.w);
    report_abs("free_rotation_body_omega_vs_rk4", err, 1e-3);
    EXPECT_LT(err, 1e-3);
    // The members move with the body: distances from the centre kept.
    const Particles& p = w.particles;
    for (uint32_t e = 0; e < 4; ++e) EXPECT_NEAR(norm(p.pos[e] - c.pos[0]), norm(c.rel[e]), 1e-15);
}

// A symmetric body (the dimer: I_s about its axis, I_t across) turns its axis about the fixed L
// at the rate |L| / I_t. After 2e5 steps (14 turns about L) the axis must be the initial one
// turned about L by that angle: within 1e-5 rad (measured 9.7e-7, the splitting's phase error;
// a rate of |L| / I_s or of |omega| is off by radians); the cone's angle kept within 1e-7.
TEST(Clumps, SymmetricBodyPrecessesAtTheClosedFormRate) {
    const ClumpShape s = builtin_clump_shape("dimer", 1e-3);
    const double dt = 2e-5;
    const uint64_t n = 200000;
    World w = free_clump_world(s, Vec3{5.0, 20.0, -8.0}, dt);
    const Clumps& c = w.clumps();
    const Vec3 L = c.mom[0], I = c.inertia[0];
    ASSERT_NEAR(I.y / I.z, 1.0, 1e-9);
    const double it = 0.5 * (I.y + I.z);
    const Vec3 axis0 = body_axis(c.q[0], 0);
    for (uint64_t k = 0; k < n; ++k) w.step();
    const Vec3 axis1 = body_axis(c.q[0], 0);
    // Rodrigues: axis0 turned about l by phi.
    const Vec3 l = normalized(L);
    const double phi = norm(L) / it * double(n) * dt;
    const Vec3 expect = axis0 * std::cos(phi) + cross(l, axis0) * std::sin(phi) + l * (dot(l, axis0) * (1.0 - std::cos(phi)));
    const double err = norm(axis1 - expect);
    std::cout << "[measure] precession: " << phi / (2.0 * kPi) << " turns of the axis about L, error " << err << "\n";
    report_abs("symmetric_precession_axis_error_rad", err, 1e-5);
    EXPECT_LT(err, 1e-5);
    EXPECT_NEAR(dot(axis1, l), dot(axis0, l), 1e-7);  // the cone's angle
}

// A dimer lying on a plane, settled with local damping: the plane carries M g, the clump rests
// level (both members on the plane) and does not turn.
TEST(Clumps, DimerOnAPlaneCarriesItsWeight) {
    World w;
    w.params.local_damping = 0.5;
    const Material mat = make_material(1e7);
    w.add_material(mat);
    const ClumpShape s = builtin_clump_shape("dimer", 2e-3);
    Plane pl;
    pl.normal = {0, 0, 1};
    w.add_plane(pl);
    ClumpDef d;
    d.position = {0, 0, s.members[0].radius + 1e-5};  // axis along x (principal axis 0), just above
    w.add_clump(s, d);
    w.params.dt = 0.2 * w.critical_dt();
    for (int k = 0; k < 40000; ++k) w.step();
    w.compute_forces();
    const double mg = w.clumps().mass[0] * 9.81;
    EXPECT_LT(report_rel("dimer_plane_weight", w.wall_force(0).z, -mg, 1e-6), 1e-6);
    EXPECT_EQ(w.contact_count(), 2u);
    EXPECT_LT(norm(w.clumps().vel[0]), 1e-9);
    EXPECT_LT(norm(w.clumps().angvel[0]), 1e-6);
    const Particles& p = w.particles;
    EXPECT_NEAR(p.pos[0].z, p.pos[1].z, 1e-12);
    w.check_invariants();
}

// A dimer falling end-on (axis vertical) onto a plane: one member touches, on the line through
// the centre of mass, so the clump meets the plane as a point of mass M: contact time
// pi sqrt(M / kn) with kn = E r_member, exit speed e times the entry speed (the dashpot is
// calibrated on the clump's mass). Tolerances as for spheres (tests/physics/test_impacts.cpp);
// the member's own mass would give a duration off by 30% and a wrong restitution.
TEST(Clumps, DimerEndOnImpactHasTheRigidBodyDurationAndRestitution) {
    for (const double e : {1.0, 0.5}) {
        World w;
        w.params.gravity = {0, 0, 0};
        const Material mat = make_material(1e7, 0.0, e);
        w.add_material(mat);
        const ClumpShape s = builtin_clump_shape("dimer", 2e-3);
        Plane pl;
        pl.normal = {0, 0, 1};
        w.add_plane(pl);
        const double r = s.members[0].radius, a = std::abs(s.members[0].center.x);
        const double m = mat.density * s.volume, kn = mat.young * r;
        const double tc = kPi * std::sqrt(m / kn);
        w.params.dt = tc / 1234.5;
        const double v = 0.5;
        ClumpDef d;
        // Principal axis 0 (the dimer's) along z: a quarter turn about y.
        d.orientation = normalized(Quat{1.0, 0.0, 1.0, 0.0});
        d.position = {0, 0, a + r + 2.5 * v * w.params.dt};
        d.velocity = {0, 0, -v};
        w.add_clump(s, d);
        const ImpactResult out = run_impact(w, 5 * 1235);
        ASSERT_TRUE(out.separated);
        if (e == 1.0) {
            EXPECT_LT(report_rel("dimer_end_on_duration", out.duration, tc, 0.01), 0.01);
        }
        EXPECT_LT(report_rel("dimer_end_on_restitution_e" + fmt(e), w.clumps().vel[0].z, e * v, 0.005), 0.005);
        // The force through the centre (to the round-off of the member's place): no turn.
        EXPECT_LT(norm(w.clumps().angvel[0]), 1e-9);
    }
}

namespace {

// Dimers, tetrahedra and spheres poured into a box: a busy scene for determinism.
World pour(int threads) {
    World w;
    w.params.threads = threads;
    w.params.local_damping = 0.2;
    w.params.track_energy = true;
    w.add_material(make_material(1e6, 0.5, 0.7, 1000.0));
    for (const Vec3 n : {Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}}) {
        Plane pl;
        pl.normal = n;
        pl.point = n * -0.02;
        pl.point.z = 0.0;
        pl.one_sided = true;
        w.add_plane(pl);
    }
    const ClumpShape dimer = builtin_clump_shape("dimer", 2e-3), tet = builtin_clump_shape("tetrahedron", 2e-3);
    int k = 0;
    for (int iz = 0; iz < 6; ++iz)
        for (int iy = 0; iy < 6; ++iy)
            for (int ix = 0; ix < 6; ++ix, ++k) {
                const Vec3 x{-0.015 + 0.006 * ix, -0.015 + 0.006 * iy, 0.004 + 0.006 * iz};
                if (k % 5 == 4) {
                    SphereDef sd;
                    sd.position = x;
                    sd.radius = 2e-3;
                    sd.velocity = {0.0, 0.0, -0.4};
                    w.add_sphere(sd);
                    continue;
                }
                ClumpDef d;
                d.position = x;
                d.orientation = normalized(Quat{1.0, 0.3 * (k % 3), -0.2 * (k % 4), 0.1 * (k % 7)});
                d.velocity = {0.01 * (k % 3), -0.02 * (k % 2), -0.4};
                d.angular_velocity = {double(k % 5), -2.0, 1.0};
                w.add_clump(k % 2 ? dimer : tet, d);
            }
    w.params.dt = 0.2 * w.critical_dt();
    return w;
}

void expect_same_state(const World& a, const World& b) {
    ASSERT_EQ(a.particles.size(), b.particles.size());
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
        ASSERT_EQ(a.particles.pos[i], b.particles.pos[i]) << i;
        ASSERT_EQ(a.particles.vel[i], b.particles.vel[i]) << i;
    }
    for (std::size_t k = 0; k < a.clumps().size(); ++k) {
        ASSERT_EQ(a.clumps().q[k], b.clumps().q[k]) << k;
        ASSERT_EQ(a.clumps().mom[k], b.clumps().mom[k]) << k;
    }
    EXPECT_EQ(a.energy().residual(), b.energy().residual());
    EXPECT_EQ(a.energy().kinetic, b.energy().kinetic);
}

}  // namespace

TEST(Clumps, PourIsBitwiseTheSameForAnyThreadCountAndAcrossACheckpoint) {
    World one = pour(1);
    for (int k = 0; k < 3000; ++k) one.step();
    EXPECT_GT(one.particle_contact_count(), 30u);
    for (const int nt : {2, 3}) {
        World many = pour(nt);
        for (int k = 0; k < 3000; ++k) many.step();
        expect_same_state(one, many);
    }
    // Stopped at 1500 steps, saved, loaded, continued.
    World first = pour(1);
    for (int k = 0; k < 1500; ++k) first.step();
    const auto path = (std::filesystem::temp_directory_path() / "vppdem_clumps_test.ckpt").string();
    save_checkpoint(path, first, "");
    World resumed;
    load_checkpoint(path, resumed);
    std::filesystem::remove(path);
    resumed.check_invariants();
    for (int k = 0; k < 1500; ++k) resumed.step();
    expect_same_state(one, resumed);
}

// The ledger's balance with clumps (docs/energy.md): gravity's work on a falling, colliding pour
// of clumps is what the grains store and dissipate. The residual, set by the contact law's
// onsets like the spheres', stays below 1% of the work (measured: 0.1%); without the clumps'
// kinetic and damping terms it would be the whole work.
TEST(Clumps, EnergyLedgerBalancesAPour) {
    World w = pour(2);
    for (int k = 0; k < 6000; ++k) w.step();
    const EnergyLedger& e = w.energy();
    ASSERT_GT(e.gravity_work, 0.0);
    EXPECT_GT(e.damping_dissipation, 0.0);
    report_abs("clump_pour_ledger_residual_over_gravity_work", std::abs(e.residual()) / e.gravity_work, 1e-2);
    EXPECT_LT(std::abs(e.residual()), 1e-2 * e.gravity_work);
}

// `vppdem bench checkpoint` times any saved World: the pour's checkpoint, its clumps counted in
// the JSON line (the contract read by bench/grain_shapes.sh); a missing file is refused.
TEST(Clumps, BenchTimesASavedWorldWithItsClumps) {
    World w = pour(1);
    for (int k = 0; k < 100; ++k) w.step();
    const auto path = (std::filesystem::temp_directory_path() / "vppdem_clumps_bench.ckpt").string();
    save_checkpoint(path, w, "");
    const auto run = [](const std::string& args) {
        std::string out;
        FILE* f = popen((std::string(VPPDEM_BINARY) + " bench checkpoint " + args + " 2>&1").c_str(), "r");
        char buf[4096];
        while (f && fgets(buf, sizeof buf, f)) out += buf;
        const int rc = f ? pclose(f) : -1;
        return std::make_pair(rc, out);
    };
    const auto [rc, out] = run("--state " + path + " --steps 50 --threads 1");
    std::filesystem::remove(path);
    ASSERT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("\"steps\": 50"), std::string::npos) << out;
    EXPECT_NE(out.find("\"clumps\": " + std::to_string(w.clumps().size())), std::string::npos) << out;
    const auto [rc2, out2] = run("--state /nonexistent.ckpt --steps 5");
    EXPECT_NE(rc2, 0);
    EXPECT_NE(out2.find("--state"), std::string::npos) << out2;
}
