// The build a run folder records (scene/build_info.h, issue 46): build.json names the build that
// started the run and every other build that resumed it, so a study can refuse to mix them.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../physics/cli_helpers.h"
#include "scene/build_info.h"

namespace fs = std::filesystem;

namespace {

using cli_test::slurp;

fs::path scratch(const std::string& name) {
    const fs::path d = cli_test::scratch_path("build_info", name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

}  // namespace

TEST(BuildInfo, TheIdIsSixteenHexDigitsAndTheCommitIsNamed) {
    const std::string id = scene::build_id();
    ASSERT_EQ(id.size(), 16u);
    for (char c : id) EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(c))) << id;
    EXPECT_FALSE(std::string(scene::build_commit()).empty());
}

TEST(BuildInfo, ANewRunRecordsThisBuildAndAResumeByAnotherIsListed) {
    const fs::path d = scratch("record");
    EXPECT_FALSE(scene::read_build_record(d.string()).has_value());  // an older vppdem's folder
    scene::record_build(d.string(), true);
    auto r = scene::read_build_record(d.string());
    ASSERT_TRUE(r.has_value());
    ASSERT_EQ(r->size(), 1u);
    EXPECT_EQ(r->front().id, scene::build_id());
    EXPECT_EQ(r->front().commit, scene::build_commit());
    EXPECT_TRUE(scene::other_builds(d.string()).empty());
    // The same build resuming changes nothing.
    const std::string once = slurp(d / "build.json");
    scene::record_build(d.string(), false);
    EXPECT_EQ(slurp(d / "build.json"), once);

    // A run another build started: this build resuming it is appended, once.
    std::ofstream(d / "build.json") << R"({"commit": "0123abcd", "id": "00000000000000aa"})" << "\n";
    scene::record_build(d.string(), false);
    scene::record_build(d.string(), false);
    r = scene::read_build_record(d.string());
    ASSERT_TRUE(r.has_value());
    ASSERT_EQ(r->size(), 2u);
    EXPECT_EQ((*r)[0].commit, "0123abcd");
    EXPECT_EQ((*r)[0].id, "00000000000000aa");
    EXPECT_EQ((*r)[1].id, scene::build_id());
    const auto other = scene::other_builds(d.string());
    ASSERT_EQ(other.size(), 1u);
    EXPECT_EQ(other[0].id, "00000000000000aa");
    EXPECT_NE(slurp(d / "build.json").find("\"resumed_by\""), std::string::npos);

    // A fresh run in the folder (--overwrite) is this build alone again.
    scene::record_build(d.string(), true);
    r = scene::read_build_record(d.string());
    ASSERT_EQ(r->size(), 1u);
    EXPECT_EQ(r->front().id, scene::build_id());
    // No temporary left beside it.
    for (const auto& e : fs::directory_iterator(d)) EXPECT_EQ(e.path().filename(), "build.json");
}

TEST(BuildInfo, AnUnreadableRecordIsNoRecord) {
    const fs::path d = scratch("unreadable");
    std::ofstream(d / "build.json") << "not json\n";
    EXPECT_FALSE(scene::read_build_record(d.string()).has_value());
    EXPECT_TRUE(scene::other_builds(d.string()).empty());
    std::ofstream(d / "build.json") << R"({"commit": 3})" << "\n";
    EXPECT_FALSE(scene::read_build_record(d.string()).has_value());
}
