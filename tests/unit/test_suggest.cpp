// "Did you mean ...?" for mistyped commands (scene/suggest.h) and the command line's answer.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <string>
#include <vector>

#include "scene/suggest.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_suggest {

namespace {
const std::vector<std::string> kCommands = {"scene", "bench", "tension", "envelope", "damper",
                                            "analyze", "plot", "sweep", "calibrate"};

struct CmdResult {
    int rc;
    std::string output;
};
CmdResult run_vppdem(const std::string& args) {
    FILE* p = ::popen((std::string(VPPDEM_BINARY) + " " + args + " 2>&1").c_str(), "r");
    CmdResult r{-1, ""};
    char buf[4096];
    while (p && fgets(buf, sizeof buf, p)) r.output += buf;
    const int st = p ? ::pclose(p) : -1;
    r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : 128;
    return r;
}
}  // namespace

TEST(Suggest, EditDistanceCountsSwapsAsOneEdit) {
    EXPECT_EQ(scene::edit_distance("damper", "damper"), 0);
    EXPECT_EQ(scene::edit_distance("dampr", "damper"), 1);
    EXPECT_EQ(scene::edit_distance("dapmer", "damper"), 1);  // swapped neighbours
    EXPECT_EQ(scene::edit_distance("", "plot"), 4);
    EXPECT_EQ(scene::edit_distance("kitten", "sitting"), 3);
}

TEST(Suggest, NearestCommandOrNothing) {
    EXPECT_EQ(scene::nearest("dampr", kCommands), "damper");
    EXPECT_EQ(scene::nearest("swep", kCommands), "sweep");
    EXPECT_EQ(scene::nearest("analyse", kCommands), "analyze");
    EXPECT_EQ(scene::nearest("calbrate", kCommands), "calibrate");
    EXPECT_EQ(scene::nearest("frobnicate", kCommands), "");  // not a typo of any command
}

TEST(Suggest, UnknownCommandIsNamedWithTheNearestOne) {
    const CmdResult r = run_vppdem("dampr --out /nonexistent/x");
    EXPECT_NE(r.rc, 0);
    EXPECT_NE(r.output.find("unknown command 'dampr'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("did you mean 'damper'?"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("A subcommand is required"), std::string::npos) << r.output;
    const CmdResult far = run_vppdem("frobnicate");
    EXPECT_NE(far.rc, 0);
    EXPECT_NE(far.output.find("unknown command 'frobnicate'"), std::string::npos) << far.output;
    EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
    EXPECT_NE(far.output.find("damper"), std::string::npos) << far.output;  // lists the commands
}

}  // namespace test_suggest
