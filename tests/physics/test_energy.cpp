// Energy balance of an undamped granular gas in a closed box of six planes (no gravity).
//   E = sum 1/2 m v^2 + 1/2 I w^2                      (kinetic, synchronous velocities)
//     + sum_pairs 1/2 kn d^2 + sum_walls 1/2 kn d^2    (normal springs, d from positions here)
//     + sum_contacts |Fs|^2 / (2 ks)                   (shear springs, from the contact history)
// Frictionless: E is conserved (leapfrog is symplectic: only an O((w dt)^2) bounded ripple).
// Frictional: Coulomb slip only dissipates, so E never grows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "helpers.h"

using namespace dem;
using namespace dem::testing;

namespace energy_test {

constexpr double kR0 = 0.01;
constexpr double kYoung = 1e7;
constexpr double kL = 0.12;  // box edge [m]

World make_gas(double mu, uint32_t seed) {
    World w;
    w.params.gravity = {0, 0, 0};
    w.params.local_damping = 0.0;
    w.add_material(make_material(kYoung, mu, 1.0));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> rad(0.8 * kR0, 1.2 * kR0), vel(-1.0, 1.0);
    // 4 x 4 x 3 lattice, pitch 2.8 r0 (gap >= 0.4 r0 at the largest radii): 48 spheres,
    // solid fraction ~ 0.11 of the box, close enough for ~10 collisions each in the run.
    const double pitch = 2.8 * kR0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 3; ++k) {
                SphereDef s;
                s.radius = rad(rng);
                s.position = {0.5 * kL + (i - 1.5) * pitch, 0.5 * kL + (j - 1.5) * pitch,
                              0.5 * kL + (k - 1.0) * pitch};
                s.velocity = {vel(rng), vel(rng), vel(rng)};
                s.angular_velocity = {vel(rng) * 50, vel(rng) * 50, vel(rng) * 50};
                w.add_sphere(s);
            }
    for (int d = 0; d < 3; ++d)
        for (int side = 0; side < 2; ++side) {
            Plane p;
            Vec3 n{};
            n[d] = side == 0 ? 1.0 : -1.0;
            p.normal = n;
            Vec3 pt{};
            pt[d] = side == 0 ? 0.0 : kL;
            p.point = pt;
            p.one_sided = true;
            w.add_plane(p);
        }
    // 3% of the critical step of the stiffest pair: ~70+ steps per contact.
    w.params.dt = 0.03 * w.critical_dt();
    return w;
}

// Call right after compute_forces().
double total_energy(const World& w) {
    const Particles& p = w.particles;
    const Material& mat = w.materials[0];
    double e = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 v = w.velocity_at_time(i), om = w.angular_velocity_at_time(i);
        e += 0.5 * p.mass[i] * norm2(v) + 0.5 * (0.4 * p.mass[i] * p.radius[i] * p.radius[i]) * norm2(om);
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            const double d = p.radius[i] + p.radius[j] - norm(p.pos[j] - p.pos[i]);
            if (d > 0.0) {
                const double a = mat.young * p.radius[i], b = mat.young * p.radius[j];
                e += 0.5 * (2.0 * a * b / (a + b)) * d * d;
            }
        }
        for (const Plane& pl : w.planes) {
            const double d = p.radius[i] - dot(p.pos[i] - pl.point, pl.normal);
            if (d > 0.0) e += 0.5 * mat.young * p.radius[i] * d * d;  // kn = E r E r / (E r)
        }
    }
    w.for_each_touching([&](const TouchingContact& c) {
        if (c.phys.ks > 0.0) e += norm2(c.shear) / (2.0 * c.phys.ks);
    });
    return e;
}

struct EnergyRun {
    double e0 = 0, max_rel_dev = 0, max_rel_increase = 0, e_end = 0;
    int onsets = 0;  // contacts that started during the run (pp and wall)
};

EnergyRun run_gas(double mu, int steps, int sample_every) {
    World w = make_gas(mu, 12345);
    EnergyRun r;
    w.compute_forces();
    r.e0 = total_energy(w);
    std::size_t prev_touch = w.contact_count();
    EXPECT_EQ(prev_touch, 0u);
    for (int s = 1; s <= steps; ++s) {
        w.integrate();
        w.compute_forces();
        const std::size_t now = w.contact_count();
        if (now > prev_touch) r.onsets += int(now - prev_touch);
        prev_touch = now;
        if (s % sample_every == 0 || s == steps) {
            const double e = total_energy(w);
            r.max_rel_dev = std::max(r.max_rel_dev, std::abs(e - r.e0) / r.e0);
            r.max_rel_increase = std::max(r.max_rel_increase, (e - r.e0) / r.e0);
            r.e_end = e;
        }
    }
    // Everything stayed in the box.
    for (const Vec3& x : w.particles.pos)
        for (int d = 0; d < 3; ++d) {
            EXPECT_GT(x[d], 0.0);
            EXPECT_LT(x[d], kL);
        }
    return r;
}


// mu = 0: E(t) = E0 within 1% at every sample over 40000 steps (~hundreds of collisions).
// Expected deviation: leapfrog energy ripple ~ (w dt)^2 / 8 with w dt <= 0.03*sqrt(2) -> ~1e-4.
// A missing factor in the force (e.g. kn/2) or a non-conservative integrator shows up as %.
TEST(PhysicsEnergy, FrictionlessGasConservesEnergy) {
    const EnergyRun r = run_gas(0.0, 40000, 50);
    std::cout << "[measure] frictionless_gas: contact onsets=" << r.onsets << "\n";
    EXPECT_GT(r.onsets, 200);  // "many collisions"
    report_abs("frictionless_gas_max_rel_energy_deviation", r.max_rel_dev, 0.01);
    EXPECT_LT(r.max_rel_dev, 0.01);
}

// mu = 0.5, ks = kn / 2: the shear springs store energy |Fs|^2 / (2 ks) and Coulomb slip
// dissipates it. E(t) must never exceed E0 by more than 1% (the ripple above plus the small
// inconsistency between the torque arm r - d/2 and the velocity arm r).
TEST(PhysicsEnergy, FrictionalGasNeverGainsEnergy) {
    const EnergyRun r = run_gas(0.5, 40000, 50);
    std::cout << "[measure] frictional_gas: contact onsets=" << r.onsets
              << " final E/E0=" << r.e_end / r.e0 << "\n";
    EXPECT_GT(r.onsets, 200);
    report_abs("frictional_gas_max_rel_energy_increase", std::max(0.0, r.max_rel_increase), 0.01);
    EXPECT_LT(r.max_rel_increase, 0.01);
    EXPECT_LT(r.e_end, r.e0);  // friction dissipated something over hundreds of collisions
}

}  // namespace energy_test
