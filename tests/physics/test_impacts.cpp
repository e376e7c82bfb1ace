// Normal impacts against closed-form answers of the linear spring(-dashpot) contact:
//  - elastic contact duration t_c = pi sqrt(m*/kn) and exit speed = entry speed,
//  - restitution through the normal dashpot: v_out / v_in = e,
//  - Yade's local (non-viscous) damping: v_out / v_in = sqrt((1 - l) / (1 + l)).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "helpers.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_impacts {

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double kR = 0.01;    // [m]
constexpr double kV = 0.5;     // [m/s] approach speed (each sphere, or the sphere on a plane)
// Steps per analytic contact duration; not an integer, so the counted duration is not
// trivially exact (it is rounded to whole steps: error < 1/1234 < 0.1%).
constexpr double kSteps = 1234.5;

}  // namespace

// 1a. Two equal spheres, head-on. m* = m/2, kn = 2 (E r)(E r) / (2 E r) = E r.
// Tolerances: the contact is counted in whole steps, so the duration has an error of at most
// one step = 1/1234 of t_c (0.08%), leapfrog's frequency error is (w dt)^2/24 ~ 4e-7; 1% leaves
// room but still catches a wrong mass (sqrt 2 = 41%) or stiffness convention (factor 2).
// Leapfrog conserves the energy of a linear oscillator up to O((w dt)^2) = 1e-5 after the
// contact, so the exit speed must match within 0.5%.
TEST(PhysicsImpact, ElasticSphereSphereDurationAndSpeed) {
    const Material mat = make_material(1e7);
    World w = two_sphere_world(mat, kR, kV, kSteps);
    const double m = sphere_mass(mat.density, kR);
    const double kn = mat.young * kR;
    const double tc = kPi * std::sqrt(0.5 * m / kn);
    const ImpactResult r = run_impact(w, 5 * uint64_t(kSteps));
    ASSERT_TRUE(r.separated);
    EXPECT_LT(report_rel("sphere_sphere_duration", r.duration, tc, 0.01), 0.01);
    // After the impact the spheres swap velocities: a moves with -v, b with +v.
    EXPECT_LT(report_rel("sphere_sphere_exit_speed_a", -r.vel_after[0].x, kV, 0.005), 0.005);
    EXPECT_LT(report_rel("sphere_sphere_exit_speed_b", r.vel_after[1].x, kV, 0.005), 0.005);
    EXPECT_EQ(r.vel_after[0].y, 0.0);
    EXPECT_EQ(r.vel_after[0].z, 0.0);
}

// 1b. Sphere on a fixed plane of the same material: m* = m, kn = E r (the wall counts as a
// sphere of the particle's radius). Same tolerances as above.
TEST(PhysicsImpact, ElasticSpherePlaneDurationAndSpeed) {
    const Material mat = make_material(1e7);
    World w = sphere_plane_world(mat, kR, kV, kSteps);
    const double m = sphere_mass(mat.density, kR);
    const double kn = mat.young * kR;
    const double tc = kPi * std::sqrt(m / kn);
    const ImpactResult r = run_impact(w, 5 * uint64_t(kSteps));
    ASSERT_TRUE(r.separated);
    EXPECT_LT(report_rel("sphere_plane_duration", r.duration, tc, 0.01), 0.01);
    EXPECT_LT(report_rel("sphere_plane_exit_speed", r.vel_after[0].z, kV, 0.005), 0.005);
}

// 1c. Sphere on a stiffer plane material: kn = 2 E1 r E2 r / (E1 r + E2 r) (springs in series).
TEST(PhysicsImpact, ElasticSpherePlaneMixedStiffness) {
    const Material mat = make_material(1e7);
    World w = sphere_plane_world(mat, kR, kV, kSteps);
    Material wall = make_material(4e7);
    w.planes[0].material = w.add_material(wall);
    const double m = sphere_mass(mat.density, kR);
    const double kn = 2.0 * 1e7 * kR * 4e7 * kR / (1e7 * kR + 4e7 * kR);  // = 1.6 E r
    const double tc = kPi * std::sqrt(m / kn);
    w.params.dt = tc / kSteps;
    const ImpactResult r = run_impact(w, 5 * uint64_t(kSteps));
    ASSERT_TRUE(r.separated);
    EXPECT_LT(report_rel("sphere_plane_mixed_duration", r.duration, tc, 0.01), 0.01);
    EXPECT_LT(report_rel("sphere_plane_mixed_exit_speed", r.vel_after[0].z, kV, 0.005), 0.005);
}

// 2. Restitution through the normal dashpot cn = 2 zeta sqrt(m* kn), with
// e = exp(-zeta pi / sqrt(1 - zeta^2)) exact for the continuous linear spring-dashpot when the
// contact ends at zero overlap. The leapfrog dashpot sees v(t - dt/2), a lag that shifts the
// effective stiffness/damping by O(zeta w dt) ~ 1e-3 at ~1200 steps per contact: tolerance 1%.
// Two stiffnesses 100x apart show the ratio does not depend on kn; both pair kinds use
// their own reduced mass (m/2 for the sphere pair, m for the plane).
class RestitutionTest : public ::testing::TestWithParam<std::tuple<double, double, bool>> {};

TEST_P(RestitutionTest, ExitOverEntrySpeedEqualsE) {
    const auto [e, young, plane] = GetParam();
    const Material mat = make_material(young, 0.0, e);
    World w = plane ? sphere_plane_world(mat, kR, kV, kSteps) : two_sphere_world(mat, kR, kV, kSteps);
    // Same dt for both stiffnesses (~1200 steps per contact for the stiff one, ~12000 for the
    // soft one), so the two runs are not merely rescaled copies of each other.
    const double m_star = sphere_mass(mat.density, kR) * (plane ? 1.0 : 0.5);
    w.params.dt = kPi * std::sqrt(m_star / (1e8 * kR)) / kSteps;
    const ImpactResult r = run_impact(w, 20 * uint64_t(kSteps) * 10);
    ASSERT_TRUE(r.separated);
    const double ratio = plane ? r.vel_after[0].z / kV : r.vel_after[1].x / kV;
    const std::string name = std::string(plane ? "plane" : "pair") + "_e" + fmt(e) + "_E" + fmt(young);
    EXPECT_LT(report_rel("restitution_" + name, ratio, e, 0.01), 0.01);
    if (!plane) {
        // Momentum is conserved exactly (equal and opposite contact forces).
        EXPECT_NEAR(r.vel_after[0].x + r.vel_after[1].x, 0.0, 1e-12);
    }
}

INSTANTIATE_TEST_SUITE_P(PhysicsImpact, RestitutionTest,
                         ::testing::Combine(::testing::Values(0.2, 0.5, 0.8),
                                            ::testing::Values(1e6, 1e8),
                                            ::testing::Bool()));

// 3. Local damping (no dashpot, e = 1 material) on a sphere hitting a fixed plane along z.
// While the sphere is loading (force and velocity opposite), the force is scaled by (1 + l);
// while unloading by (1 - l). Energy: 1/2 m v0^2 = 1/2 (1 + l) kn d^2 and
// 1/2 m v1^2 = 1/2 (1 - l) kn d^2, so v1/v0 = sqrt((1 - l) / (1 + l)).
// The switch happens at v = 0 where a one-step timing error costs only O((w dt)^2): 1% tolerance.
class LocalDampingImpactTest : public ::testing::TestWithParam<double> {};

TEST_P(LocalDampingImpactTest, ExitSpeedRatio) {
    const double l = GetParam();
    const Material mat = make_material(1e7);
    World w = sphere_plane_world(mat, kR, kV, kSteps);
    w.params.local_damping = l;
    const ImpactResult r = run_impact(w, 5 * uint64_t(kSteps));
    ASSERT_TRUE(r.separated);
    const double expected = std::sqrt((1.0 - l) / (1.0 + l));
    EXPECT_LT(report_rel("local_damping_l" + fmt(l), r.vel_after[0].z / kV, expected, 0.01),
              0.01);
    // No motion appears in the undamped-free directions.
    EXPECT_EQ(r.vel_after[0].x, 0.0);
    EXPECT_EQ(r.vel_after[0].y, 0.0);
}

INSTANTIATE_TEST_SUITE_P(PhysicsImpact, LocalDampingImpactTest, ::testing::Values(0.1, 0.3));

// The normal dashpot is not clipped (docs/model.md, "dashpot"): a decision, pinned here. With
// e = 0.5 the total normal force at the end of an impact on a plane pulls, by the dashpot part
// alone, F_end = -cn v_out = -cn e v_in (the overlap is zero there), and that is the smallest
// force of the impact (4 zeta^2 < 1: the force still falls as the overlap closes). The elastic
// part never pulls: the force at the deepest overlap equals kn d_max + 0 (vn = 0 there).
// Tolerance 1%: the last step's overlap is at most v_out dt = 1/1234 of the travel.
TEST(PhysicsImpact, DashpotPullsAtTheEndOfAnImpactAsDocumented) {
    Material mat = make_material(1e7, 0.0, 0.5);
    World w = sphere_plane_world(mat, kR, kV, kSteps);
    const double m = sphere_mass(mat.density, kR), kn = mat.young * kR;
    const double zeta = damping_ratio_from_restitution(0.5);
    const double cn = 2.0 * zeta * std::sqrt(m * kn);
    double fmin = 0.0, fmax = 0.0, vout = 0.0;
    bool touched = false;
    for (int s = 0; s < 5 * int(kSteps); ++s) {
        w.compute_forces();
        const double fz = -w.wall_force(0).z;  // force of the plane on the sphere
        if (w.contact_count() > 0) {
            touched = true;
            fmin = std::min(fmin, fz);
            fmax = std::max(fmax, fz);
        } else if (touched) {
            vout = w.particles.vel[0].z;
            break;
        }
        w.integrate();
    }
    ASSERT_TRUE(touched);
    EXPECT_LT(report_rel("dashpot_exit_speed_over_e", vout, 0.5 * kV, 0.01), 0.01);
    EXPECT_LT(fmin, 0.0);  // it pulls
    EXPECT_LT(report_rel("dashpot_end_pull", -fmin, cn * 0.5 * kV, 0.01), 0.01);
    EXPECT_LT(-fmin, 0.3 * fmax);  // a short pull, here 26% of the peak force
}

}  // namespace test_impacts
