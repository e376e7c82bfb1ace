// The damper's state blob in its checkpoints (vpp::damper_detail::RunState): it reads back what
// it wrote, non-finite numbers included, and refuses a damaged blob with the checkpoint's path
// (fuzz/fuzz_checkpoint.cpp found a stage outside the enum indexing past stage_name()).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "vpp/damper/run.h"

using vpp::damper_detail::RunState;
using vpp::damper_detail::Stage;

namespace {

std::string refusal(const std::string& blob) {
    try {
        RunState::load(blob, "dir/run.ckpt");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

// One energy.csv row with a NaN residual (a run that went wrong).
void EnergyRowForTest(RunState& s) {
    vpp::damper_detail::EnergyRow e{};
    for (int k = 0; k < 10; ++k) e.v[k] = k == 0 ? 0.5 : double(k);
    e.v[10] = std::numeric_limits<double>::quiet_NaN();
    s.energy.push_back(e);
}

}  // namespace

TEST(RunState, ReadsBackWhatItWroteNonFiniteNumbersIncluded) {
    RunState s;
    s.stage = Stage::Cycling;
    s.stage_t0 = 0.1;
    s.window_n = 7;
    s.grains = 27;
    s.geometry["grains.radius"] = 2.965e-3;
    s.report["prepare.packing_fraction"] = std::numeric_limits<double>::quiet_NaN();
    s.report["prepare.cap_force"] = -std::numeric_limits<double>::infinity();
    s.warnings.push_back("vacuum: not at rest");
    s.samples.push_back({0.5, 1e-3, 12.5, 0.25});
    const RunState r = RunState::load(s.save(), "run.ckpt");
    EXPECT_EQ(r.stage, Stage::Cycling);
    EXPECT_EQ(r.window_n, 7);
    EXPECT_EQ(r.grains, 27u);
    EXPECT_EQ(r.geometry.at("grains.radius"), 2.965e-3);
    EXPECT_TRUE(std::isnan(r.report.at("prepare.packing_fraction")));
    EXPECT_EQ(r.report.at("prepare.cap_force"), -std::numeric_limits<double>::infinity());
    // operator>> stopped at "nan" and dropped what followed: the warning and the samples.
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_EQ(r.warnings[0], "vacuum: not at rest");
    ASSERT_EQ(r.samples.size(), 1u);
    EXPECT_EQ(r.samples[0].grains, 12.5);
}

TEST(RunState, RefusesADamagedBlobNamingTheCheckpoint) {
    EXPECT_NE(refusal("stage 6\n").find("checkpoint 'dir/run.ckpt': damper state entry 'stage' holds 6"),
              std::string::npos);
    EXPECT_NE(refusal("stage -1\n").find("not a stage"), std::string::npos);
    EXPECT_NE(refusal("stage 2\nsample 1 2 x 4\n").find("entry 'sample' holds 'x' where a number belongs"),
              std::string::npos);
    EXPECT_NE(refusal("stage 2\nsample 1 2\n").find("entry 'sample' holds nothing"), std::string::npos);
    EXPECT_NE(refusal("grains -3\n").find("entry 'grains' holds '-3'"), std::string::npos);
    EXPECT_NE(refusal("report\n").find("entry 'report' has no name"), std::string::npos);
    EXPECT_NE(refusal("stage 2\nbogus 1\n").find("unknown damper state entry 'bogus'"), std::string::npos);
}

// One format for all run state: the blob is the run-state archive of the World's sections
// (dem/io/archive.h), every field bit for bit; the key/value text of older checkpoints still
// loads into the same state; a damaged archive is refused naming the checkpoint.
TEST(RunState, IsTheRunStateArchiveAndReadsTheOlderTextToo) {
    RunState s;
    s.stage = Stage::Vacuum;
    s.stage_t0 = 0.125;
    s.cap_d0 = -1.5e-4;
    s.cycle_t0 = 0.3;
    s.window_grains = 10.5;
    s.window_foil = -2.25;
    s.window_n = 41;
    s.grains = 4321;
    s.geometry["damper.radius"] = 0.0255;
    s.settings["process.underpressure"] = 0.06;
    s.report["prepare.cap_force"] = 12.0;
    s.warnings = {"first warning", "second: with spaces"};
    s.samples = {{0.5, 1e-3, 12.5, 0.25}, {0.6, 2e-3, 13.5, -0.5}};
    EnergyRowForTest(s);
    s.gas_amount = 4.5;
    s.gas_volume = 1e-5;
    s.gas_work = -0.01;
    s.air.push_back({1.1e-4, 1e-4, 4e4, 6e4, 2e-3, -0.01});
    const std::string blob = s.save();
    ASSERT_EQ(blob.compare(0, 4, "RUNS"), 0);
    const RunState r = RunState::load(blob, "run.ckpt");
    EXPECT_EQ(r.save(), blob);  // every field read back bit for bit
    EXPECT_EQ(r.stage, Stage::Vacuum);
    EXPECT_EQ(r.window_n, 41);
    EXPECT_EQ(r.grains, 4321u);
    EXPECT_EQ(r.warnings, s.warnings);
    ASSERT_EQ(r.air.size(), 1u);
    EXPECT_EQ(r.air[0].dp, 6e4);
    ASSERT_EQ(r.energy.size(), 1u);
    EXPECT_TRUE(std::isnan(r.energy[0].v[10]));
    EXPECT_EQ(r.energy[0].v[9], 9.0);

    // The text an older vppdem wrote for the same state.
    const std::string text =
        "stage 3\nstage_t0 0.125\ncap_d0 -0.00015\ncycle_t0 0.29999999999999999\nwindow 10.5 -2.25 41\n"
        "geometry damper.radius 0.0255\nsetting process.underpressure 0.059999999999999998\ngrains 4321\n"
        "report prepare.cap_force 12\nwarning first warning\nwarning second: with spaces\n"
        "sample 0.5 0.001 12.5 0.25\nsample 0.59999999999999998 0.002 13.5 -0.5\n"
        "energy 0.5 1 2 3 4 5 6 7 8 9 nan\ngas 4.5 1.0000000000000001e-05 -0.01\n"
        "air 0.00011 0.0001 40000 60000 0.002 -0.01\n";
    const RunState t = RunState::load(text, "old/run.ckpt");
    EXPECT_EQ(t.save(), blob);

    std::string cut = blob.substr(0, blob.size() - 5);
    EXPECT_NE(refusal(cut).find("checkpoint 'dir/run.ckpt' is truncated or corrupt"), std::string::npos);
    std::string bad_stage = blob;
    bad_stage[12] = 6;  // the stage: the first field after the section's tag and length
    EXPECT_NE(refusal(bad_stage).find("checkpoint 'dir/run.ckpt': damper state entry 'stage' holds 6"),
              std::string::npos);
    EXPECT_NE(refusal(blob + "x").find("truncated or corrupt"), std::string::npos);
}
