// The batch engine (dem/batch, docs/gpu.md) on systems without contacts: its host backend over a
// batch gives each World's bits. Spheres in free flight (gravity, external forces, local damping)
// and bonded membranes under a follower pressure, 10,000 steps, batches of one and of three, 1 to
// 3 threads. The damper's systems (contacts, walls, motions): tests/physics/test_batch_damper.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <random>
#include <thread>
#include <vector>

#include "dem/batch/batch_stepper.h"
#include "dem/batch/batch_systems.h"
#include "dem/world/world.h"

using namespace dem;

namespace {

// n spheres on a widely spaced lattice (they never touch), random velocities and spins; every
// third one pushed by an external force.
World free_flight(uint64_t seed, int n, double lambda, Vec3 g) {
    World w;
    w.params.gravity = g;
    w.params.local_damping = lambda;
    w.params.dt = 1e-5;
    Material m;
    m.name = "m";
    m.density = 2500.0;
    m.young = 1e7;
    w.add_material(m);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < n; ++k) {
        SphereDef d;
        d.position = {0.5 * (k % 10), 0.5 * ((k / 10) % 10), 0.5 * (k / 100)};
        d.radius = 0.002 + 0.001 * (u(rng) + 1.0);
        d.velocity = {u(rng), u(rng), u(rng)};
        d.angular_velocity = {50 * u(rng), 50 * u(rng), 50 * u(rng)};
        w.add_sphere(d);
    }
    w.particles.ext_force.assign(w.particles.size(), Vec3{});
    for (std::size_t i = 0; i < w.particles.size(); i += 3) w.particles.ext_force[i] = {1e-3 * u(rng), 2e-3, -1e-3};
    return w;
}

void expect_same(const World& a, const World& b) {
    ASSERT_EQ(a.particles.size(), b.particles.size());
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
        ASSERT_EQ(a.particles.pos[i], b.particles.pos[i]) << i;
        ASSERT_EQ(a.particles.vel[i], b.particles.vel[i]) << i;
        ASSERT_EQ(a.particles.angvel[i], b.particles.angvel[i]) << i;
    }
}

}  // namespace

TEST(Batch, FreeFlightOfABatchGivesEachWorldsBits) {
    const int steps = 10000;
    for (const int threads : {1, 3}) {
        std::vector<World> ref;
        ref.push_back(free_flight(1, 120, 0.3, {0, 0, -9.81}));
        ref.push_back(free_flight(2, 64, 0.0, {0, 0, -9.81}));
        ref.push_back(free_flight(3, 200, 0.8, {1.0, -2.0, -5.0}));
        std::vector<World> mine = ref;
        batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        ASSERT_EQ(b.systems(), 3u);
        for (World& w : ref)
            for (int k = 0; k < steps; ++k) w.step();
        batch::step_host(b, threads, steps);
        for (std::size_t s = 0; s < ref.size(); ++s) {
            b.store(s);
            expect_same(ref[s], mine[s]);
            EXPECT_EQ(ref[s].steps, mine[s].steps);
            EXPECT_EQ(ref[s].time, mine[s].time);
        }
        // Damping and gravity did act: the damped systems moved differently from a free parabola.
        EXPECT_NE(ref[0].particles.vel[1], ref[1].particles.vel[1]);
    }
}

TEST(Batch, ABatchOfOneIsTheWorldAndClumpsAreRefusedForNow) {
    World w = free_flight(7, 50, 0.2, {0, 0, -9.81});
    World out = w;
    batch::BatchSystems b;
    b.add(out);
    for (int k = 0; k < 10000; ++k) {
        w.step();
        batch::step_host(b, 2);
    }
    b.store(0);
    expect_same(w, out);
    World c;
    Material m;
    m.name = "m";
    m.density = 1000.0;
    m.young = 1e7;
    c.add_material(m);
    c.add_clump(builtin_clump_shape("dimer", 1e-3), ClumpDef{});
    EXPECT_THROW(b.add(c), std::invalid_argument);
}

namespace {

// A bonded net (n x n spheres 2.2 radii apart, bonds to the right and upper neighbours, the
// border fixed) under gravity and a follower pressure on the interior nodes: the foil's physics
// without contacts (the diagonal neighbours stay 3.1 radii apart).
World membrane(int n, double dp, double lambda, double kn) {
    World w;
    w.params.local_damping = lambda;
    Material m;
    m.name = "foil";
    m.density = 1000.0;
    m.young = 1e6;
    w.add_material(m);
    const double r = 1e-3, a = 2.2e-3;
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix) {
            SphereDef d;
            d.position = {a * ix, a * iy, 0.0};
            d.radius = r;
            if (ix == 0 || iy == 0 || ix == n - 1 || iy == n - 1) d.flags = kFixed;
            w.add_sphere(d);
        }
    const auto id = [n](int ix, int iy) { return uint32_t(iy * n + ix); };
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix) {
            if (ix + 1 < n) w.add_bond(id(ix, iy), id(ix + 1, iy), kn, 0.5 * kn);
            if (iy + 1 < n) w.add_bond(id(ix, iy), id(ix, iy + 1), kn, 0.5 * kn);
        }
    for (int iy = 1; iy + 1 < n; ++iy)
        for (int ix = 1; ix + 1 < n; ++ix)
            w.pressure.nodes.push_back({id(ix, iy), {id(ix + 1, iy), id(ix, iy + 1), id(ix - 1, iy), id(ix, iy - 1)}});
    w.pressure.dp = dp;
    w.params.dt = 0.2 * w.critical_dt();
    return w;
}

}  // namespace

// The membrane's step in a batch: pressure, bonds with shear history, World's gather order and
// the leapfrog, 10,000 steps, four different membranes (pressures, damping, stiffness, the bonds'
// arm) and 1 or 2 threads: each World's bits. Without the gather's order (a plain running sum) it fails.
TEST(Batch, BondedMembranesUnderPressureGiveEachWorldsBits) {
    for (const int threads : {1, 2}) {
        std::vector<World> ref;
        ref.push_back(membrane(12, 200.0, 0.2, 1e3));
        ref.push_back(membrane(9, 50.0, 0.0, 3e3));
        ref.push_back(membrane(15, 0.0, 0.5, 2e3));
        ref.push_back(membrane(9, 100.0, 0.1, 2e3));  // bonds 2.2 r long, springs at the bond point
        ref.back().set_bond_arm(BondArm::kBondPoint);
        std::vector<World> mine = ref;
        batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        for (World& w : ref)
            for (int k = 0; k < 10000; ++k) w.step();
        batch::step_host(b, threads, 10000);
        for (std::size_t s = 0; s < ref.size(); ++s) {
            EXPECT_EQ(ref[s].contact_count(), 0u);
            b.store(s);
            expect_same(ref[s], mine[s]);
        }
        // The pressure and gravity did deform it: the centre sagged.
        EXPECT_LT(ref[0].particles.pos[6 * 12 + 6].z, -1e-5);
    }
}

// BatchStepper (lockstep runs): four runs in their own threads, each stepping its World through
// one stepper for a different number of steps (so they leave at different times), one of them
// joining late, one handing its state back mid-run (sync) to read it, one leaving between the
// halves of a step (as a run that threw there): each World ends with the bits of stepping alone,
// whatever the threads' timing.
TEST(Batch, LockstepRunsJoinAndLeaveAndKeepEachWorldsBits) {
    std::vector<World> ref, mine;
    ref.push_back(membrane(10, 120.0, 0.2, 1e3));
    ref.push_back(free_flight(11, 80, 0.3, {0, 0, -9.81}));
    ref.push_back(membrane(8, 0.0, 0.0, 2e3));
    ref.push_back(free_flight(12, 40, 0.0, {0.5, 0, -3.0}));
    mine = ref;
    const int steps[] = {3000, 1200, 2500, 700};
    for (std::size_t s = 0; s < ref.size(); ++s)
        for (int k = 0; k < steps[s]; ++k) ref[s].step();
    // Run 2 leaves between the halves of its last step (as a run that threw there).
    ref[2].compute_forces();
    batch::BatchStepper stepper(2);
    std::vector<Vec3> seen(ref.size());
    const Vec3 start = mine[1].particles.pos[0];
    std::vector<std::thread> runs;
    for (std::size_t s = 0; s < mine.size(); ++s)
        runs.emplace_back([&, s] {
            if (s == 3) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // joins late
            for (int k = 0; k < steps[s]; ++k) {
                // Run 0 waits at its step 100 until another run waits to join (or has joined), so
                // that the runs overlap however the threads are scheduled (on a loaded machine the
                // others' threads could start after run 0 had ended).
                if (s == 0 && k == 100)
                    while (stepper.joining() == 0 && stepper.most_systems() < 2) std::this_thread::yield();
                stepper.compute_forces(mine[s]);
                stepper.integrate(mine[s]);
                if (s == 2 && k + 1 == steps[s]) {
                    stepper.compute_forces(mine[s]);
                    break;
                }
                if (k == steps[s] / 2) {
                    stepper.sync(mine[s]);
                    seen[s] = mine[s].particles.pos[0];
                }
            }
            stepper.leave(mine[s]);
        });
    for (auto& t : runs) t.join();
    for (std::size_t s = 0; s < ref.size(); ++s) {
        expect_same(ref[s], mine[s]);
        EXPECT_EQ(ref[s].steps, mine[s].steps);
    }
    for (std::size_t i = 0; i < ref[2].particles.size(); ++i) ASSERT_EQ(ref[2].particles.force[i], mine[2].particles.force[i]) << i;
    EXPECT_GT(stepper.most_systems(), 1u);
    // sync() handed the state back mid-run (without it World's arrays hold the start).
    EXPECT_NE(seen[1], start);
}
