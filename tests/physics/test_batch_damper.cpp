// The batch engine (dem/batch, docs/gpu.md) on the damper: the tests' small damper after a cycle
// (foil of bonded particles under the follower pressure, grains, frictional contacts opening and
// closing, the caps as planes, the top cap and the foil's top ring driven by motions), stepped on
// by World and by the batch's host backend. A batch of one gives World's bits over 10,000 steps;
// a batch of 8 mixed cases (two packings, two underpressures, two frictions) gives each case's
// bits, for 1 and 3 threads. The energy ledger too (with normal dashpots in some cases).
#include <gtest/gtest.h>

#include <string>
#include <atomic>
#include <thread>
#include <vector>

#include "batch_compare.h"
#include "cli_helpers.h"
#include "dem/batch/batch_stepper.h"
#include "dem/batch/device_batch.h"
#include "dem/batch/batch_systems.h"
#include "dem/io/checkpoint.h"
#include "dem/world/world.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_batch_damper {

using namespace cli_test;
using dem::World;

namespace {

fs::path scratch(const std::string& name) { return scratch_path("batch_damper_test", name); }

// The small damper of the other tests, one cycle, for a seed: its run.ckpt is the sample after
// the cycle (the motions have ended there; load() drives them on). Mass-scaled as the feature
// tests' damper (cli_helpers.h, kMassScaled): the question here is bits, the batch's against
// World's, its ledger's entries among them; that the ledger closes over a damper's cycles is
// EnergyDamper.BalanceClosesPerCycle's question, at the paper's masses. The suite runs as one
// ctest entry (CMakeLists.txt), so both samples are prepared once.
std::string damper_args(int seed) {
    return "--set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 "
           "--set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=1 "
           "--set process.samples_per_cycle=20 --set simulation.threads=1 --set simulation.seed=" +
           std::to_string(seed) + " --set simulation.dt_safety=0.45 --no-plot --quiet" + kMassScaled;
}

class BatchDamper : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        fs::remove_all(scratch(""));
        fs::create_directories(scratch(""));
        for (int seed : {1, 2}) {
            const std::string folder = scratch(std::string("s").append(std::to_string(seed))).string();
            const Outcome r = run(std::string("damper --out ").append(folder).append(" ").append(damper_args(seed)));
            ok_ = ok_ && r.status == 0;
            if (r.status != 0) log_ += r.output;
        }
    }
    static void TearDownTestSuite() { fs::remove_all(scratch("")); }
    static bool ok_;
    static std::string log_;
};
bool BatchDamper::ok_ = true;
std::string BatchDamper::log_;

World load(int seed, double dp, double mu, bool energy = true, double restitution = 1.0) {
    return batch_test::load_case((scratch(std::string("s").append(std::to_string(seed))) / "run.ckpt").string(), dp, mu, energy,
                                 restitution);
}
using batch_test::Case;
using batch_test::eight_cases;
using batch_test::expect_same;

}  // namespace

TEST_F(BatchDamper, ABatchOfOneGivesTheWorldsBitsOver10000Steps) {
    ASSERT_TRUE(ok_) << log_;
    World ref = load(1, 60e3, 0.3);
    World mine = ref;
    const std::size_t contacts0 = ref.contact_count();
    const uint64_t rebuilds0 = ref.rebuild_count();
    dem::batch::BatchSystems b;
    b.add(mine);
    for (int k = 0; k < 10000; ++k) ref.step();
    dem::batch::step_host(b, 1, 10000);
    b.store(0);
    expect_same(ref, mine, "batch of one");
    // It was a damper's step: contacts, rebuilds, a loaded cap that moved.
    EXPECT_GT(contacts0, 50u);
    EXPECT_GT(ref.rebuild_count(), rebuilds0);
    EXPECT_GT(mine.rebuild_count(), rebuilds0);
    EXPECT_GT(std::abs(ref.wall_force(1).z), 0.1);
    // The ledger booked every source of the damper (its entries are World's bits: expect_same).
    const dem::EnergyLedger& L = mine.energy();
    EXPECT_EQ(L.steps, 10000u);
    for (double v : {L.boundary_work, L.pressure_work, L.friction_slip, L.elastic_contacts, L.elastic_bonds})
        EXPECT_NE(v, 0.0);
    // The handed-back World steps on as if it had never left.
    for (int k = 0; k < 200; ++k) {
        ref.step();
        mine.step();
    }
    expect_same(ref, mine, "after the hand-back");
}

TEST_F(BatchDamper, ABatchOfEightMixedCasesGivesEachCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    std::vector<Case> cases = eight_cases();
    // 1500 steps: every case's neighbour lists rebuilt on the way (checked), at the
    // mass-scaled step.
    const int steps = 1500;
    std::vector<World> ref;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        const uint64_t rebuilds0 = ref.back().rebuild_count();
        for (int k = 0; k < steps; ++k) ref.back().step();
        EXPECT_GT(ref.back().rebuild_count(), rebuilds0) << "case " << ref.size() - 1;
    }
    // The cases differ: each pair of neighbours in the list ends apart.
    for (std::size_t q = 0; q + 1 < ref.size(); ++q)
        EXPECT_NE(ref[q].wall_force(1), ref[q + 1].wall_force(1)) << q;
    for (const int threads : {1, 3}) {
        std::vector<World> mine;
        for (const Case& c : cases) mine.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        dem::batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        dem::batch::step_host(b, threads, steps);
        for (std::size_t q = 0; q < cases.size(); ++q) {
            b.store(q);
            expect_same(ref[q], mine[q], "case " + std::to_string(q) + ", " + std::to_string(threads) + " thread(s)");
        }
    }
}

// The device backend (dem/batch/device_batch.h) on the emulated device: the device's kernels
// compiled by the host compiler, its memory host memory, and the whole exchange with World (the
// touch test's finds placed by World, the frees, the rebuilds and compactions, the ledger's sums)
// as on a GPU. A batch of one gives World's bits over 10,000 steps, then hands back a World that
// steps on as if it had never left; 8 mixed cases give each case's bits.
TEST_F(BatchDamper, TheDeviceBackendOnTheEmulatedDeviceGivesTheWorldsBits) {
    ASSERT_TRUE(ok_) << log_;
    World ref = load(1, 60e3, 0.3);
    World mine = ref;
    const uint64_t rebuilds0 = ref.rebuild_count();
    dem::batch::BatchSystems b;
    b.add(mine);
    dem::batch::DeviceBatch d(dem::batch::dev::emulated_device());
    d.load(b);
    for (int k = 0; k < 10000; ++k) ref.step();
    d.step(b, 10000);
    d.pull(b, 0);
    b.store(0);
    expect_same(ref, mine, "device batch of one (emulated)");
    EXPECT_GT(mine.rebuild_count(), rebuilds0);
    for (int k = 0; k < 200; ++k) {
        ref.step();
        mine.step();
    }
    expect_same(ref, mine, "after the hand-back");
}

TEST_F(BatchDamper, TheDeviceBackendOnTheEmulatedDeviceGivesEachOfEightCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    std::vector<Case> cases = eight_cases();
    // 1500 steps: every case's neighbour lists rebuilt on the way (checked), at the
    // mass-scaled step.
    const int steps = 1500;
    std::vector<World> ref;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        const uint64_t rebuilds0 = ref.back().rebuild_count();
        for (int k = 0; k < steps; ++k) ref.back().step();
        EXPECT_GT(ref.back().rebuild_count(), rebuilds0) << "case " << ref.size() - 1;
    }
    // The dashpots worked where the ledger is on (their forward halves are the device's sums).
    for (std::size_t q = 0; q < cases.size(); ++q)
        if (cases[q].energy && cases[q].restitution < 1.0) {
            EXPECT_GT(ref[q].energy().viscous_dissipation, 0.0) << q;
        }
    // The host parts of the systems shared among 1 and 3 threads: the same bits.
    for (const int threads : {1, 3}) {
        std::vector<World> mine;
        for (const Case& c : cases) mine.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        dem::batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        dem::batch::DeviceBatch d(dem::batch::dev::emulated_device(), threads);
        d.load(b);
        d.step(b, steps);
        for (std::size_t q = 0; q < cases.size(); ++q) {
            d.pull(b, q);
            b.store(q);
            expect_same(ref[q], mine[q], "case " + std::to_string(q) + " (emulated device, " + std::to_string(threads) + " threads)");
        }
    }
}

// BatchStepper on the emulated device: two runs, each in its own thread stepping its World as
// ever, the second joining late and leaving early, give their Worlds' bits.
TEST_F(BatchDamper, TheStepperOnTheEmulatedDeviceGivesEachRunsBits) {
    ASSERT_TRUE(ok_) << log_;
    World ra = load(1, 50e3, 0.3), rb = load(2, 70e3, 0.5, false);
    World a = ra, b = rb;
    for (int k = 0; k < 1500; ++k) ra.step();
    for (int k = 0; k < 700; ++k) rb.step();
    dem::batch::BatchStepper stepper(1, dem::batch::BatchStepper::Backend::kEmulated);
    // a waits at its step 200 until b waits to join (or has joined), so that the two overlap however
    // the threads are scheduled (on a loaded machine b's thread could start after a had finished).
    const auto run = [&](World& w, int skip, int steps, bool first) {
        for (int k = 0; k < skip; ++k) w.step();  // before joining: on its own
        for (int k = 0; k < steps; ++k) {
            if (first && k == 200)
                while (stepper.joining() == 0 && stepper.most_systems() < 2) std::this_thread::yield();
            stepper.compute_forces(w);
            stepper.integrate(w);
        }
        stepper.leave(w);
    };
    std::thread ta([&] { run(a, 0, 1500, true); });
    std::thread tb([&] { run(b, 100, 600, false); });
    ta.join();
    tb.join();
    expect_same(ra, a, "run a (stepper, emulated device)");
    expect_same(rb, b, "run b (stepper, emulated device)");
    EXPECT_EQ(stepper.most_systems(), 2u);
}

// The kernels' work split among a block's threads, as on a GPU: the emulated device with 4 threads
// per system meeting at the kernels' barriers and appending with atomics (the found and opened
// contacts then come in any order: the host sorts them). Each case's bits, 8 mixed cases, over
// 250 steps: 4 threads meeting at every barrier on the 2-core machine took a minute for 1000.
TEST_F(BatchDamper, TheKernelsSplitAmongABlocksThreadsGiveEachCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    std::vector<Case> cases = eight_cases();
    const int steps = 250;
    std::vector<World> ref, mine;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        mine.push_back(ref.back());
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    dem::batch::BatchSystems b;
    for (World& w : mine) b.add(w);
    dem::batch::DeviceBatch d(dem::batch::dev::emulated_device(4), 2);
    d.load(b);
    d.step(b, steps);
    for (std::size_t q = 0; q < cases.size(); ++q) {
        d.pull(b, q);
        b.store(q);
        expect_same(ref[q], mine[q], "case " + std::to_string(q) + " (emulated device, 4 threads per block)");
    }
}

// Chunks (DeviceBatch::run, issue 58): the device runs the steps between events by itself (the
// walls' motion, the clock, the prescribed motions, the rebuild test, the compaction rule, the
// ledger's booking), the host only laying a system out where World would and handing it back at
// its events. World's bits for chunks of 1, 7 and 64 steps, with events at odd steps (two of them
// one step apart), across the rebuilds on the way; then the per-step halves on the same device,
// and the handed-back World, step on as if nothing had happened.
TEST_F(BatchDamper, ChunksOnTheEmulatedDeviceGiveTheWorldsBitsForAnyK) {
    ASSERT_TRUE(ok_) << log_;
    const std::vector<uint64_t> events = {137, 900, 901, 2300, 3000};  // steps from the start
    World ref = load(1, 60e3, 0.3);
    const World start = ref;
    const uint64_t s0 = start.steps, rebuilds0 = start.rebuild_count();
    std::vector<World> at_event;
    for (uint64_t e : events) {
        while (ref.steps < s0 + e) ref.step();
        at_event.push_back(ref);
    }
    EXPECT_GE(ref.rebuild_count(), rebuilds0 + 2);
    for (const int K : {1, 7, 64}) {
        World mine = start;
        dem::batch::BatchSystems b;
        b.add(mine);
        dem::batch::DeviceBatch d(dem::batch::dev::emulated_device());
        d.load(b);
        std::vector<std::exception_ptr> err(1);
        for (std::size_t q = 0; q < events.size(); ++q) {
            d.run(b, {s0 + events[q]}, K, {}, err);
            if (err[0]) std::rethrow_exception(err[0]);
            ASSERT_EQ(mine.steps, s0 + events[q]);
            // What a caller reads at its event is current: the clock, the walls' reactions, the
            // prescribed particles, the ledger (the free particles come with pull()).
            EXPECT_EQ(mine.time, at_event[q].time) << "K = " << K << ", event " << q;
            for (std::size_t k = 0; k < mine.wall_count(); ++k)
                ASSERT_EQ(mine.wall_force(k), at_event[q].wall_force(k)) << "K = " << K << ", event " << q << ", wall " << k;
            for (std::size_t i = 0; i < mine.particles.size(); ++i)
                if (mine.particles.flags[i] & dem::kPrescribed) {
                    ASSERT_EQ(mine.particles.pos[i], at_event[q].particles.pos[i]) << "K = " << K << ", particle " << i;
                    ASSERT_EQ(mine.particles.force[i], at_event[q].particles.force[i]) << "K = " << K << ", particle " << i;
                }
            EXPECT_EQ(mine.energy().boundary_work, at_event[q].energy().boundary_work) << "K = " << K << ", event " << q;
            if (q == 2) {  // a look at everything mid-way, as a checkpoint would
                d.pull(b, 0);
                b.store(0);
                expect_same(at_event[q], mine, "chunks of " + std::to_string(K) + ", event " + std::to_string(q));
            }
        }
        d.pull(b, 0);
        b.store(0);
        expect_same(ref, mine, "chunks of " + std::to_string(K));
        EXPECT_GE(d.relayouts(), 2u) << K;
        // The per-step halves on the same device go on from there, and so does the World.
        World ref2 = ref;
        for (int k = 0; k < 100; ++k) ref2.step();
        d.step(b, 100);
        d.pull(b, 0);
        b.store(0);
        expect_same(ref2, mine, "per-step halves after chunks of " + std::to_string(K));
        for (int k = 0; k < 100; ++k) {
            ref2.step();
            mine.step();
        }
        expect_same(ref2, mine, "the World handed back after chunks of " + std::to_string(K));
    }
}

// Between events the host neither waits nor copies: a chunk is one wait (its results, one copy),
// a layout one more (the system's contacts); nothing per step. 3000 steps in chunks of up to
// 4096: one chunk per event and per layout, whatever the number of steps between them.
TEST_F(BatchDamper, ChunksExchangeNothingPerStepBetweenEvents) {
    ASSERT_TRUE(ok_) << log_;
    World mine = load(1, 60e3, 0.3);
    dem::batch::BatchSystems b;
    b.add(mine);
    dem::batch::DeviceBatch d(dem::batch::dev::emulated_device());
    d.load(b);
    const uint64_t s0 = mine.steps;
    std::vector<std::exception_ptr> err(1);
    const std::vector<uint64_t> events = {1000, 3000};
    for (uint64_t e : events) d.run(b, {s0 + e}, 4096, {}, err);
    ASSERT_FALSE(err[0]);
    ASSERT_EQ(mine.steps, s0 + 3000);
    EXPECT_GE(d.relayouts(), 2u);
    EXPECT_EQ(d.waits(), d.chunks() + d.relayouts());
    EXPECT_LE(d.chunks(), d.relayouts() + events.size());
    // Every copy and launch belongs to a chunk or a layout (about 30 each here: the contacts'
    // arrays one by one), none to a step: this scene lays out every ~26 steps (pressed at
    // 0.067 m/s); the paper's damper at 0.01 m/s every ~2,000.
    EXPECT_LE(d.exchanges(), 40 * (d.chunks() + d.relayouts()));
}

// Eight mixed cases (the ledger on and off, normal dashpots) in chunks of 16 with events, their
// host parts shared among 1 and 3 threads: each case's bits.
TEST_F(BatchDamper, ChunksGiveEachOfEightCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    std::vector<Case> cases = eight_cases();
    const int steps = 1500;
    std::vector<World> ref;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    for (const int threads : {1, 3}) {
        std::vector<World> mine;
        for (const Case& c : cases) mine.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        dem::batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        dem::batch::DeviceBatch d(dem::batch::dev::emulated_device(), threads);
        d.load(b);
        std::vector<std::exception_ptr> err(cases.size());
        // Each case its own events: case q stops at 100 + 37 q, then all at the end.
        std::vector<uint64_t> until(cases.size());
        for (std::size_t q = 0; q < cases.size(); ++q) until[q] = mine[q].steps + 100 + 37 * q;
        d.run(b, until, 16, {}, err);
        for (std::size_t q = 0; q < cases.size(); ++q) until[q] = mine[q].steps - (100 + 37 * q) + steps;
        d.run(b, until, 16, {}, err);
        for (std::size_t q = 0; q < cases.size(); ++q) {
            if (err[q]) std::rethrow_exception(err[q]);
            d.pull(b, q);
            b.store(q);
            expect_same(ref[q], mine[q], "case " + std::to_string(q) + " (chunks, " + std::to_string(threads) + " threads)");
        }
    }
}

// Chunks with each system's kernels split among 4 threads meeting at the barriers (a GPU block's
// shape, the grid barriers of a chunk among them): each case's bits over 150 steps in chunks of 16.
TEST_F(BatchDamper, ChunksSplitAmongABlocksThreadsGiveEachCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    std::vector<Case> cases = eight_cases();
    const int steps = 150;
    std::vector<World> ref, mine;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu, c.energy, c.restitution));
        mine.push_back(ref.back());
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    dem::batch::BatchSystems b;
    for (World& w : mine) b.add(w);
    dem::batch::DeviceBatch d(dem::batch::dev::emulated_device(4), 2);
    d.load(b);
    d.run(b, steps, 16);
    for (std::size_t q = 0; q < cases.size(); ++q) {
        d.pull(b, q);
        b.store(q);
        expect_same(ref[q], mine[q], "case " + std::to_string(q) + " (chunks, 4 threads per block)");
    }
}

// BatchStepper with chunks (compute_forces(world, until, probe)): two runs, each stepping to its
// own events (every 37 and every 53 steps, the second joining late and stepping half by half for a
// while), a probe summing a wall's reaction and some particles' forces over each stretch as a
// caller adding them after each step: each run's bits and each stretch's sums.
TEST_F(BatchDamper, TheStepperInChunksGivesEachRunsBitsAndWindowSums) {
    ASSERT_TRUE(ok_) << log_;
    World ra = load(1, 50e3, 0.3), rb = load(2, 70e3, 0.5, false);
    World a = ra, b = rb;
    // Prescribed particles (the damper's top ring): a World in a batch has their forces current
    // between its halves, as the walls' reactions.
    std::vector<uint32_t> probe_particles;
    for (uint32_t i = 0; i < ra.particles.size() && probe_particles.size() < 4; ++i)
        if (ra.particles.flags[i] & dem::kPrescribed) probe_particles.push_back(i);
    ASSERT_EQ(probe_particles.size(), 4u);
    // The references: stepped alone, the sums formed by hand.
    const auto reference = [&](World& w, int skip, int steps, int every, std::vector<dem::Vec3>& sums) {
        for (int k = 0; k < skip; ++k) w.step();
        dem::Vec3 wall, parts;
        for (int k = 0; k < steps; ++k) {
            w.compute_forces();
            wall += w.wall_force(1);
            dem::Vec3 f;
            for (uint32_t i : probe_particles) f += w.particles.force[i];
            parts += f;
            if ((k + 1) % every == 0) {
                sums.push_back(wall);
                sums.push_back(parts);
                wall = parts = dem::Vec3{};
            }
            w.integrate();
        }
    };
    std::vector<dem::Vec3> sa, sb, ma, mb;
    reference(ra, 0, 1500, 37, sa);
    reference(rb, 100, 600, 53, sb);
    dem::batch::BatchStepper stepper(1, dem::batch::BatchStepper::Backend::kEmulated, 64);
    ASSERT_TRUE(stepper.chunked());
    const auto run = [&](World& w, int skip, int steps, int every, int halves_until, std::vector<dem::Vec3>& sums) {
        for (int k = 0; k < skip; ++k) w.step();
        dem::batch::DeviceBatch::Probe probe;
        probe.particles = probe_particles;
        probe.sums.from = -1.0;
        probe.sums.wall = 1;
        const uint64_t s0 = w.steps;
        int k = 0;
        while (k < steps) {
            // Half by half for a while (the first run's steps before halves_until), else to the
            // stretch's last step in a chunk, then its forces half.
            const int last = std::min(steps, (k / every + 1) * every) - 1;
            const int to = k < halves_until ? k : last;
            stepper.compute_forces(w, s0 + uint64_t(to), &probe);
            // The stretch's sums so far come from the probe; this step's forces from the World.
            probe.sums.wall_sum += w.wall_force(1);
            dem::Vec3 f;
            for (uint32_t i : probe_particles) f += w.particles.force[i];
            probe.sums.particle_sum += f;
            k = to + 1;
            if (k % every == 0) {
                sums.push_back(probe.sums.wall_sum);
                sums.push_back(probe.sums.particle_sum);
                probe.sums.wall_sum = probe.sums.particle_sum = dem::Vec3{};
            }
            stepper.integrate(w);
        }
        stepper.leave(w);
    };
    std::thread ta([&] { run(a, 0, 1500, 37, 300, ma); });
    std::thread tb([&] { run(b, 100, 600, 53, 0, mb); });
    ta.join();
    tb.join();
    expect_same(ra, a, "run a (stepper in chunks)");
    expect_same(rb, b, "run b (stepper in chunks)");
    ASSERT_EQ(ma.size(), sa.size());
    for (std::size_t q = 0; q < sa.size(); ++q) EXPECT_EQ(ma[q], sa[q]) << "run a, stretch " << q / 2;
    ASSERT_EQ(mb.size(), sb.size());
    for (std::size_t q = 0; q < sb.size(); ++q) EXPECT_EQ(mb[q], sb[q]) << "run b, stretch " << q / 2;
}

// `vppdem damper --backend cuda` (issue 58, item 5) on the emulated device: one damper's cycling
// through the device backend, its steps between samples run by the device alone, the window's
// forces summed there: the CPU run's files byte for byte, from the same sample. Without a CUDA
// build (and no emulation) the run is refused before anything is written (exit 2).
TEST_F(BatchDamper, TheDamperCommandOnTheDeviceWritesTheCpuRunsFiles) {
    ASSERT_TRUE(ok_) << log_;
    const std::string from = (scratch("s1") / "prepared.ckpt").string();
    const fs::path cpu = scratch("cmd_cpu"), dev = scratch("cmd_device"), refused = scratch("cmd_refused");
    const Outcome a = run("damper --from " + from + " --out " + cpu.string() + " " + damper_args(1));
    ASSERT_EQ(a.status, 0) << a.output;
    const Outcome b = shell("VPPDEM_EMULATE_DEVICE=1 " + kBinary + " damper --from " + from + " --out " + dev.string() +
                            " --backend cuda " + damper_args(1));
    ASSERT_EQ(b.status, 0) << b.output;
    for (const char* f : {"forces.csv", "cycles.csv", "energy.csv"}) EXPECT_EQ(slurp(cpu / f), slurp(dev / f)) << f;
    EXPECT_FALSE(slurp(cpu / "forces.csv").empty());
    if (!dem::batch::dev::cuda_built()) {
        const Outcome c = shell("env -u VPPDEM_EMULATE_DEVICE " + kBinary + " damper --from " + from + " --out " +
                                refused.string() + " --backend cuda " + damper_args(1));
        EXPECT_EQ(WEXITSTATUS(c.status), 2) << c.output;
        EXPECT_NE(c.output.find("--backend cuda: this vppdem was built without CUDA"), std::string::npos) << c.output;
        EXPECT_FALSE(fs::exists(refused / "forces.csv"));
    }
}

}  // namespace test_batch_damper
