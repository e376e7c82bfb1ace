// The damper's state blob in its checkpoints (vpp::damper_detail::RunState): it reads back what
// it wrote, non-finite numbers included, and refuses a damaged blob with the checkpoint's path
// (fuzz/fuzz_checkpoint.cpp found a stage outside the enum indexing past stage_name()).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "vpp/damper_run.h"

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
