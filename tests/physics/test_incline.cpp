// A sphere on an incline: rolling without slip (a = 5/7 g sin th) below the threshold
// tan th < 7/2 mu, sliding (a = g (sin th - mu cos th)) above it.
// The plane stays horizontal (normal +z); gravity is tilted: g (sin th, 0, -cos th).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "helpers.h"

using namespace dem;
using namespace dem::testing;

namespace incline_test {

struct InclineResult {
    double accel = 0.0;    // [m/s^2] least-squares slope of v_x(t) over the window
    double alpha = 0.0;    // [rad/s^2] least-squares slope of w_y(t) over the window
    double max_vz = 0.0;   // [m/s] largest |v_z| seen (should stay ~0: no bouncing)
};

constexpr double kG = 9.81;
constexpr double kR = 0.01;
constexpr double kYoung = 1e7;  // overlap / r = m g / (E r^2) ~ 1e-4: lever-arm effects negligible

// Sphere resting on the plane z = 0 at its equilibrium overlap m g cos th / kn (so the normal
// spring starts balanced and does not oscillate), at rest; then `settle` steps, then a
// least-squares fit of v_x and w_y against time over `window` steps.
InclineResult run_incline(double theta, double mu, int settle, int window) {
    World w;
    w.add_material(make_material(kYoung, mu));
    w.params.gravity = {kG * std::sin(theta), 0.0, -kG * std::cos(theta)};
    w.params.local_damping = 0.0;  // local damping would scale the downhill force by (1 - l)
    const double m = sphere_mass(2800.0, kR);
    const double kn = kYoung * kR, ks = 0.5 * kn;
    // Stick oscillation of the contact point: effective mass m / (1 + m r^2 / I) = 2/7 m.
    const double omega_t = std::sqrt(ks * 3.5 / m);
    w.params.dt = 0.05 / omega_t;  // ~125 steps per tangential period; normal period longer
    SphereDef s;
    s.radius = kR;
    s.position = {0, 0, kR - m * kG * std::cos(theta) / kn};
    w.add_sphere(s);
    Plane p;
    p.normal = {0, 0, 1};
    w.add_plane(p);

    InclineResult r;
    for (int k = 0; k < settle; ++k) w.step();
    double st = 0, sv = 0, sw = 0, stt = 0, stv = 0, stw = 0;
    for (int k = 0; k < window; ++k) {
        w.step();
        const double t = w.time;  // vel is v(t - dt/2): the offset cancels in the slope
        const double v = w.particles.vel[0].x, om = w.particles.angvel[0].y;
        st += t; sv += v; sw += om; stt += t * t; stv += t * v; stw += t * om;
        r.max_vz = std::max(r.max_vz, std::abs(w.particles.vel[0].z));
    }
    const double n = window;
    const double den = n * stt - st * st;
    r.accel = (n * stv - st * sv) / den;
    r.alpha = (n * stw - st * sw) / den;
    return r;
}


// Rolling: tan 30deg = 0.577 < 7/2 * 0.5 = 1.75 (and < 7/4 mu = 0.875, so even the start-up
// stick oscillation, whose friction peaks at twice the mean 2/7 m g sin th, never slips).
// a = g sin th / (1 + I/(m r^2)) = 5/7 g sin th; alpha = a / r.
// Tolerance 1%: the undamped stick oscillation adds a velocity ripple of amplitude
// (2/7 g sin th)/omega_t to v_x; over omega_t T = 0.05 * 20000 = 1000 rad its effect on the
// fitted slope is < 0.1%; the lever arm r - overlap/2 vs r changes a by ~1e-5.
TEST(PhysicsIncline, RollingAcceleration) {
    const double th = 30.0 * kPi / 180.0, mu = 0.5;
    ASSERT_LT(std::tan(th), 3.5 * mu);
    const InclineResult r = run_incline(th, mu, 500, 20000);
    const double a = 5.0 / 7.0 * kG * std::sin(th);
    EXPECT_LT(report_rel("incline_rolling_accel", r.accel, a, 0.01), 0.01);
    EXPECT_LT(report_rel("incline_rolling_alpha_r", r.alpha * kR, a, 0.01), 0.01);
    EXPECT_LT(r.max_vz, 1e-6);  // started at equilibrium overlap: no bouncing
}

// Sliding: tan 45deg = 1 > 7/2 * 0.2 = 0.7. Friction is mu N with N = m g cos th throughout,
// a = g (sin th - mu cos th); the spin-up alpha = (mu m g cos th) r / I = 5/2 mu g cos th / r.
// The shear spring reaches the Coulomb cap within a few steps of the start; 500 settle steps
// skip that. Tolerance 1% for a (no oscillation once sliding: expect ~1e-6), 1% for alpha
// (the torque arm is r - overlap/2, 5e-5 short of r).
TEST(PhysicsIncline, SlidingAcceleration) {
    const double th = 45.0 * kPi / 180.0, mu = 0.2;
    ASSERT_GT(std::tan(th), 3.5 * mu);
    const InclineResult r = run_incline(th, mu, 500, 20000);
    const double a = kG * (std::sin(th) - mu * std::cos(th));
    const double alpha = 2.5 * mu * kG * std::cos(th) / kR;
    EXPECT_LT(report_rel("incline_sliding_accel", r.accel, a, 0.01), 0.01);
    EXPECT_LT(report_rel("incline_sliding_alpha", r.alpha, alpha, 0.01), 0.01);
    EXPECT_LT(r.max_vz, 1e-6);
}

// Just above the threshold the sphere must slide (a < 5/7 g sin th), just below it must roll:
// discriminates "7/2 mu" from e.g. a wrong inertia factor. tan th = 7/2 mu * (1 +- 15%).
TEST(PhysicsIncline, ThresholdSeparatesRollingFromSliding) {
    const double mu = 0.2;
    const double th_roll = std::atan(0.85 * 3.5 * mu), th_slide = std::atan(1.15 * 3.5 * mu);
    const InclineResult roll = run_incline(th_roll, mu, 2000, 20000);
    const InclineResult slide = run_incline(th_slide, mu, 2000, 20000);
    EXPECT_LT(report_rel("incline_below_threshold_accel", roll.accel, 5.0 / 7.0 * kG * std::sin(th_roll),
                         0.01),
              0.01);
    EXPECT_LT(report_rel("incline_above_threshold_accel", slide.accel,
                         kG * (std::sin(th_slide) - mu * std::cos(th_slide)), 0.01),
              0.01);
}

}  // namespace incline_test
