// Device studies (vpp/study/device_study.h; docs/devices.md, "Studies"): `vppdem sweep` on a study file
// with the key `device` runs its named cases (seed by seed), each the run `vppdem device --set`
// would make, skips finished runs, refuses a changed study, publishes the small records
// (tools.csv.gz from the press on) and takes them back into a fresh folder.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_device_study {

namespace {

namespace fs = std::filesystem;
using cli_test::quote;
using cli_test::run_vppdem;
using cli_test::write_file;
const auto& slurp = cli_test::slurp;

fs::path fresh_dir(const std::string& name) {
    const fs::path p = fs::path(::testing::TempDir()) / ("device_study_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// The tests' tiny gripper (tests/data/devices/tiny_gripper.toml, about 7 s of CPU a run).
const fs::path kTinyGripper = fs::path(VPPDEM_SOURCE_DIR) / "tests/data/devices/tiny_gripper.toml";

std::string study_text(const std::string& dp50 = "50000") {
    return "device = " + quote(kTinyGripper.string()) +
           "\n[set]\n\"output.vtk\" = false\n"
           "[cases.dp0]\n\"stages.underpressure\" = 0\n"
           "[cases.dp50]\n\"stages.underpressure\" = " + dp50 + "\n";
}

// tools.csv's rows from the press on (stage >= 2), each value as "%.6g": the published record.
std::string press_on(const fs::path& tools) {
    std::ifstream in(tools);
    std::string line, out;
    std::getline(in, line);
    out = line + "\n";
    while (std::getline(in, line)) {
        std::stringstream s(line);
        std::string c, row;
        std::vector<double> v;
        while (std::getline(s, c, ',')) v.push_back(std::stod(c));
        if (v[1] < 2.0) continue;
        for (std::size_t i = 0; i < v.size(); ++i) {
            char b[32];
            std::snprintf(b, sizeof b, "%.6g", v[i]);
            if (i) row += ',';
            row += b;
        }
        out += row + "\n";
    }
    return out;
}

}  // namespace

TEST(DeviceStudy, RunsEachCaseAsTheDeviceCommandWouldAndPublishesItsRecords) {
    const fs::path dir = fresh_dir("run");
    write_file(dir / "study.toml", study_text());
    const fs::path out = dir / "out", pub = dir / "results";

    // --list: the runs in order, with their overrides; nothing written.
    const auto list = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(out) + " --list");
    ASSERT_EQ(list.rc, 0) << list.output;
    EXPECT_NE(list.output.find("dp0 dp0 0 output.vtk=false stages.underpressure=0\n"), std::string::npos) << list.output;
    EXPECT_LT(list.output.find("dp0 dp0"), list.output.find("dp50 dp50"));
    EXPECT_FALSE(fs::exists(out));

    const auto r = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(out) + " --quiet --publish " + quote(pub));
    ASSERT_EQ(r.rc, 0) << r.output;
    for (const char* run : {"dp0", "dp50"}) {
        EXPECT_NE(slurp(out / run / "summary.json").find("\"stage\": \"done\""), std::string::npos) << run;
        EXPECT_TRUE(fs::exists(out / run / "build.json")) << run;
        EXPECT_NE(slurp(out / run / "case.toml").find("stages.underpressure="), std::string::npos) << run;
        // Published: summary.json as it is, tools.csv.gz the rows from the press on.
        EXPECT_EQ(slurp(pub / run / "summary.json"), slurp(out / run / "summary.json")) << run;
        const auto gz = cli_test::shell("gzip -dc " + quote(pub / run / "tools.csv.gz"));
        EXPECT_EQ(gz.output, press_on(out / run / "tools.csv")) << run;
    }
    // summary.csv: a row per run with the numbers of its summary.json, status ok.
    const std::string table = slurp(out / "summary.csv");
    EXPECT_EQ(table.rfind("case,seed,folder,holding_force,press_force,underpressure,", 0), 0u) << table;
    EXPECT_NE(table.find("\ndp0,0,dp0,"), std::string::npos) << table;
    EXPECT_NE(table.find(",50000,"), std::string::npos) << table;
    EXPECT_EQ(slurp(pub / "summary.csv"), table);
    // summary_cases.csv: a row per case (no seeds: one run each), published beside it.
    const std::string cases = slurp(out / "summary_cases.csv");
    EXPECT_EQ(cases.rfind("case,seeds,ok,holding_force_n,holding_force_mean,holding_force_sd,holding_force_ci95,", 0), 0u)
        << cases;
    EXPECT_NE(cases.find("\ndp0,1,1,1,"), std::string::npos) << cases;
    EXPECT_EQ(slurp(pub / "summary_cases.csv"), cases);
    // The numbers against the case, drawn at the end (vppdem.plot.device_study).
    EXPECT_TRUE(fs::exists(out / "sweep_numbers.png"));

    // The same run by hand is the study's run, bit for bit.
    const fs::path hand = dir / "hand";
    const auto h = run_vppdem("device " + quote(kTinyGripper) + " --out " + quote(hand) +
                              " --quiet --set output.vtk=false --set stages.underpressure=50000");
    ASSERT_EQ(h.rc, 0) << h.output;
    EXPECT_EQ(slurp(hand / "tools.csv"), slurp(out / "dp50" / "tools.csv"));
    EXPECT_EQ(slurp(hand / "air.csv"), slurp(out / "dp50" / "air.csv"));

    // Again: every run is finished, nothing runs, the records stay.
    const std::string before = slurp(out / "dp0" / "summary.json");
    fs::remove(out / "sweep_numbers.png");
    const auto again = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(out) + " --no-plot");
    ASSERT_EQ(again.rc, 0) << again.output;
    EXPECT_EQ(again.output.find("[1/2]"), std::string::npos) << again.output;
    EXPECT_NE(again.output.find("2 of 2 run(s) finished"), std::string::npos) << again.output;
    EXPECT_EQ(slurp(out / "dp0" / "summary.json"), before);
    EXPECT_FALSE(fs::exists(out / "sweep_numbers.png"));  // --no-plot

    // A fresh folder takes the published records back: finished, nothing runs.
    const auto back = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(dir / "fresh") + " --publish " + quote(pub));
    ASSERT_EQ(back.rc, 0) << back.output;
    EXPECT_NE(back.output.find("2 of 2 run(s) finished"), std::string::npos) << back.output;
    EXPECT_EQ(slurp(dir / "fresh" / "summary.csv"), table);

    // The study changed under its folder: refused (exit 2) naming the run, nothing runs.
    write_file(dir / "study.toml", study_text("40000"));
    const auto changed = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(out) + " --quiet");
    EXPECT_EQ(changed.rc, 2) << changed.output;
    EXPECT_NE(changed.output.find("dp50"), std::string::npos) << changed.output;
    EXPECT_NE(changed.output.find("other settings"), std::string::npos) << changed.output;
}

TEST(DeviceStudy, BadStudiesAreRefusedNamingTheKey) {
    const fs::path dir = fresh_dir("bad");
    const std::string device = "device = " + quote(kTinyGripper.string()) + "\n";
    struct Case {
        std::string text, names;
    };
    const std::vector<Case> bad = {
        {device + "[cases.a]\n\"stages.nonsense\" = 1\n", "stages.nonsense"},
        {device + "[cases.a]\n\"stages.underpressure\" = -5\n", "stages.underpressure"},
        {device + "grid = 1\n[cases.a]\n", "unknown key 'grid'"},
        {device, "no cases"},
        {device + "seeds = 0\n[cases.a]\n", "key 'seeds' = 0"},
        {device + "seeds = 2\n[cases.a]\n\"simulation.seed\" = 3\n", "simulation.seed"},
        {"device = \"missing.toml\"\n[cases.a]\n", "missing.toml"},
        {device + "[cases.\"a b\"]\n", "case name 'a b'"},
        // A key in both [set] and a case (the case's value silently won), quoted or dotted alike:
        // refused as a damper study refuses one in both [set] and [grid].
        {device + "[set]\n\"stages.underpressure\" = 1000\n[cases.a]\n[cases.b]\n\"stages.underpressure\" = 0\n",
         "key 'stages.underpressure' is in both [set] and [cases.b]"},
        {device + "[set]\nstages.ramp_time = 0.01\n[cases.a]\n\"stages.ramp_time\" = 0.02\n",
         "key 'stages.ramp_time' is in both [set] and [cases.a]"},
    };
    for (const Case& c : bad) {
        write_file(dir / "study.toml", c.text);
        const auto r = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(dir / "out") + " --quiet");
        EXPECT_EQ(r.rc, 2) << c.text << r.output;
        EXPECT_NE(r.output.find(c.names), std::string::npos) << c.text << r.output;
        EXPECT_FALSE(fs::exists(dir / "out")) << c.text;
    }
}

// summary_cases.csv (a row per case over its seeds, as a damper study's): on hand-made finished
// runs read by --report-only (no run), the known means, standard deviations and 95% Student-t
// half widths; a run not finished and a number the runs lack are left out of n.
TEST(DeviceStudy, CasesTableHoldsTheMeanAndTheStudentIntervalOverTheSeeds) {
    const fs::path dir = fresh_dir("cases");
    write_file(dir / "study.toml", "device = " + quote(kTinyGripper.string()) +
                                       "\nseeds = 3\n[cases.a]\n\"stages.underpressure\" = 50000\n"
                                       "[cases.b]\n\"stages.underpressure\" = 0\n");
    const fs::path out = dir / "out";
    // holding_ratio F / (dp A) with A = 1e-4 m^2 at 50 kPa (case a only: b has no vacuum).
    auto run = [&](const std::string& folder, double hf, double dv) {
        const std::string ratio = folder[0] == 'a' ? ", \"holding_ratio\": " + std::to_string(hf / 5.0) : "";
        write_file(out / folder / "summary.json", "{\"stage\": \"done\", \"holding_force\": " + std::to_string(hf) +
                                                       ", \"volume_change\": " + std::to_string(dv) + ratio + "}\n");
    };
    run("a_s1", 1.0, -0.1);
    run("a_s2", 2.0, -0.1);
    run("a_s3", 3.0, -0.1);
    run("b_s1", 0.5, -0.2);
    run("b_s2", 1.5, -0.4);  // b_s3 not run
    const auto r = run_vppdem("sweep " + quote(dir / "study.toml") + " --out " + quote(out) + " --report-only --quiet");
    ASSERT_EQ(r.rc, 0) << r.output;
    std::ifstream in(out / "summary_cases.csv");
    std::string line;
    std::getline(in, line);
    std::vector<std::string> head;
    for (std::stringstream h(line); std::getline(h, line, ',');) head.push_back(line);
    ASSERT_GE(head.size(), 7u);
    EXPECT_EQ(std::vector<std::string>(head.begin(), head.begin() + 7),
              (std::vector<std::string>{"case", "seeds", "ok", "holding_force_n", "holding_force_mean", "holding_force_sd",
                                        "holding_force_ci95"}));
    EXPECT_EQ(head.back(), "folders");
    std::map<std::string, std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream c(line);
        for (std::string cell; std::getline(c, cell, ',');) cells.push_back(cell);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        ASSERT_EQ(cells.size(), head.size()) << line;
        for (std::size_t k = 0; k < head.size(); ++k) rows[cells[0]][head[k]] = cells[k];
    }
    ASSERT_EQ(rows.size(), 2u);
    auto num = [&](const std::string& c, const std::string& col) { return std::stod(rows[c][col]); };
    const double t2 = 4.302652729749464, t1 = 12.706204736174698;  // t_{0.975, 2}, t_{0.975, 1}
    EXPECT_EQ(rows["a"]["seeds"], "3");
    EXPECT_EQ(rows["a"]["ok"], "3");
    EXPECT_EQ(rows["a"]["holding_force_n"], "3");
    EXPECT_NEAR(num("a", "holding_force_mean"), 2.0, 1e-12);
    EXPECT_NEAR(num("a", "holding_force_sd"), 1.0, 1e-12);
    EXPECT_NEAR(num("a", "holding_force_ci95"), t2 / std::sqrt(3.0), 1e-9);
    EXPECT_NEAR(num("a", "volume_change_mean"), -0.1, 1e-12);
    EXPECT_NEAR(num("a", "volume_change_ci95"), 0.0, 1e-12);
    EXPECT_EQ(rows["a"]["folders"], "a_s1;a_s2;a_s3");
    // The gripper's F / (dp A): 0.2, 0.4, 0.6 (mean 0.4, sd 0.2); b's runs have none.
    EXPECT_NEAR(num("a", "holding_ratio_mean"), 0.4, 1e-6);
    EXPECT_NEAR(num("a", "holding_ratio_ci95"), t2 * 0.2 / std::sqrt(3.0), 1e-6);
    EXPECT_EQ(rows["b"]["holding_ratio_n"], "0");
    EXPECT_EQ(rows["b"]["seeds"], "3");
    EXPECT_EQ(rows["b"]["ok"], "2");
    EXPECT_EQ(rows["b"]["holding_force_n"], "2");
    EXPECT_NEAR(num("b", "holding_force_mean"), 1.0, 1e-12);
    EXPECT_NEAR(num("b", "holding_force_sd"), std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(num("b", "holding_force_ci95"), t1 * 0.5, 1e-9);
    EXPECT_NEAR(num("b", "volume_change_mean"), -0.3, 1e-12);
    // A number no run has (the gripper's stiffness): n 0, the rest empty.
    EXPECT_EQ(rows["b"]["stiffness_n"], "0");
    EXPECT_EQ(rows["b"]["stiffness_mean"] + rows["b"]["stiffness_sd"] + rows["b"]["stiffness_ci95"], "");
}

}  // namespace test_device_study
