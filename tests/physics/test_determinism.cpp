// Results must not depend on the thread count: forces are written per contact and
// gathered per particle in a fixed order, so 1, 2 and 3 threads must give bitwise-identical
// positions, velocities, angular velocities and wall forces. Nor on the processor: every SIMD
// target the kernels are compiled for (AVX-512, AVX2, SSE4, ..., scalar) must give the same
// bits (dem/core/lanes.h).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "dem/kernels/kernels.h"
#include "helpers.h"

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double kBox = 0.1;

// 500 spheres (10 x 10 x 5 jittered lattice, radii 4.5-5 mm, pitch 9.5 mm, jitter 0.1 mm, so
// about half of the neighbour pairs start overlapping by up to 0.7 mm), random velocities,
// a box of 5 one-sided planes, two tilted facets (a ramp) just under the packing and a
// vertical two-sided blade between two columns of it, friction 0.5, gravity, damping 0.2,
// plus bonds and membrane pressure on the top layer, whose material is frictionless with a
// dashpot (so frictionless pairs, dashpots and the energy ledger are covered too).
World make_scene(int threads) {
    World w;
    w.params.threads = threads;
    w.params.gravity = {0, 0, -9.81};
    w.params.local_damping = 0.2;
    w.add_material(make_material(1e6, 0.5, 1.0));
    w.add_material(make_material(2e6, 0.3, 0.6));  // walls: other stiffness, friction, restitution
    w.add_material(make_material(1e6, 0.0, 0.8));  // the membrane layer: frictionless, dashpot
    std::mt19937_64 rng(20240607);
    std::uniform_real_distribution<double> rad(0.0045, 0.005), jit(-0.0001, 0.0001), vel(-0.5, 0.5);
    const double pitch = 0.0095;
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 10; ++i) {
                SphereDef s;
                s.radius = rad(rng);
                s.position = {0.005 + i * pitch + jit(rng), 0.005 + j * pitch + jit(rng),
                              0.013 + k * pitch + jit(rng)};
                s.velocity = {vel(rng), vel(rng), vel(rng) - 0.3};
                s.angular_velocity = {vel(rng) * 20, vel(rng) * 20, vel(rng) * 20};
                if (k == 4) s.material = 2;
                w.add_sphere(s);
            }
    auto plane = [&](Vec3 pt, Vec3 n) {
        Plane p;
        p.point = pt;
        p.normal = n;
        p.material = 1;
        p.one_sided = true;
        w.add_plane(p);
    };
    plane({0, 0, 0}, {0, 0, 1});
    plane({0, 0, 0}, {1, 0, 0});
    plane({kBox, 0, 0}, {-1, 0, 0});
    plane({0, 0, 0}, {0, 1, 0});
    plane({0, kBox, 0}, {0, -1, 0});
    // Ramp z = 0.005 + 0.02 x over the whole floor, as two triangles (normal up).
    auto zf = [](double x) { return 0.005 + 0.02 * x; };
    Facet f;
    f.material = 1;
    f.vertices = {Vec3{0, 0, zf(0)}, Vec3{kBox, 0, zf(kBox)}, Vec3{kBox, kBox, zf(kBox)}};
    w.add_facet(f);
    f.vertices = {Vec3{0, 0, zf(0)}, Vec3{kBox, kBox, zf(kBox)}, Vec3{0, kBox, zf(0)}};
    w.add_facet(f);
    // A vertical two-sided blade in the plane x = x_b halfway between lattice columns 4 and 5
    // (centres 4.75 mm away: the bigger spheres touch it).
    const double xb = 0.005 + 4.5 * pitch;
    f.vertices = {Vec3{xb, 0.01, 0.01}, Vec3{xb, 0.09, 0.01}, Vec3{xb, 0.05, 0.07}};
    w.add_facet(f);
    // The top layer (k = 4) is a bonded membrane patch: bonds between lattice neighbours
    // (rest length = current distance) and a follower pressure on every other interior node,
    // so the bond and pressure kernels are covered too.
    auto idx = [](int i, int j, int k) { return uint32_t((k * 10 + j) * 10 + i); };
    const double kb = 1e6 * 0.005;
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
            if (i + 1 < 10) w.add_bond(idx(i, j, 4), idx(i + 1, j, 4), kb, 0.5 * kb);
            if (j + 1 < 10) w.add_bond(idx(i, j, 4), idx(i, j + 1, 4), kb, 0.5 * kb);
        }
    for (int j = 2; j < 9; j += 2)
        for (int i = 2; i < 9; i += 2)
            w.pressure.nodes.push_back(
                {idx(i, j, 4), {idx(i + 1, j, 4), idx(i, j + 1, 4), idx(i - 1, j, 4), idx(i, j - 1, 4)}});
    w.pressure.dp = 10.0;  // [Pa] force 4 h^2 dp ~ m g per node
    w.params.dt = 0.2 * w.critical_dt();
    w.params.track_energy = true;  // its sums run in parallel over fixed blocks
    return w;
}

struct Snapshot {
    std::vector<double> values;  // pos, vel, angvel of every particle, wall forces, energy ledger
    uint64_t rebuilds = 0;
    std::size_t contacts = 0;
};

Snapshot run(int threads, int steps) {
    World w = make_scene(threads);
    for (int s = 0; s < steps; ++s) w.step();
    w.compute_forces();
    Snapshot snap;
    for (std::size_t i = 0; i < w.particles.size(); ++i)
        for (const Vec3* v : {&w.particles.pos[i], &w.particles.vel[i], &w.particles.angvel[i]})
            for (int d = 0; d < 3; ++d) snap.values.push_back((*v)[d]);
    for (std::size_t k = 0; k < w.wall_count(); ++k)
        for (int d = 0; d < 3; ++d) {
            snap.values.push_back(w.wall_force(k)[d]);
            snap.values.push_back(w.wall_torque(k)[d]);
        }
    const EnergyLedger& e = w.energy();
    for (double v : {e.boundary_work, e.pressure_work, e.gravity_work, e.friction_slip, e.shear_release,
                     e.damping_dissipation, e.viscous_dissipation, e.kinetic, e.elastic_contacts, e.elastic_bonds})
        snap.values.push_back(v);
    snap.rebuilds = w.rebuild_count();
    snap.contacts = w.contact_count();
    return snap;
}

}  // namespace

TEST(PhysicsDeterminism, BitwiseIdenticalAcrossThreadCounts) {
    constexpr int kSteps = 300;
    const Snapshot ref = run(1, kSteps);
    // The scene must exercise what could break determinism: many contacts, wall and facet
    // contacts, and candidate-list rebuilds (history carried across merges).
    std::cout << "[measure] determinism scene: contacts=" << ref.contacts << " rebuilds=" << ref.rebuilds
              << "\n";
    EXPECT_GT(ref.contacts, 100u);
    EXPECT_GE(ref.rebuilds, 3u);
    for (double v : ref.values) ASSERT_TRUE(std::isfinite(v));
    for (int threads : {2, 3}) {
        const Snapshot s = run(threads, kSteps);
        ASSERT_EQ(s.values.size(), ref.values.size());
        EXPECT_EQ(s.rebuilds, ref.rebuilds) << "threads=" << threads;
        EXPECT_EQ(s.contacts, ref.contacts) << "threads=" << threads;
        std::size_t mismatches = 0, first = s.values.size();
        for (std::size_t k = 0; k < s.values.size(); ++k)
            if (std::bit_cast<uint64_t>(s.values[k]) != std::bit_cast<uint64_t>(ref.values[k])) {
                ++mismatches;
                if (first == s.values.size()) first = k;
            }
        std::cout << "[measure] determinism threads=" << threads << ": bitwise mismatches=" << mismatches
                  << " of " << s.values.size() << " (tol 0)\n";
        EXPECT_EQ(mismatches, 0u) << "threads=" << threads;
        if (first < s.values.size()) {
            EXPECT_EQ(s.values[first], ref.values[first]) << "first mismatch at value " << first;
        }
    }
}

// Each SIMD target of the kernels gives the same bits as the others (and the scalar target is
// the plain double arithmetic of the lane templates).
TEST(PhysicsDeterminism, BitwiseIdenticalAcrossSimdTargets) {
    constexpr int kSteps = 300;
    const std::vector<int64_t> targets = kernels::available_targets();
    // With one target there is nothing to compare and the loop below would pass without a
    // check: the build always carries the scalar target beside the machine's SIMD ones (AVX3
    // AVX2 SSE4 SSSE3 SCALAR on an AVX-512 machine), so fewer than two means a broken dispatch.
    ASSERT_GE(targets.size(), 2u) << "only one SIMD target built or supported: the comparison would be vacuous";
    std::cout << "[measure] SIMD targets:";
    for (int64_t t : targets) std::cout << " " << kernels::target_name(t);
    std::cout << "\n";
    kernels::restrict_to_target(targets.front());
    const Snapshot ref = run(2, kSteps);
    for (std::size_t k = 1; k < targets.size(); ++k) {
        kernels::restrict_to_target(targets[k]);
        const Snapshot s = run(2, kSteps);
        ASSERT_EQ(s.values.size(), ref.values.size());
        std::size_t mismatches = 0;
        for (std::size_t v = 0; v < s.values.size(); ++v)
            mismatches += std::bit_cast<uint64_t>(s.values[v]) != std::bit_cast<uint64_t>(ref.values[v]);
        std::cout << "[measure] " << kernels::target_name(targets[k]) << " vs " << kernels::target_name(targets.front())
                  << ": bitwise mismatches=" << mismatches << " of " << s.values.size() << " (tol 0)\n";
        EXPECT_EQ(mismatches, 0u) << kernels::target_name(targets[k]);
        EXPECT_EQ(s.contacts, ref.contacts) << kernels::target_name(targets[k]);
    }
    kernels::restrict_to_target(0);
}
