// Studies through the vppdem binary on the small quick damper (56 grains, 494 foil particles):
// a sweep shares its preparation and writes summary.csv, resumes after being killed, a
// calibration recovers the friction of a synthetic experiment, bad study files fail clearly.
// Also the pure parts: range strings, the loop misfit.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "scene/config.h"
#include "cli_helpers.h"
#include "dem/io/csv.h"
#include "vpp/calibrate.h"
#include "vpp/study.h"

namespace fs = std::filesystem;

namespace {

using namespace cli_test;


// The small damper of tests/physics/test_damper.cpp as a study's [set].
const std::string kSmallSet =
    "[set]\n"
    "\"damper.radius\" = 0.012\n"
    "\"damper.height\" = 0.03\n"
    "\"grains.volume_fraction\" = 0.45\n"
    "\"process.velocity\" = 0.1\n"
    "\"process.amplitude\" = 0.002\n"
    "\"process.cycles\" = 2\n"
    "\"process.samples_per_cycle\" = 80\n"
    "\"simulation.threads\" = 1\n";

fs::path scratch(const std::string& name) { return scratch_path("study_test", name); }

std::vector<std::string> lines_of(const fs::path& p) {
    std::vector<std::string> out;
    std::ifstream in(p);
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) out.push_back(l);
    return out;
}

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
    return out;
}

class Study : public ::testing::Test {
protected:
    void SetUp() override { fs::create_directories(scratch("")); }
    static void TearDownTestSuite() { fs::remove_all(scratch("")); }
};

const std::string kTwoFrictions = kSmallSet + "[grid]\n\"grains.friction\" = [0.3, 0.6]\n";

}  // namespace

TEST(StudyUnits, RangesIncludeTheStopAndRoundCleanly) {
    bool ints = true;
    const auto v = vpp::parse_range("grains.friction", "0:1:0.1", &ints);
    ASSERT_EQ(v.size(), 11u);
    EXPECT_FALSE(ints);
    EXPECT_EQ(v[3], 0.3);  // not 0.30000000000000004
    EXPECT_EQ(v[10], 1.0);
    const auto c = vpp::parse_range("process.cycles", "2:6:2", &ints);
    EXPECT_TRUE(ints);
    EXPECT_EQ(c, (std::vector<double>{2, 4, 6}));
    for (const char* bad : {"0:1", "0:1:0", "1:0:0.1", "a:1:0.1", "0:1:0.1:2", "0:1:"})
        EXPECT_THROW(vpp::parse_range("grains.friction", bad), cfg::ConfigError) << bad;
}

TEST(StudyUnits, MisfitIsZeroForTheSameLoopAndGrowsWithTheDifference) {
    // A parallelogram-like loop, 3 cycles: up along F = 10 d + 2, down along F = 10 d - 2.
    vpp::LoopSeries a;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 40; ++k) {
            const double d = k < 20 ? k / 20.0 : (40 - k) / 20.0;
            a.time.push_back(c * 40 + k);
            a.displacement.push_back(d);
            a.force.push_back(10 * d + (k < 20 ? 2.0 : -2.0));
            a.cycle.push_back(c + 1);
        }
    const vpp::Misfit same = vpp::loop_misfit(a, a);
    EXPECT_NEAR(same.value, 0.0, 1e-12);
    EXPECT_EQ(same.cycles, (std::vector<int>{2, 3}));  // the stabilised cycles
    vpp::LoopSeries b = a;
    for (double& f : b.force) f *= 1.1;
    vpp::LoopSeries c = a;
    for (double& f : c.force) f *= 1.3;
    const double mb = vpp::loop_misfit(b, a).value, mc = vpp::loop_misfit(c, a).value;
    EXPECT_GT(mb, 0.1);  // the energy term alone is 0.1
    EXPECT_GT(mc, mb);
}

// A rig that counts compression negative: the parallelogram loop of the misfit test, 3 cycles,
// stroke 2 mm from an offset origin, in mm and N; sign -1 flips both columns, `force_sign` the
// force alone.
std::string rig_record(double sign, double force_sign = 1.0) {
    std::ostringstream os;
    os << "t,stroke,load\n";
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 40; ++k) {
            const double d = k < 20 ? 2.0 * k / 20.0 : 2.0 * (40 - k) / 20.0;  // [mm]
            const double f = 10 * d + (k < 20 ? 2.0 : -2.0);                    // [N]
            os << c * 40 + k << "," << sign * (d + 12.5) << "," << sign * force_sign * f << "\n";
        }
    return os.str();
}

TEST(StudyUnits, AnExperimentWithTheOtherSignConventionIsRefused) {
    const fs::path p = scratch_path("study_units", "rig.csv");
    vpp::ExperimentFormat fmt;
    fmt.time_col = "t";
    fmt.disp_col = "stroke";
    fmt.force_col = "load";
    fmt.disp_scale = 1e-3;
    auto check = [&](const std::string& text, bool flag) {
        write_file(p, text);
        fmt.compression_negative = flag;
        const vpp::LoopSeries s = vpp::read_experiment(p.string(), fmt);
        vpp::check_experiment_orientation(s, p.string(), flag, true);
    };
    EXPECT_NO_THROW(check(rig_record(1.0), false));
    EXPECT_NO_THROW(check(rig_record(-1.0), true));
    // Compression negative, read as it is: refused, naming the flag.
    try {
        check(rig_record(-1.0), false);
        FAIL() << "accepted a compression-negative record without --compression-negative";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("pass --compression-negative"), std::string::npos) << e.what();
    }
    // The flag on a compression-positive record: refused, saying to drop it.
    try {
        check(rig_record(1.0), true);
        FAIL() << "accepted a compression-positive record with --compression-negative";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("drop --compression-negative"), std::string::npos) << e.what();
    }
    // Only the force the other way: the loop runs backwards (negative area).
    try {
        check(rig_record(1.0, -1.0), false);
        FAIL() << "accepted a loop of negative area";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("negative area"), std::string::npos) << e.what();
    }
    // Extension first: a negative force is what that protocol gives.
    write_file(p, rig_record(-1.0));
    fmt.compression_negative = false;
    EXPECT_NO_THROW(vpp::check_experiment_orientation(vpp::read_experiment(p.string(), fmt), p.string(), false, false));
    fs::remove_all(p.parent_path());
}

TEST_F(Study, CalibrationRefusesAnExperimentOfTheOtherSignAndRunsNothing) {
    const fs::path study = scratch("sign.toml"), out = scratch("sign_out"), exp = scratch("rig.csv");
    write_file(study, kTwoFrictions);
    write_file(exp, rig_record(-1.0));
    const Outcome r = run("calibrate " + study.string() + " --experiment " + exp.string() + " --out " + out.string() +
                          " --time-column t --displacement-column stroke --force-column load --displacement-unit mm");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--compression-negative"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST_F(Study, SweepSharesOnePreparationAndWritesTheSummary) {
    const fs::path study = scratch("two.toml"), out = scratch("sweep");
    write_file(study, kTwoFrictions);
    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --jobs 2 --no-plot");
    ASSERT_EQ(r.status, 0) << r.output;
    const auto rows = lines_of(out / "summary.csv");
    ASSERT_EQ(rows.size(), 3u) << slurp(out / "summary.csv");
    // The contract columns first, then the ones added later (docs/studies.md, "Outputs").
    EXPECT_EQ(rows[0], "grains.friction,W,dissipated_energy,peak_force,run_seconds,status,case,"
                       "W_settled,settled_cycles,first_settled_cycle,friction_share,damping_share,grains,packing_fraction,warnings");
    double W[2];
    for (int k = 0; k < 2; ++k) {
        const auto c = cells(rows[std::size_t(k) + 1]);
        ASSERT_EQ(c.size(), 15u) << rows[std::size_t(k) + 1];
        // Two cycles never settle (W_settled empty, 0 settled cycles); the ledger gives the split;
        // the warnings of the case (this toy is not quasi-static) are in the last column.
        EXPECT_EQ(c[7], "");
        EXPECT_EQ(c[8], "0");
        EXPECT_GT(std::stod(c[10]), 0.2);
        EXPECT_NEAR(std::stod(c[10]) + std::stod(c[11]), 1.0, 1e-9);
        EXPECT_GT(std::stoi(c[12]), 50);                       // grains after the re-fills
        EXPECT_GT(std::stod(c[13]), 0.5);                      // packing fraction
        EXPECT_NE(c[14].find("not quasi-static"), std::string::npos) << c[14];
        EXPECT_EQ(c[0], k == 0 ? "0.3" : "0.6");
        EXPECT_EQ(c[5], "ok");
        W[k] = std::stod(c[1]);
        EXPECT_GT(W[k], 0.0);
        EXPECT_GT(std::stod(c[3]), 0.0);  // peak force
    }
    std::printf("W: %.5g J/m^2 at friction 0.3, %.5g J/m^2 at 0.6\n", W[0], W[1]);
    EXPECT_GT(W[1], W[0]);
    // One preparation: the first case prepared, the second branched from it.
    const fs::path c1 = out / "grains.friction=0.3", c2 = out / "grains.friction=0.6";
    EXPECT_TRUE(fs::exists(c1 / "prepared.ckpt"));
    EXPECT_FALSE(fs::exists(c2 / "prepared.ckpt"));
    EXPECT_NE(slurp(c2 / "summary.json").find("grains.friction=0.3/prepared.ckpt\""), std::string::npos)
        << slurp(c2 / "summary.json");
    // The cases' own results agree with the summary (last cycle).
    const auto cyc = lines_of(c2 / "cycles.csv");
    EXPECT_EQ(std::stod(cells(cyc.back())[2]), W[1]);
    // A second run finds everything done and changes nothing.
    const std::string before = slurp(c1 / "forces.csv");
    const Outcome again = run("sweep " + study.string() + " --out " + out.string() + " --no-plot");
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("grains.friction=0.3: done earlier"), std::string::npos) << again.output;
    EXPECT_NE(again.output.find("grains.friction=0.6: done earlier"), std::string::npos) << again.output;
    EXPECT_EQ(slurp(c1 / "forces.csv"), before);
    EXPECT_EQ(lines_of(out / "summary.csv").size(), 3u);
}

TEST_F(Study, SweepResumesAfterBeingKilled) {
    const fs::path study = scratch("two_kill.toml"), out = scratch("killed");
    write_file(study, kTwoFrictions);
    const fs::path c1 = out / "grains.friction=0.3", c2 = out / "grains.friction=0.6";
    // One job: the preparing case first, then the branch. Kill the sweep while the branch runs.
    const std::string cmd = "exec " + kBinary + " sweep " + study.string() + " --out " + out.string() +
                            " --jobs 1 --no-plot --quiet --checkpoint-every 0.3 > /dev/null 2>&1";
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd.c_str(), (char*)nullptr);
        _exit(127);
    }
    const auto t0 = std::chrono::steady_clock::now();
    bool branch_started = false;
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
        if (fs::exists(c1 / "summary.json") && fs::exists(c2 / "run.ckpt")) {
            branch_started = true;
            break;
        }
        if (waitpid(pid, nullptr, WNOHANG) == pid) break;  // finished (too fast to kill) or died
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    ASSERT_TRUE(branch_started) << "the sweep did not reach its second case";
    ASSERT_FALSE(fs::exists(c2 / "summary.json")) << "the second case finished before the kill";
    ASSERT_FALSE(fs::exists(out / "summary.csv"));
    const auto stamp = fs::last_write_time(c1 / "summary.json");
    const std::string first_forces = slurp(c1 / "forces.csv");

    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --jobs 1 --no-plot");
    ASSERT_EQ(r.status, 0) << r.output;
    std::printf("%s", r.output.c_str());
    // The finished case is not run again; the killed one resumed from its own checkpoint.
    EXPECT_NE(r.output.find("grains.friction=0.3: done earlier"), std::string::npos) << r.output;
    EXPECT_EQ(fs::last_write_time(c1 / "summary.json"), stamp);
    EXPECT_EQ(slurp(c1 / "forces.csv"), first_forces);
    EXPECT_NE(slurp(c2 / "summary.json").find("grains.friction=0.6/run.ckpt\""), std::string::npos)
        << slurp(c2 / "summary.json");
    const auto rows = lines_of(out / "summary.csv");
    ASSERT_EQ(rows.size(), 3u);
    for (int k = 1; k <= 2; ++k) EXPECT_EQ(cells(rows[std::size_t(k)])[5], "ok") << rows[std::size_t(k)];
    // 2 cycles of 80 samples, as an uninterrupted run.
    EXPECT_EQ(lines_of(c2 / "forces.csv").size(), 161u);
}

// A calibration that could fail: the "experiment" is the small damper at a friction between the
// grid values (0.45), from a seed the grid does not run (11: another packing), written as a test
// rig would (stroke in mm from an arbitrary origin, load in kN, compression negative, noise). The
// grid 0, 0.3, 0.6, 0.9 runs 2 seeds per value; the misfit of a value is the mean over its seeds.
// The best value must lie within one grid step of the truth (0.3 or 0.6).
TEST_F(Study, CalibrationRecoversTheFrictionOfAnExperimentFromAnotherPacking) {
    const fs::path sim = scratch("truth");
    const Outcome t = run("damper --out " + sim.string() +
                          " --set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 "
                          "--set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=2 "
                          "--set process.samples_per_cycle=80 --set simulation.threads=1 "
                          "--set grains.friction=0.45 --set simulation.seed=11 --no-plot --quiet");
    ASSERT_EQ(t.status, 0) << t.output;
    std::vector<std::string> header;
    const auto rows = dem::read_numeric_csv((sim / "forces.csv").string(), 7, &header);
    ASSERT_EQ(header[1], "displacement");
    ASSERT_EQ(header[5], "force_zeroed");
    std::mt19937 rng(7);
    std::normal_distribution<double> dn(0.0, 2e-3), fn(0.0, 0.4e-3);  // 2 um, 0.4 N
    std::ostringstream exp;
    exp << "# synthetic test record\nt_s,stroke_mm,load_kN,channel\n";
    exp.precision(9);
    for (const auto& r : rows)
        exp << r[0] << "," << -(12.5 + 1e3 * r[1] + dn(rng)) << "," << -(1e-3 * r[5] + fn(rng)) << ",7\n";
    const fs::path expfile = scratch("experiment.csv");
    write_file(expfile, exp.str());

    const fs::path study = scratch("calib.toml"), out = scratch("calib");
    write_file(study, "seeds = 2\n" + kSmallSet + "[grid]\n\"grains.friction\" = [0.0, 0.3, 0.6, 0.9]\n");
    const std::string columns = " --time-column t_s --displacement-column stroke_mm --force-column load_kN "
                                "--displacement-unit mm --force-unit kN --compression-negative";
    const Outcome r = run("calibrate " + study.string() + " --experiment " + expfile.string() + " --out " +
                          out.string() + columns + " --jobs 2");
    ASSERT_EQ(r.status, 0) << r.output;
    std::printf("%s", r.output.substr(r.output.find("=== vppdem calibrate")).c_str());
    // misfit.csv: one row per friction, the mean over the 2 seeds and its interval.
    const auto m = lines_of(out / "misfit.csv");
    ASSERT_EQ(m.size(), 5u);
    EXPECT_EQ(m[0], "grains.friction,misfit,status,case,misfit_n,misfit_sd,misfit_ci95");
    std::map<std::string, std::vector<std::string>> row;
    for (std::size_t k = 1; k < m.size(); ++k) row[cells(m[k])[0]] = cells(m[k]);
    for (const char* mu : {"0", "0.3", "0.6", "0.9"}) {
        ASSERT_EQ(row.count(mu), 1u) << mu;
        EXPECT_EQ(row[mu][4], "2") << mu;  // both seeds compared
        EXPECT_GT(std::stod(row[mu][6]), 0.0) << mu;
    }
    // The mean is the mean of the runs' misfits (misfit_runs.csv), the interval Student's.
    const auto runs = lines_of(out / "misfit_runs.csv");
    ASSERT_EQ(runs.size(), 9u);
    EXPECT_EQ(runs[0], "grains.friction,simulation.seed,misfit,status,case");
    const double m1 = std::stod(cells(runs[5])[2]), m2 = std::stod(cells(runs[6])[2]);  // friction 0.6
    EXPECT_EQ(cells(runs[5])[0], "0.6");
    EXPECT_NEAR(std::stod(row["0.6"][1]), 0.5 * (m1 + m2), 1e-12);
    EXPECT_NEAR(std::stod(row["0.6"][6]), std::tan(0.475 * M_PI) * std::abs(m1 - m2) / 2.0, 1e-9);
    // The best within one grid step of 0.45, and the values whose interval overlaps the best's
    // (calibration.json "uncertainty") span the truth.
    const std::string json = slurp(out / "calibration.json");
    const double best = json_number(json, "grains.friction", "best");
    std::printf("best friction %g (truth 0.45)\n", best);
    EXPECT_LE(std::abs(best - 0.45), 0.3 + 1e-9) << json;
    const auto u = json.find("\"uncertainty\"");
    ASSERT_NE(u, std::string::npos) << json;
    const std::string range = json.substr(json.find('[', json.find("\"grains.friction\"", u)),
                                          json.find(']', json.find("\"grains.friction\"", u)) -
                                              json.find('[', json.find("\"grains.friction\"", u)) + 1);
    std::printf("friction within the best's interval: %s\n", range.c_str());
    std::vector<double> vals;
    {
        std::string inner = range.substr(1, range.size() - 2);
        std::stringstream ss(inner);
        for (std::string v; std::getline(ss, v, ',');) vals.push_back(std::stod(v));
    }
    // The best is one of them (its interval overlaps itself).
    EXPECT_NE(std::find(vals.begin(), vals.end(), best), vals.end()) << range;
    EXPECT_NEAR(json_number(json, "seeds"), 2.0, 0.0);
    EXPECT_TRUE(fs::exists(out / "calibration.png"));
    EXPECT_TRUE(fs::exists(out / "summary.csv"));
    EXPECT_TRUE(fs::exists(out / "summary_cases.csv"));

    // A failed calibration into the same folder keeps the good results and reports into
    // *_failed files: (1) an experiment no case can be compared with (a dead force channel, all
    // zero); (2) a changed study, which every case folder refuses: those cases are not compared,
    // although their folders still hold the earlier run's results.
    const std::string json_before = slurp(out / "calibration.json"), misfit_before = slurp(out / "misfit.csv");
    const std::string png_before = slurp(out / "calibration.png");
    std::string dead;
    {
        std::istringstream in(exp.str());
        std::string line;
        std::getline(in, line);  // comment
        std::getline(in, line);  // header
        dead = "t_s,stroke_mm,load_kN\n";
        while (std::getline(in, line)) dead += line.substr(0, line.find(',', line.find(',') + 1)) + ",0\n";
    }
    const fs::path deadfile = scratch("dead_channel.csv");
    write_file(deadfile, dead);
    for (const std::string& args : {"--experiment " + deadfile.string(),
                                    "--experiment " + expfile.string() + " --set process.cycles=3"}) {
        SCOPED_TRACE(args);
        const Outcome failed =
            run("calibrate " + study.string() + " " + args + " --out " + out.string() + " --no-plot" + columns);
        EXPECT_EQ(WEXITSTATUS(failed.status), 1) << failed.output;
        EXPECT_NE(failed.output.find("earlier calibration.json is kept"), std::string::npos) << failed.output;
        EXPECT_EQ(slurp(out / "calibration.json"), json_before);
        EXPECT_EQ(slurp(out / "misfit.csv"), misfit_before);
        EXPECT_EQ(slurp(out / "calibration.png"), png_before);
        const std::string report = slurp(out / "calibration_failed.json");
        EXPECT_NE(report.find("\"best\": null"), std::string::npos) << report;
        EXPECT_TRUE(fs::exists(out / "misfit_failed.csv"));
    }
}

TEST_F(Study, FailedCasesAreReportedAndDoNotStopTheOthers) {
    // 5 mm grains do not fit this damper: that case fails at once, the other runs (one cycle).
    const fs::path study = scratch("one_bad.toml"), out = scratch("one_bad");
    write_file(study, kSmallSet + "[grid]\n\"grains.radius\" = [0.005, 0.002965]\n");
    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --set process.cycles=1 --no-plot");
    EXPECT_EQ(WEXITSTATUS(r.status), 1) << r.output;
    EXPECT_NE(r.output.find("grains.radius=0.005: FAILED"), std::string::npos) << r.output;
    const auto rows = lines_of(out / "summary.csv");
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_NE(rows[1].find(",failed: "), std::string::npos) << rows[1];
    EXPECT_NE(rows[1].find("grains.radius"), std::string::npos) << rows[1];
    EXPECT_EQ(cells(rows[2])[5], "ok") << rows[2];
    EXPECT_TRUE(fs::exists(out / "grains.radius=0.005" / "FAILED"));
}

TEST_F(Study, BadStudyFilesFailClearlyAndRunNothing) {
    struct Case {
        std::string text, must_mention, also;
    };
    const std::vector<Case> cases = {
        {kSmallSet + "[gird]\n\"grains.friction\" = [0.3]\n", "gird", "unknown"},
        {kSmallSet + "[grid]\n\"grains.friction\" = []\n", "grains.friction", "empty"},
        {kSmallSet + "[grid]\n\"grains.friction\" = \"0:1\"\n", "grains.friction", "start:stop:step"},
        {kSmallSet + "[grid]\n\"grains.friction\" = \"0:1:0\"\n", "grains.friction", "step"},
        {kSmallSet + "[grid]\n\"grains.friction\" = \"0:x:0.1\"\n", "grains.friction", "'x'"},
        {kSmallSet + "[grid]\n\"grains.colour\" = [1, 2]\n", "grains.colour", "unknown"},
        {kSmallSet + "[grid]\n\"grains.friction\" = [0.3, -0.5]\n", "grains.friction", "-0.5"},
        {kSmallSet + "[grid]\n\"grains.friction\" = 0.3\n", "grains.friction", "list"},
        {kSmallSet + "[grid]\n\"grains.friction\" = [0.3, 0.3]\n", "grains.friction", "repeats"},
        {"base = \"missing.toml\"\n" + kSmallSet, "base", "not found"},
        {kSmallSet + "[grid]\n\"damper.radius\" = [0.012]\n", "damper.radius", "both"},
    };
    for (const Case& c : cases) {
        const fs::path study = scratch("bad.toml"), out = scratch("bad_out");
        fs::remove_all(out);
        write_file(study, c.text);
        const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --no-plot");
        EXPECT_NE(r.status, 0) << c.text;
        EXPECT_NE(r.output.find(c.must_mention), std::string::npos) << c.text << "\n" << r.output;
        EXPECT_NE(r.output.find(c.also), std::string::npos) << c.text << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.text;
    }
}

#ifdef VPPDEM_WITH_MPI
TEST_F(Study, MpiSweepWritesTheSameSummaryAsTheSerialOne) {
    const fs::path study = scratch("two_mpi.toml"), serial = scratch("serial"), mpi = scratch("mpi");
    write_file(study, kTwoFrictions);
    const Outcome a = run("sweep " + study.string() + " --out " + serial.string() + " --jobs 2 --no-plot --quiet");
    ASSERT_EQ(a.status, 0) << a.output;
    const Outcome b = shell("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + std::string(MPIEXEC) +
                            " --oversubscribe -n 2 " + kBinary + " sweep " + study.string() + " --out " + mpi.string() +
                            " --no-plot");
    ASSERT_EQ(b.status, 0) << b.output;
    EXPECT_NE(b.output.find("rank 1 "), std::string::npos) << b.output;  // rank 1 ran a case
    // Equal but for run_seconds (column 5).
    auto strip = [](const std::vector<std::string>& rows) {
        std::vector<std::string> out;
        for (const auto& r : rows) {
            auto c = cells(r);
            c.erase(c.begin() + 4);
            std::string j;
            for (const auto& x : c) j += x + ",";
            out.push_back(j);
        }
        return out;
    };
    EXPECT_EQ(strip(lines_of(mpi / "summary.csv")), strip(lines_of(serial / "summary.csv")));
    EXPECT_EQ(slurp(mpi / "grains.friction=0.6" / "forces.csv"), slurp(serial / "grains.friction=0.6" / "forces.csv"));
}
#endif
