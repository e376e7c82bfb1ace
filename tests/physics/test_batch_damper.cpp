// The batch engine (dem/batch, docs/gpu.md) on the damper: the tests' small damper after a cycle
// (foil of bonded particles under the follower pressure, grains, frictional contacts opening and
// closing, the caps as planes, the top cap and the foil's top ring driven by motions), stepped on
// by World and by the batch's host backend. A batch of one gives World's bits over 10,000 steps;
// a batch of 8 mixed cases (two packings, two underpressures, two frictions) gives each case's
// bits, for 1 and 3 threads.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli_helpers.h"
#include "dem/batch/batch_systems.h"
#include "dem/io/checkpoint.h"
#include "dem/world/world.h"

using namespace cli_test;
using dem::World;

namespace {

fs::path scratch(const std::string& name) { return scratch_path("batch_damper_test", name); }

// The small damper of the other tests, one cycle, for a seed: its run.ckpt is the sample after
// the cycle (the motions have ended there; load() drives them on).
std::string damper_args(int seed) {
    return "--set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 "
           "--set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=1 "
           "--set process.samples_per_cycle=20 --set simulation.threads=1 --set simulation.seed=" +
           std::to_string(seed) + " --no-plot --quiet";
}

class BatchDamper : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        fs::remove_all(scratch(""));
        fs::create_directories(scratch(""));
        for (int seed : {1, 2}) {
            const Outcome r = run("damper --out " + scratch("s" + std::to_string(seed)).string() + " " + damper_args(seed));
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

// The sample of `seed` after its cycle, at underpressure dp [Pa] and grain friction mu, with the
// top cap and the ring pressed down 2 mm over the next 0.03 s (past the 10,000 steps), without
// the energy ledger (the batch does not keep one yet).
World load(int seed, double dp, double mu) {
    World w;
    dem::load_checkpoint((scratch("s" + std::to_string(seed)) / "run.ckpt").string(), w);
    w.params.track_energy = false;
    w.pressure.dp = dp;
    w.materials[0].friction = mu;
    w.invalidate_contact_physics();
    const double t1 = w.time + 0.03;
    const auto press = [&](dem::Motion& m) {
        if (m.history.empty()) return;
        m.history.push_back({t1, m.history.back().displacement + dem::Vec3{0, 0, -0.002}});
    };
    for (dem::Plane& p : w.planes) press(p.motion);
    for (dem::Motion& m : w.motions) press(m);
    return w;
}

void expect_same(const World& a, const World& b, const std::string& what) {
    ASSERT_EQ(a.particles.size(), b.particles.size()) << what;
    ASSERT_EQ(a.steps, b.steps) << what;
    ASSERT_EQ(a.time, b.time) << what;
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
        ASSERT_EQ(a.particles.pos[i], b.particles.pos[i]) << what << ", particle " << i;
        ASSERT_EQ(a.particles.vel[i], b.particles.vel[i]) << what << ", particle " << i;
        ASSERT_EQ(a.particles.angvel[i], b.particles.angvel[i]) << what << ", particle " << i;
        ASSERT_EQ(a.particles.force[i], b.particles.force[i]) << what << ", particle " << i;
    }
    ASSERT_EQ(a.contact_count(), b.contact_count()) << what;
    for (std::size_t k = 0; k < a.wall_count(); ++k) ASSERT_EQ(a.wall_force(k), b.wall_force(k)) << what << ", wall " << k;
    for (std::size_t k = 0; k < a.bonds().size(); ++k) ASSERT_EQ(a.bonds().shear[k], b.bonds().shear[k]) << what;
}

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
    // The handed-back World steps on as if it had never left.
    for (int k = 0; k < 200; ++k) {
        ref.step();
        mine.step();
    }
    expect_same(ref, mine, "after the hand-back");
}

TEST_F(BatchDamper, ABatchOfEightMixedCasesGivesEachCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    struct Case { int seed; double dp, mu; };
    std::vector<Case> cases;
    for (int seed : {1, 2})
        for (double dp : {40e3, 80e3})
            for (double mu : {0.2, 0.6}) cases.push_back({seed, dp, mu});
    const int steps = 3000;
    std::vector<World> ref;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu));
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    // The cases differ: each pair of neighbours in the list ends apart.
    for (std::size_t q = 0; q + 1 < ref.size(); ++q)
        EXPECT_NE(ref[q].wall_force(1), ref[q + 1].wall_force(1)) << q;
    for (const int threads : {1, 3}) {
        std::vector<World> mine;
        for (const Case& c : cases) mine.push_back(load(c.seed, c.dp, c.mu));
        dem::batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        dem::batch::step_host(b, threads, steps);
        for (std::size_t q = 0; q < cases.size(); ++q) {
            b.store(q);
            expect_same(ref[q], mine[q], "case " + std::to_string(q) + ", " + std::to_string(threads) + " thread(s)");
        }
    }
}
