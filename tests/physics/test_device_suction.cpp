// The suction's seal in a device run (vpp/device/suction.h, docs/devices.md "Suction"): on the
// tests' tiny gripper with suction.enabled the membrane seals on the object at the load stage's
// start, the seal pulls it (suction.csv, summary.json), the ledger books the pull's work (the
// energy residual stays as small as without it), a run stopped within the load stage resumes to
// the records of an uninterrupted one (the seal is in the checkpoint), and its bad values are
// refused naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "vpp/device/definition.h"
#include "vpp/device/run.h"

namespace device_suction_test {

namespace fs = std::filesystem;

fs::path dir(const std::string& name) {
    const fs::path p = fs::path(::testing::TempDir()) / ("suction_" + std::to_string(::getpid()) + "_" + name);
    return p;
}

fs::path gripper_file() {
    const fs::path p = dir("file") / "gripper.toml";
    cli_test::write_file(p, cli_test::slurp(fs::path(VPPDEM_SOURCE_DIR) / "tests/data/devices/tiny_gripper.toml"));
    return p;
}

std::vector<std::vector<double>> rows(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    std::vector<std::vector<double>> out;
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) row.push_back(std::stod(cell));
        out.push_back(row);
    }
    return out;
}

// The tiny gripper with the suction on, run once into "on".
const vpp::DeviceResult& suction_run() {
    static vpp::DeviceResult r;
    static bool ran = false;
    if (!ran) {
        const vpp::DeviceDef d = vpp::load_device(gripper_file().string(), {"suction.enabled=true"});
        vpp::DeviceOptions o;
        fs::remove_all(dir("on"));
        o.out_dir = dir("on").string();
        o.quiet = true;
        r = vpp::run_device(d, o);
        ran = true;
    }
    return r;
}

TEST(DeviceSuction, TheSealPullsTheObjectAndTheLedgerBooksIt) {
    const vpp::DeviceResult& r = suction_run();
    ASSERT_EQ(r.stage, "done");
    EXPECT_GT(r.seal_area, 0.0);
    EXPECT_GT(r.suction_force_max, 0.0);
    // No more than the surroundings can push through the footprint.
    EXPECT_LT(r.suction_force_max, 101325.0 * r.seal_area);
    const auto s = rows(dir("on") / "suction.csv");
    ASSERT_FALSE(s.empty());
    double largest = 0;
    for (const auto& row : s) {
        ASSERT_EQ(row.size(), 8u);
        EXPECT_EQ(row[1], row[2] + row[3]);  // every open particle in a pocket below or at the ambient pressure
        EXPECT_LE(row[4], 101325.0);
        largest = std::max(largest, row[7]);
    }
    EXPECT_EQ(largest, r.suction_force_max);
    // The pull's work on the membrane is booked (Particles::ext_force): the ledger closes as the
    // gripper's does without it (test_device.cpp, 2% of the largest term).
    ASSERT_GT(r.energy_scale, 0.0);
    EXPECT_LT(std::abs(r.energy_residual), 0.02 * r.energy_scale);
    // The holding ratio is the holding force over dp and the object's cross-section (a sphere of
    // 4 mm radius at resolution 5: its inscribed silhouette within 2% below pi r^2).
    EXPECT_LT(r.object_area, M_PI * 0.004 * 0.004);
    EXPECT_GT(r.object_area, 0.98 * M_PI * 0.004 * 0.004);
    EXPECT_NEAR(r.holding_ratio, r.holding_force / (5e4 * r.object_area), 1e-12);
}

TEST(DeviceSuction, AResumeWithinTheLoadStageWritesTheRecordsOfAnUninterruptedRun) {
    const vpp::DeviceResult& full = suction_run();
    ASSERT_EQ(full.stage, "done");
    double t_load = -1;
    for (const auto& row : rows(dir("on") / "tools.csv"))
        if (t_load < 0 && int(row[1]) == int(vpp::DeviceStage::Load)) t_load = row[0];
    ASSERT_GT(t_load, 0);
    const vpp::DeviceDef d = vpp::load_device(gripper_file().string(), {"suction.enabled=true"});
    vpp::DeviceOptions o;
    fs::remove_all(dir("split"));
    o.out_dir = dir("split").string();
    o.quiet = true;
    o.stop_at_time = t_load + 1e-3;  // within the seal's life
    EXPECT_EQ(vpp::run_device(d, o).stage, "load");
    o.stop_at_time = -1;
    EXPECT_EQ(vpp::run_device(d, o).stage, "done");
    for (const char* f : {"tools.csv", "air.csv", "energy.csv", "suction.csv"}) {
        const std::string a = cli_test::slurp(dir("on") / f), b = cli_test::slurp(dir("split") / f);
        EXPECT_FALSE(a.empty()) << f;
        EXPECT_TRUE(a == b) << f << " differs after a resume";
    }
}

TEST(DeviceSuction, BadValuesAreRefusedNamingTheKey) {
    const fs::path file = gripper_file();
    struct Case {
        std::string set, expected;
    };
    const std::vector<Case> cases = {
        {"suction.gap=0", "config key 'suction.gap' = 0: must be in [1e-9, membrane.particle_radius]"},
        {"suction.gap=0.01", "config key 'suction.gap' = 0.01: must be in [1e-9, membrane.particle_radius]"},
        {"suction.ambient=4e4", "config key 'suction.ambient' = 40000.0: must be above stages.underpressure"},
        {"suction.capture=-1e-5", "config key 'suction.capture' = -1e-05: must be in [0, membrane.particle_radius]"},
        {"suction.viscosity=0", "config key 'suction.viscosity' = 0: must be in (0, 1]"},
        {"suction.colour=1", "unknown config key 'suction.colour'"},
    };
    for (const Case& c : cases) {
        const fs::path out = dir("bad_out");
        const cli_test::RunResult r = cli_test::run_vppdem("device " + cli_test::quote(file.string()) + " --out " +
                                                           cli_test::quote(out.string()) + " --quiet --set suction.enabled=true --set " + c.set);
        EXPECT_EQ(r.rc, 2) << c.set << "\n" << r.output;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.set << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.set;
    }
    // The seal needs the object it seals on.
    const cli_test::RunResult r = cli_test::run_vppdem("device " + cli_test::quote(file.string()) + " --out " +
                                                       cli_test::quote(dir("bad_out").string()) +
                                                       " --quiet --set suction.enabled=true --set result.object=");
    EXPECT_EQ(r.rc, 2) << r.output;
    EXPECT_NE(r.output.find("config key 'result.object'"), std::string::npos) << r.output;
}

}  // namespace device_suction_test
