// The device run's inputs that once did not do what they say (issue 61, item 4), each against a
// known answer on the tiny gripper (tests/data/devices/tiny_gripper.toml):
//   an empty or blank output folder is refused by the run itself, naming --out;
//   a force segment that stops at its max_travel below its force is warned, naming the keys, the
//   force reached and the travel (and one that reaches its force is not);
//   the fill that ends at stages.fill_time warns with the keys to change and the rest criterion;
//   a folder left by a run killed before its first checkpoint is started afresh without
//   --overwrite (its stale frames and partial checkpoint cleared), and a folder with anything
//   else in it is still refused, its files untouched.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "scene/build_info.h"
#include "scene/config.h"
#include "vpp/device/definition.h"
#include "vpp/device/run.h"
#include "cli_helpers.h"

namespace test_device_inputs {

namespace fs = std::filesystem;

fs::path inputs_dir(const std::string& name) {
    const fs::path p = fs::path(::testing::TempDir()) / ("device_inputs_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(p);
    return p;
}

const fs::path kTiny = fs::path(VPPDEM_SOURCE_DIR) / "tests/data/devices/tiny_gripper.toml";

// The tiny gripper (or the device file `file`) with `sets`, run into `out` up to the end of
// stage `upto`, quietly.
vpp::DeviceResult run_tiny(const fs::path& out, const std::vector<std::string>& sets, vpp::DeviceStage upto,
                           const fs::path& file = kTiny) {
    std::vector<std::string> all = {"output.vtk=false"};
    all.insert(all.end(), sets.begin(), sets.end());
    vpp::DeviceOptions o;
    o.out_dir = out.string();
    o.quiet = true;
    o.stop_after = upto;
    return vpp::run_device(vpp::load_device(file.string(), all), o);
}

// The warnings of `r` that contain `what`.
std::vector<std::string> warnings_with(const vpp::DeviceResult& r, const std::string& what) {
    std::vector<std::string> out;
    for (const std::string& w : r.warnings)
        if (w.find(what) != std::string::npos) out.push_back(w);
    return out;
}

// The number after `label` in `text` (e.g. "travel " in "(travel 0.001 m)").
double number_after(const std::string& text, const std::string& label) {
    const std::size_t at = text.find(label);
    EXPECT_NE(at, std::string::npos) << label << " in " << text;
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + label.size()));
}


TEST(DeviceInputs, AnEmptyOrBlankOutIsRefusedNamingOut) {
    for (const char* out : {"", "  "}) {
        vpp::DeviceOptions o;
        o.out_dir = out;
        o.quiet = true;
        try {
            vpp::run_device(vpp::load_device(kTiny.string()), o);
            ADD_FAILURE() << "out_dir '" << out << "' was not refused";
        } catch (const cfg::ConfigError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("--out '" + std::string(out) + "'"), std::string::npos) << m;
            EXPECT_NE(m.find("an empty or blank output folder is refused"), std::string::npos) << m;
        }
    }
}

TEST(DeviceInputs, APressStoppedAtItsMaxTravelIsWarnedAndOneAtItsForceIsNot) {
    // The holder's press asks 1000 N (the bag can give about 1 N) within 1 mm at 0.1 m/s: it
    // stops at its travel. The key, the target, the travel (1 mm, to less than a step's 0.1 m/s
    // dt) and a reaction below the target are named.
    std::string text = cli_test::slurp(kTiny);
    const std::string press = "force = 1.0\nspeed = 0.1\nmax_travel = 0.008\n";
    ASSERT_NE(text.find(press), std::string::npos);
    text.replace(text.find(press), press.size(), "force = 1000.0\nspeed = 0.1\nmax_travel = 0.001\n");
    const fs::path dir = inputs_dir("short");
    cli_test::write_file(dir / "gripper.toml", text);
    const vpp::DeviceResult shortfall = run_tiny(dir / "out", {}, vpp::DeviceStage::Press, dir / "gripper.toml");
    ASSERT_EQ(shortfall.stage, "vacuum");
    const std::vector<std::string> w = warnings_with(shortfall, "max_travel");
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("tools[0].program[0].max_travel = 0.001 m reached (tool 'holder', stage press;"), std::string::npos)
        << w[0];
    EXPECT_NE(w[0].find("short of tools[0].program[0].force = 1000 N"), std::string::npos) << w[0];
    const double travel = number_after(w[0], "; travel ");
    EXPECT_GE(travel, 0.001 * (1 - 1e-3));
    EXPECT_LT(travel, 0.001 + 0.1 * shortfall.dt + 1e-9);
    const double reached = number_after(w[0], "a reaction F_z of ");
    EXPECT_LT(reached, 1000.0);
    // The file's press (1 N within 8 mm) reaches its force: no such warning.
    const vpp::DeviceResult reaching = run_tiny(inputs_dir("reach"), {}, vpp::DeviceStage::Press);
    ASSERT_EQ(reaching.stage, "vacuum");
    EXPECT_TRUE(warnings_with(reaching, "max_travel").empty());
    EXPECT_GT(reaching.press_force, 0.5);
}

TEST(DeviceInputs, AFillCutShortSaysWhichKeysToChangeAndTheCriterion) {
    // The tiny gripper's fill (0.03 s, frictionless) ends before its grains are at rest.
    const vpp::DeviceResult r = run_tiny(inputs_dir("fill"), {}, vpp::DeviceStage::Fill);
    EXPECT_FALSE(r.fill_settled);
    const std::vector<std::string> w = warnings_with(r, "fill: the grains are not at rest");
    ASSERT_EQ(w.size(), 1u);
    for (const char* key : {"stages.fill_time = 0.03 s", "Raise stages.fill_time", "simulation.local_damping (now 0.3",
                            "grains.fill_friction above 0 (now 0", "1e-4 N m g 2r", "every 2 ms from stages.fill_min_time = 0.01 s"})
        EXPECT_NE(w[0].find(key), std::string::npos) << key << "\n" << w[0];
    // The ratio it gives is the kinetic energy over the bound (each to three digits).
    const double ke = number_after(w[0], "kinetic energy "), ratio = number_after(w[0], " J, ");
    const double bound = number_after(w[0], "the bound of rest, ");
    EXPECT_NEAR(ratio, ke / bound, 0.01 * ratio);
    EXPECT_GT(ratio, 1.0);
}

TEST(DeviceInputs, AFolderOfARunKilledBeforeItsFirstCheckpointStartsAfresh) {
    // What a device run leaves when it is killed before its first checkpoint: its lock file (the
    // kernel dropped the lock), build.json (another build's), VTK frames and a partial checkpoint.
    const fs::path out = inputs_dir("killed");
    fs::create_directories(out / "vtk");
    cli_test::write_file(out / ".vppdem.lock", "pid 1 on a host that is gone\n");
    cli_test::write_file(out / "build.json", "{\"commit\": \"another\", \"id\": \"0000000000000000\"}\n");
    cli_test::write_file(out / "run.ckpt.part", "half a checkpoint");
    cli_test::write_file(out / "vtk" / "frame_000001.vtk", "a stale frame");
    cli_test::write_file(out / "vtk" / "stage_0_fill.vtk.part", "half a stale frame");
    // Anything else there is a user's: refused, as before, naming it; nothing removed.
    cli_test::write_file(out / "notes.txt", "mine");
    vpp::DeviceOptions o;
    o.out_dir = out.string();
    o.quiet = true;
    o.stop_at_time = 1e-3;  // [s] a few steps: the run has started, with its checkpoint
    const vpp::DeviceDef d = vpp::load_device(kTiny.string(), {"output.vtk=false"});
    try {
        vpp::run_device(d, o);
        ADD_FAILURE() << "a folder holding notes.txt was not refused";
    } catch (const cfg::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("--out '" + out.string() + "' exists and is not empty (it holds 'notes.txt')"),
                  std::string::npos) << e.what();
    }
    for (const char* f : {"notes.txt", "build.json", "run.ckpt.part", "vtk/frame_000001.vtk", "vtk/stage_0_fill.vtk.part"})
        EXPECT_TRUE(fs::exists(out / f)) << f << " was removed";
    EXPECT_FALSE(fs::exists(out / "run.ckpt"));
    // A file of a user's among the frames is refused too.
    fs::rename(out / "notes.txt", out / "vtk" / "notes.txt");
    EXPECT_THROW(vpp::run_device(d, o), cfg::ConfigError);
    // The killed run's leftovers alone: the same call starts the run afresh.
    fs::remove(out / "vtk" / "notes.txt");
    const vpp::DeviceResult r = vpp::run_device(d, o);
    EXPECT_EQ(r.stage, "fill");
    EXPECT_TRUE(fs::exists(out / "run.ckpt"));
    EXPECT_TRUE(fs::exists(out / "tools.csv"));
    for (const char* f : {"run.ckpt.part", "vtk/frame_000001.vtk", "vtk/stage_0_fill.vtk.part"})
        EXPECT_FALSE(fs::exists(out / f)) << f << " (stale) was kept";
    const auto builds = scene::read_build_record(out.string());
    ASSERT_TRUE(builds.has_value());
    ASSERT_EQ(builds->size(), 1u);  // a new run's record: this build alone
    EXPECT_EQ(builds->front().id, scene::build_id());
    // And the same call again resumes it from its checkpoint (the folder is a run's now).
    o.stop_at_time = 2e-3;
    EXPECT_EQ(vpp::run_device(d, o).stage, "fill");
    EXPECT_FALSE(fs::exists(out / ".vppdem.lock"));  // released at the end of the run
    fs::remove_all(out);
}

}  // namespace test_device_inputs
