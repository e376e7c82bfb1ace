// The damper end to end on a small sample (56 grains, 494 foil particles), through the
// vppdem binary as a user runs it: loops, pressure dependence, force split, restart, bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "dem/io/csv.h"

namespace fs = std::filesystem;

namespace {

using namespace cli_test;

const std::string kSmall = kSmallDamper;

fs::path scratch(const std::string& name) { return scratch_path("damper_test", name); }

class Damper : public ::testing::Test {
protected:
    // One preparation at 0.06 MPa for the whole suite; other cases branch from prepared.ckpt.
    static void SetUpTestSuite() {
        fs::remove_all(scratch(""));
        fs::create_directories(scratch(""));
        base_ = run("damper --out " + scratch("dp060").string() + " " + kSmall);
    }
    static void TearDownTestSuite() { fs::remove_all(scratch("")); }
    static Outcome base_;
};
Outcome Damper::base_;

}  // namespace

TEST_F(Damper, RunsAndWritesTheContractFiles) {
    ASSERT_EQ(base_.status, 0) << base_.output;
    const fs::path d = scratch("dp060");
    for (const char* f : {"forces.csv", "cycles.csv", "summary.json", "prepared.ckpt", "run.ckpt"})
        EXPECT_TRUE(fs::exists(d / f)) << f;
    std::ifstream in(d / "forces.csv");
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "time,displacement,force_total,force_grains,force_foil,force_zeroed,cycle");
    std::ifstream in2(d / "cycles.csv");
    std::getline(in2, header);
    EXPECT_EQ(header.substr(0, 40), "cycle,dissipated_energy,W,peak_force,min");
    const auto f = read_columns(d / "forces.csv");
    EXPECT_EQ(f.at("cycle").size(), 2u * 80u);  // samples_per_cycle rows per cycle
}

TEST_F(Damper, LoopsEncloseAPositiveArea) {
    ASSERT_EQ(base_.status, 0) << base_.output;
    const auto c = read_columns(scratch("dp060") / "cycles.csv");
    ASSERT_EQ(c.at("cycle").size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
        std::printf("cycle %zu: energy %.5g J, W %.5g J/m^2, peak %.4g N\n", k + 1, c.at("dissipated_energy")[k],
                    c.at("W")[k], c.at("peak_force")[k]);
        EXPECT_GT(c.at("dissipated_energy")[k], 0.0);
        // W = energy / (pi r_p^2)
        EXPECT_NEAR(c.at("W")[k], c.at("dissipated_energy")[k] / (3.14159265358979 * 0.012 * 0.012),
                    1e-9 * c.at("W")[k]);
    }
}

TEST_F(Damper, GrainAndFoilForcesAddToTheTotal) {
    ASSERT_EQ(base_.status, 0) << base_.output;
    const auto f = read_columns(scratch("dp060") / "forces.csv");
    const double t0 = f.at("force_total")[0];
    for (std::size_t k = 0; k < f.at("force_total").size(); ++k) {
        const double tot = f.at("force_total")[k];
        EXPECT_NEAR(tot, f.at("force_grains")[k] + f.at("force_foil")[k], 1e-9 * (1.0 + std::abs(tot)));
        EXPECT_NEAR(f.at("force_zeroed")[k], tot - t0, 1e-9 * (1.0 + std::abs(tot)));
    }
    // The displacement is a triangle of the amplitude: 0 .. 2 mm .. 0, sampled on the step that
    // reaches each sample time, so within one step of travel (v dt = 0.1 m/s * 2e-6 s).
    double dmax = 0;
    for (double d : f.at("displacement")) dmax = std::max(dmax, d);
    EXPECT_NEAR(dmax, 0.002, 2e-7);
}

TEST_F(Damper, HigherUnderpressureGivesLargerLoopsAndPeakForce) {
    ASSERT_EQ(base_.status, 0) << base_.output;
    const fs::path low = scratch("dp020");
    const Outcome r = run("damper --out " + low.string() + " --from " + (scratch("dp060") / "prepared.ckpt").string() +
                      " --set process.underpressure=0.02e6 " + kSmall);
    ASSERT_EQ(r.status, 0) << r.output;
    const auto hi = read_columns(scratch("dp060") / "cycles.csv");
    const auto lo = read_columns(low / "cycles.csv");
    std::printf("W: %.5g J/m^2 at 0.06 MPa, %.5g J/m^2 at 0.02 MPa; peak %.4g N vs %.4g N\n", hi.at("W")[1],
                lo.at("W")[1], hi.at("peak_force")[1], lo.at("peak_force")[1]);
    EXPECT_GT(hi.at("W")[1], lo.at("W")[1]);
    EXPECT_GT(hi.at("peak_force")[1], lo.at("peak_force")[1]);
}

TEST_F(Damper, RestartFromCheckpointGivesTheSameForces) {
    ASSERT_EQ(base_.status, 0) << base_.output;
    // Branch from the preparation at the same settings, interrupted (killed) part-way, then
    // resumed from its last checkpoint: forces.csv must equal the uninterrupted run's.
    const fs::path d = scratch("restart");
    const std::string args = "damper --out " + d.string() + " --from " +
                             (scratch("dp060") / "prepared.ckpt").string() + " --checkpoint-every 0.3 " + kSmall;
    shell("timeout -s KILL 2.5 " + kBinary + " " + args);
    ASSERT_TRUE(fs::exists(d / "run.ckpt"));
    const Outcome resumed = run("damper --out " + d.string() + " --from " + (d / "run.ckpt").string() + " " + kSmall);
    ASSERT_EQ(resumed.status, 0) << resumed.output;
    EXPECT_EQ(slurp(d / "forces.csv"), slurp(scratch("dp060") / "forces.csv"));
}

TEST_F(Damper, BadConfigsFailClearlyAndWriteNothing) {
    ASSERT_EQ(base_.status, 0) << base_.output;
    struct Case {
        std::string args, must_mention;
    };
    const std::string prepared = (scratch("dp060") / "prepared.ckpt").string();
    const std::vector<Case> cases = {
        {"--set grains.colour=3", "grains.colour"},
        {"--set grains.radius=-0.001", "grains.radius"},
        {"--set process.velocity=0", "process.velocity"},
        {"--set grains.volume_fraction=0.7", "grains.volume_fraction"},  // more grains than fit
        {"--set damper.cycles=2", "damper.cycles"},
        {"--from " + prepared + " --set damper.radius=0.013", "damper.radius"},  // another geometry
        {"--from " + prepared + " --set grains.radius=0.0028", "grains.radius"},
    };
    for (const Case& c : cases) {
        const fs::path d = scratch("bad");
        fs::remove_all(d);
        const Outcome r = run("damper --out " + d.string() + " " + kSmall + " " + c.args);
        EXPECT_NE(r.status, 0) << c.args;
        EXPECT_NE(r.output.find(c.must_mention), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_FALSE(fs::exists(d)) << c.args << ": wrote " << d;
    }
}
