// The batch engine (dem/batch, docs/gpu.md) on the damper: the tests' small damper after a cycle
// (foil of bonded particles under the follower pressure, grains, frictional contacts opening and
// closing, the caps as planes, the top cap and the foil's top ring driven by motions), stepped on
// by World and by the batch's host backend. A batch of one gives World's bits over 10,000 steps;
// a batch of 8 mixed cases (two packings, two underpressures, two frictions) gives each case's
// bits, for 1 and 3 threads. The energy ledger too.
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

// The sample of `seed` after its cycle, at underpressure dp [Pa] and grain friction mu, with the
// top cap and the ring pressed down 2 mm over the next 0.03 s (past the 10,000 steps), its energy
// ledger started afresh (or off).
World load(int seed, double dp, double mu, bool energy = true) {
    World w;
    const std::string folder = std::string("s").append(std::to_string(seed));
    dem::load_checkpoint((scratch(folder) / "run.ckpt").string(), w);
    w.params.track_energy = energy;
    w.reset_energy();
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
    const dem::EnergyLedger &p = a.energy(), &q = b.energy();
    ASSERT_EQ(p.steps, q.steps) << what;
    const double pv[] = {p.boundary_work, p.pressure_work, p.gravity_work, p.external_work, p.friction_slip,
                         p.shear_release, p.damping_dissipation, p.viscous_dissipation, p.kinetic, p.elastic_contacts,
                         p.elastic_bonds, p.stored0, p.time, p.t0, p.pending_boundary, p.pending_pressure,
                         p.pending_gravity, p.pending_external, p.pending_damping, p.pending_viscous};
    const double qv[] = {q.boundary_work, q.pressure_work, q.gravity_work, q.external_work, q.friction_slip,
                         q.shear_release, q.damping_dissipation, q.viscous_dissipation, q.kinetic, q.elastic_contacts,
                         q.elastic_bonds, q.stored0, q.time, q.t0, q.pending_boundary, q.pending_pressure,
                         q.pending_gravity, q.pending_external, q.pending_damping, q.pending_viscous};
    for (std::size_t k = 0; k < std::size(pv); ++k) ASSERT_EQ(pv[k], qv[k]) << what << ", ledger entry " << k;
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
    // The ledger booked every source of the damper and balances (docs/energy.md).
    const dem::EnergyLedger& L = mine.energy();
    EXPECT_EQ(L.steps, 10000u);
    for (double v : {L.boundary_work, L.pressure_work, L.friction_slip, L.elastic_contacts, L.elastic_bonds})
        EXPECT_NE(v, 0.0);
    EXPECT_LT(std::abs(L.residual()), 1e-3 * std::max(std::abs(L.boundary_work), std::abs(L.pressure_work)));
    // The handed-back World steps on as if it had never left.
    for (int k = 0; k < 200; ++k) {
        ref.step();
        mine.step();
    }
    expect_same(ref, mine, "after the hand-back");
}

TEST_F(BatchDamper, ABatchOfEightMixedCasesGivesEachCasesBits) {
    ASSERT_TRUE(ok_) << log_;
    struct Case { int seed; double dp, mu; bool energy; };
    std::vector<Case> cases;
    for (int seed : {1, 2})
        for (double dp : {40e3, 80e3})
            for (double mu : {0.2, 0.6}) cases.push_back({seed, dp, mu, cases.size() % 3 != 1});
    const int steps = 3000;
    std::vector<World> ref;
    for (const Case& c : cases) {
        ref.push_back(load(c.seed, c.dp, c.mu, c.energy));
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    // The cases differ: each pair of neighbours in the list ends apart.
    for (std::size_t q = 0; q + 1 < ref.size(); ++q)
        EXPECT_NE(ref[q].wall_force(1), ref[q + 1].wall_force(1)) << q;
    for (const int threads : {1, 3}) {
        std::vector<World> mine;
        for (const Case& c : cases) mine.push_back(load(c.seed, c.dp, c.mu, c.energy));
        dem::batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        dem::batch::step_host(b, threads, steps);
        for (std::size_t q = 0; q < cases.size(); ++q) {
            b.store(q);
            expect_same(ref[q], mine[q], "case " + std::to_string(q) + ", " + std::to_string(threads) + " thread(s)");
        }
    }
}
