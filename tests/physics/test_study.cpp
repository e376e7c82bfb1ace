// Studies through the vppdem binary on the small quick damper (56 grains, 494 foil particles):
// a sweep shares its preparation and writes summary.csv, resumes after being killed, a
// calibration recovers the friction of a synthetic experiment, bad study files fail clearly.
// --report-only rewrites a sweep's tables from its records, and tabulates hand-made records with
// their paired differences (summary_paired.csv) without simulating.
// Also the pure parts: range strings, the loop misfit.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "scene/build_info.h"
#include "scene/config.h"
#include "cli_helpers.h"
#include "dem/io/csv.h"
#include "vpp/calibration/calibrate.h"
#include "vpp/analysis/stats.h"
#include "vpp/study/study.h"
#include "vpp/study/study_progress.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_study {

namespace fs = std::filesystem;

namespace {

using namespace cli_test;


// The small damper of tests/physics/test_damper.cpp as a study's [set].
// The [set] of the tests' small damper without a time step (a study that sets its own), and with
// the tests' (tests/physics/cli_helpers.h, kSmallDamper).
const std::string kSmallSetAnyStep =
    "[set]\n"
    "\"damper.radius\" = 0.012\n"
    "\"damper.height\" = 0.03\n"
    "\"grains.volume_fraction\" = 0.45\n"
    "\"process.velocity\" = 0.1\n"
    "\"process.amplitude\" = 0.002\n"
    "\"process.cycles\" = 2\n"
    "\"process.samples_per_cycle\" = 80\n"
    "\"simulation.threads\" = 1\n"
    // mass-scaled as the feature tests' damper (cli_helpers.h, kSmallDamper)
    "\"grains.density\" = 268963.9\n"
    "\"foil.density\" = 15177\n";
const std::string kSmallSet = kSmallSetAnyStep + "\"simulation.dt_safety\" = 0.45\n";

fs::path scratch(const std::string& name) { return scratch_path("study_test", name); }

std::vector<std::string> lines_of(const fs::path& p) {
    std::vector<std::string> out;
    std::ifstream in(p);
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) out.push_back(l);
    return out;
}

// The cells of a CSV line as dem::csv_text writes them: a cell with a comma or a quote is quoted,
// its quotes doubled (a run's warnings hold both).
std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out(1);
    bool quoted = false;
    for (std::size_t k = 0; k < line.size(); ++k) {
        const char c = line[k];
        if (quoted && c == '"' && k + 1 < line.size() && line[k + 1] == '"') out.back() += line[++k];
        else if (c == '"') quoted = !quoted;
        else if (c == ',' && !quoted) out.emplace_back();
        else out.back() += c;
    }
    return out;
}

// A CSV file as rows of cells by column name.
std::vector<std::map<std::string, std::string>> table_of(const fs::path& p) {
    const auto rows = lines_of(p);
    std::vector<std::map<std::string, std::string>> out;
    if (rows.empty()) return out;
    const auto head = cells(rows[0]);
    for (std::size_t r = 1; r < rows.size(); ++r) {
        const auto c = cells(rows[r]);
        EXPECT_EQ(c.size(), head.size()) << p << ": " << rows[r];
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < head.size() && k < c.size(); ++k) row[head[k]] = c[k];
        out.push_back(row);
    }
    return out;
}

// The folders and files directly in `dir`, by name.
std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
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

// A case folder's case.toml against the study's record for it (vpp/study/records.h): the same
// record (or the same overrides in another order) is the same case, a larger process.cycles alone
// continues it, anything else (fewer
// cycles, another value, another key, another base, a record that is not TOML) is refused. Values
// with quotes and backslashes round-trip through the record's escaping.
TEST(StudyUnits, ACaseFolderAcceptsMoreCyclesAndRefusesAnyOtherChange) {
    const fs::path dir = scratch("case_folder");
    fs::remove_all(dir);
    fs::create_directories(dir);
    vpp::Study s;
    vpp::StudyCase c;
    c.overrides = {"process.cycles=5", "grains.friction=0.6", "output.note=\"a \\\"quoted\\\" path\\\\x\""};
    const std::string held = vpp::case_record(s, c);
    std::ofstream(dir / "case.toml") << held;
    auto with = [&](std::vector<std::string> overrides, const std::string& base = "") {
        vpp::Study t;
        t.base = base;
        vpp::StudyCase d;
        d.overrides = std::move(overrides);
        return vpp::case_record(t, d);
    };
    EXPECT_EQ(vpp::check_case_folder(dir, held), vpp::CaseFolder::Same);
    std::vector<std::string> more = c.overrides;
    more[0] = "process.cycles=8";
    EXPECT_EQ(vpp::check_case_folder(dir, with(more)), vpp::CaseFolder::MoreCycles);
    std::vector<std::string> fewer = c.overrides;
    fewer[0] = "process.cycles=4";
    EXPECT_THROW(vpp::check_case_folder(dir, with(fewer)), std::runtime_error);
    std::vector<std::string> other = more;
    other[1] = "grains.friction=0.8";
    EXPECT_THROW(vpp::check_case_folder(dir, with(other)), std::runtime_error);
    std::vector<std::string> note = more;
    note[2] = "output.note=\"a quoted path\"";
    EXPECT_THROW(vpp::check_case_folder(dir, with(note)), std::runtime_error);
    std::vector<std::string> extra = more;
    extra.push_back("grains.young=2.3e9");
    EXPECT_THROW(vpp::check_case_folder(dir, with(extra)), std::runtime_error);
    const fs::path base = dir / "base.toml";
    std::ofstream(base) << "[grains]\nfriction = 0.6\n";
    EXPECT_THROW(vpp::check_case_folder(dir, with(more, base.string())), std::runtime_error);
    // The last of a key wins, as in the config: a repeated key before the final value is the same case.
    std::vector<std::string> repeated = more;
    repeated.insert(repeated.begin() + 1, "grains.friction=0.1");
    EXPECT_EQ(vpp::check_case_folder(dir, with(repeated)), vpp::CaseFolder::MoreCycles);
    // The same settings in another order (an older build wrote --set before [set]): the same case;
    // with a repeated key the last one wins, so an order that changes the winner is another case.
    EXPECT_EQ(vpp::check_case_folder(dir, with({c.overrides[2], c.overrides[0], c.overrides[1]})), vpp::CaseFolder::Same);
    EXPECT_EQ(vpp::check_case_folder(dir, with({"grains.friction=0.1", c.overrides[2], c.overrides[0], c.overrides[1]})),
              vpp::CaseFolder::Same);
    EXPECT_THROW(vpp::check_case_folder(dir, with({c.overrides[0], c.overrides[1], c.overrides[2], "grains.friction=0.1"})),
                 std::runtime_error);
    std::ofstream(dir / "case.toml") << "overrides = [ not toml";
    EXPECT_THROW(vpp::check_case_folder(dir, with(more)), std::runtime_error);
    fs::remove(dir / "case.toml");
    EXPECT_EQ(vpp::check_case_folder(dir, with(other)), vpp::CaseFolder::Same);  // none yet: a new case
    fs::remove_all(dir);
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

// The study's progress line (vpp/study/study_progress.h) against its rules worked by hand: 4
// cases on 2 jobs, times in seconds.
TEST(StudyUnits, TheStudysTimeLeftFollowsTheRunningCasesAndTheFinishedOnes) {
    vpp::StudyProgress p("sweep", 4, 2, 1.0);
    p.started(0, "a", 0);
    p.started(1, "b", 0);
    p.stage(0, "prepare: fill", 256, 1000, 1);
    EXPECT_LT(p.time_left(1), 0);  // nothing cycles, nothing finished: unknown, and said so
    EXPECT_NE(p.line(1).find("time left: known once a case cycles or ends"), std::string::npos) << p.line(1);
    // a cycles at 50 steps/s (500 of 1000 at t = 20): 10 s left; b at 20 steps/s (100 -> 300 of
    // 1100 from t = 10 to 20): 40 s left. The 2 pending cases take a's total, 20 + 10 s, each:
    // (10 + 40 + 2 x 30) / 2 jobs = 55 s, longer than b's 40.
    p.stage(0, "cycle", 0, 1000, 10);
    p.stage(0, "cycle", 500, 1000, 20);
    p.stage(1, "cycle", 100, 1100, 10);
    p.stage(1, "cycle", 300, 1100, 20);
    EXPECT_DOUBLE_EQ(p.time_left(20), 55.0);
    // a ends at 25 s (the mean case now), c starts and prepares. At 30: b 40 - 10 = 30 s, c 25 - 5
    // = 20 s, the last pending case 25 s: (30 + 20 + 25) / 2 = 37.5 s.
    p.finished(0, true, 25);
    p.started(2, "c", 25);
    p.stage(2, "prepare: fill", 256, 1000, 26);
    EXPECT_DOUBLE_EQ(p.time_left(30), 37.5);
    EXPECT_EQ(p.line(30), "sweep: 1 of 4 cases done, running: b (cycle 27%), c (prepare: fill 26%); about 38s left");
    // A line when due: at once, then not before `every` (1 s) has passed.
    EXPECT_FALSE(p.due(30).empty());
    EXPECT_TRUE(p.due(30.5).empty());
    EXPECT_FALSE(p.due(31.1).empty());
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

// `vppdem analyze` reads a rig's record with calibrate's flags (columns, units, sign) and warns
// when the sign looks reversed. Closed form: rig_record's loop, 2 mm of stroke between the lines
// F = 10 d + 2 and F = 10 d - 2 [N, mm] sampled every 0.1 mm, encloses the parallelogram 4 N x
// 2 mm less its two corners cut by the sampling (0.5 x 4 N x 0.1 mm each): 7.6 N mm per cycle.
TEST(AnalyzeCommand, ReadsARigsRecordWithCalibratesFlagsAndWarnsOfAReversedSign) {
    const fs::path dir = scratch_path("analyze_rig", ""), rig = dir / "rig.csv", kn = dir / "rig_kN.csv";
    fs::remove_all(dir);
    write_file(rig, rig_record(-1.0));  // compression negative, mm and N
    std::string text = "t,stroke,load\n";  // the same in kN
    std::istringstream in(rig_record(-1.0));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        const auto c = cells(line);
        text += c[0] + "," + c[1] + "," + dem::csv_number(std::stod(c[2]) * 1e-3) + "\n";
    }
    write_file(kn, text);
    const std::string cols = " --time-column t --displacement-column stroke --force-column load --displacement-unit mm "
                             "--radius 0.012 --out ";
    const double energy = 7.6e-3, W = energy / (M_PI * 0.012 * 0.012);  // [J], [J/m^2]
    auto check_cycles = [&](const fs::path& csv) {
        const auto c = read_columns(csv);
        ASSERT_EQ(c.at("cycle").size(), 3u) << slurp(csv);
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_NEAR(c.at("dissipated_energy")[k], energy, 1e-6 * energy) << k;
            EXPECT_NEAR(c.at("W")[k], W, 1e-6 * W) << k;
        }
    };
    // Read as it is: the loop looks reversed, and the warning names the flag.
    const Outcome as_is = run("analyze " + rig.string() + cols + (dir / "as_is.csv").string());
    ASSERT_EQ(as_is.status, 0) << as_is.output;
    EXPECT_NE(as_is.output.find("warning: '" + rig.string() + "' looks the other way round"), std::string::npos)
        << as_is.output;
    EXPECT_NE(as_is.output.find("pass --compression-negative"), std::string::npos) << as_is.output;
    // With the flag: no warning, the three cycles of the closed form.
    const Outcome flipped =
        run("analyze " + rig.string() + cols + (dir / "flipped.csv").string() + " --compression-negative");
    ASSERT_EQ(flipped.status, 0) << flipped.output;
    EXPECT_EQ(flipped.output.find("warning"), std::string::npos) << flipped.output;
    check_cycles(dir / "flipped.csv");
    // The same record in kN, read with --force-unit kN: the same cycles.
    const Outcome in_kn = run("analyze " + kn.string() + cols + (dir / "kn.csv").string() +
                              " --compression-negative --force-unit kN");
    ASSERT_EQ(in_kn.status, 0) << in_kn.output;
    check_cycles(dir / "kn.csv");
    // The flag on a compression-positive record: warned, saying to drop it.
    write_file(rig, rig_record(1.0));
    const Outcome wrong_flag =
        run("analyze " + rig.string() + cols + (dir / "wrong_flag.csv").string() + " --compression-negative");
    ASSERT_EQ(wrong_flag.status, 0) << wrong_flag.output;
    EXPECT_NE(wrong_flag.output.find("drop --compression-negative"), std::string::npos) << wrong_flag.output;
    const Outcome right = run("analyze " + rig.string() + cols + (dir / "right.csv").string());
    EXPECT_EQ(right.output.find("warning"), std::string::npos) << right.output;
    check_cycles(dir / "right.csv");
    fs::remove_all(dir);
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

// Issue 62: one seed has no interval: a one-seed calibration says so instead of listing the
// grid points "within its interval" (the points of equal misfit); with two seeds it lists them.
TEST_F(Study, AOneSeedCalibrationSaysItHasNoInterval) {
    const fs::path study = scratch("one_seed.toml"), out = scratch("one_seed"), truth = scratch("one_seed_truth");
    write_file(study, kTwoFrictions);
    const Outcome t = run("damper --out " + truth.string() + " " + kSmallDamper + " --set grains.friction=0.45");
    ASSERT_EQ(t.status, 0) << t.output;
    const Outcome r = run("calibrate " + study.string() + " --experiment " + (truth / "forces.csv").string() +
                          " --force-column force_zeroed --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("over 1 seed(s)); one seed: no interval (run --seeds 2 or more for one)"), std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("within its interval"), std::string::npos) << r.output;
    // The runs' warnings are passed on, once per kind (the small damper at 0.1 m/s is not
    // quasi-static); the plot adds none of its own (an empty legend made matplotlib warn).
    EXPECT_NE(r.output.find("WARNING: runs: not quasi-static: 2 of 2 runs (grains.friction=0.3, grains.friction=0.6)"),
              std::string::npos)
        << r.output;
    EXPECT_TRUE(fs::exists(out / "calibration.png")) << r.output;
    for (const char* leak : {"UserWarning", "No artists", "matplotlib"}) EXPECT_EQ(r.output.find(leak), std::string::npos) << leak << r.output;
    // An interval of the best value alone (nothing to shade) drew an empty legend box, and
    // matplotlib warned: the legend now holds the misfit curve and the best value.
    auto cal = nlohmann::json::parse(slurp(out / "calibration.json"));
    cal["uncertainty"] = {{"grains.friction", {0.3}}};
    write_file(out / "calibration.json", cal.dump());
    const Outcome p = run("plot " + out.string());
    ASSERT_EQ(p.status, 0) << p.output;
    for (const char* leak : {"UserWarning", "No artists", "matplotlib"}) EXPECT_EQ(p.output.find(leak), std::string::npos) << leak << p.output;
}

// Issue 46: a study refuses a folder whose cases another build ran (their build.json), naming the
// cases and both builds, before it runs or writes anything; --mix-builds is the way on. Every run
// records its build: `vppdem --version` names the same one.
TEST_F(Study, AFolderOfAnotherBuildsRunsIsRefusedUnlessMixBuildsIsGiven) {
    const fs::path study = scratch("builds.toml"), out = scratch("builds_out");
    write_file(study, kTwoFrictions);
    const std::string other = R"({"commit": "0123abcd-dirty", "id": "00000000000000aa"})";
    write_file(out / "grains.friction=0.6" / "build.json", other + "\n");
    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --jobs 1 --no-plot");
    EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
    EXPECT_NE(r.output.find("grains.friction=0.6 (commit 0123abcd-dirty, build 00000000000000aa)"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(std::string("build ") + scene::build_id()), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--mix-builds"), std::string::npos) << r.output;
    // Nothing run or written: the other case has no folder, this one only its record.
    EXPECT_FALSE(fs::exists(out / "grains.friction=0.3"));
    EXPECT_EQ(entries(out / "grains.friction=0.6"), std::vector<std::string>{"build.json"});
    EXPECT_EQ(slurp(out / "grains.friction=0.6" / "build.json"), other + "\n");
    // --list and --report-only read, they do not refuse.
    EXPECT_EQ(run("sweep " + study.string() + " --out " + out.string() + " --list").status, 0);

    const Outcome v = run("--version");
    EXPECT_EQ(v.status, 0) << v.output;
    EXPECT_NE(v.output.find(std::string(scene::build_commit()) + " (build " + scene::build_id() + ")"), std::string::npos)
        << v.output;
}

TEST_F(Study, SweepSharesOnePreparationAndWritesTheSummary) {
    const fs::path study = scratch("two.toml"), out = scratch("sweep");
    write_file(study, kTwoFrictions);
    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --jobs 2 --no-plot");
    ASSERT_EQ(r.status, 0) << r.output;
    // Every case records the build that ran it (build.json).
    for (const char* c : {"grains.friction=0.3", "grains.friction=0.6"}) {
        const auto b = scene::read_build_record((out / c).string());
        ASSERT_TRUE(b.has_value()) << c;
        ASSERT_EQ(b->size(), 1u) << c;
        EXPECT_EQ(b->front().id, scene::build_id()) << c;
    }
    const std::string summary = slurp(out / "summary.csv"), summary_cases = slurp(out / "summary_cases.csv");
    EXPECT_FALSE(fs::exists(out / "summary_paired.csv"));  // no seeds, nothing to pair
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
    // --report-only reads the finished cases back into the very tables the sweep wrote (run
    // time included: summary.json keeps it to the last bit), and touches no case.
    fs::remove(out / "summary.csv");
    fs::remove(out / "summary_cases.csv");
    const auto stamp = fs::last_write_time(c2 / "summary.json");
    const Outcome report = run("sweep " + study.string() + " --out " + out.string() + " --report-only");
    ASSERT_EQ(report.status, 0) << report.output;
    EXPECT_NE(report.output.find("2 of 2 cases finished"), std::string::npos) << report.output;
    EXPECT_EQ(slurp(out / "summary.csv"), summary);
    EXPECT_EQ(slurp(out / "summary_cases.csv"), summary_cases);
    EXPECT_EQ(fs::last_write_time(c2 / "summary.json"), stamp);
    EXPECT_FALSE(fs::exists(out / "sweep_W.png"));  // no plot
}

namespace {

// Per-case numbers of the fabricated sweep below: friction index f, underpressure index p,
// seed s (1..3). The seed moves W and the peak force by a few per cent, differently at each
// friction and underpressure, so the paired differences scatter.
double fake_W(int f, int p, int s) { return 100.0 + 40.0 * f + 25.0 * p + 3.0 * s * s * (1 + f) - 2.0 * s * p; }
double fake_peak(int f, int p, int s) { return 200.0 + 10.0 * f + 7.0 * p + 5.0 * s + f * s + 1.5 * s * s * p; }

// A finished case folder as the damper leaves it, by hand: cycles.csv (4 cycles of W within 0.4%
// of `W`, which the stationarity test settles; the dissipation split when `energy`) and
// summary.json. No case.toml: a folder without one is accepted, as by a resumed sweep.
void fabricate_case(const fs::path& dir, double W, double peak, bool energy, double friction_dissipation) {
    std::ostringstream cyc;
    cyc.precision(17);
    cyc << "cycle,dissipated_energy,W,peak_force,min_force"
        << (energy ? ",friction_dissipation,damping_dissipation,viscous_dissipation" : "") << "\n";
    const double wiggle[4] = {1.004, 0.997, 1.001, 1.0};
    for (int k = 0; k < 4; ++k) {
        const double w = W * wiggle[k];
        cyc << k + 1 << "," << w * 4.5e-4 << "," << w << "," << peak * wiggle[k] << ",-3";  // [J], [J/m^2], [N]
        if (energy) cyc << "," << friction_dissipation << ",0.3,0";
        cyc << "\n";
    }
    write_file(dir / "cycles.csv", cyc.str());
    write_file(dir / "summary.json", "{\"grains\": 60, \"preparation\": {\"packing_fraction\": 0.61}, "
                                     "\"warnings\": [\"a hand-made record\"], \"run_seconds\": 12.5}\n");
}

}  // namespace

// --report-only on a sweep folder whose records were written by hand (nothing simulated): the
// finished cases are read, the others marked "not run", no folder or marker is made, and
// summary_paired.csv holds the seed-by-seed differences of summary.csv's own numbers.
TEST_F(Study, ReportOnlyTabulatesTheFinishedCasesAndPairsTheSeeds) {
    const fs::path study = scratch("report.toml"), out = scratch("report");
    write_file(study, "seeds = 3\n" + kSmallSet +
                          "[grid]\n\"grains.friction\" = [0.3, 0.6]\n\"process.underpressure\" = [0.02e6, 0.06e6]\n");
    const char* friction[2] = {"0.3", "0.6"};
    const char* dp[2] = {"20000", "60000"};
    auto name = [&](int f, int p, int s) {
        return std::string("grains.friction=") + friction[f] + "_process.underpressure=" + dp[p] +
               "_simulation.seed=" + std::to_string(s);
    };
    // Not finished: friction 0.3, 0.06 MPa, seed 2 (failed earlier: FAILED, no summary.json) and
    // friction 0.6, 0.06 MPa, seed 3 (never started: no folder). The energy ledger only at 0.02
    // MPa: at 0.06 MPa the shares are empty.
    for (int f = 0; f < 2; ++f)
        for (int p = 0; p < 2; ++p)
            for (int s = 1; s <= 3; ++s) {
                if ((f == 0 && p == 1 && s == 2) || (f == 1 && p == 1 && s == 3)) continue;
                fabricate_case(out / name(f, p, s), fake_W(f, p, s), fake_peak(f, p, s), p == 0, 0.5 + 0.1 * f + 0.03 * s);
            }
    write_file(out / name(0, 1, 2) / "FAILED", "an earlier failure\n");
    const auto before = entries(out);
    const std::string failed_dir = slurp(out / name(0, 1, 2) / "FAILED");

    // A folder that does not exist: refused, naming it, and not created.
    const Outcome missing = run("sweep " + study.string() + " --out " + (out / "nowhere").string() + " --report-only");
    EXPECT_NE(missing.status, 0) << missing.output;
    EXPECT_NE(missing.output.find((out / "nowhere").string() + "': no such folder"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(out / "nowhere"));

    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --report-only");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("10 of 12 cases finished"), std::string::npos) << r.output;
    // Only the three tables are new; the failed case keeps its marker and gets no case.toml.
    std::vector<std::string> expected = before;
    for (const char* f : {"summary.csv", "summary_cases.csv", "summary_paired.csv"}) expected.push_back(f);
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(entries(out), expected);
    EXPECT_EQ(slurp(out / name(0, 1, 2) / "FAILED"), failed_dir);
    EXPECT_FALSE(fs::exists(out / name(0, 1, 2) / "case.toml"));

    // summary.csv: 12 rows in grid order; the unfinished ones "not run" with empty numbers.
    const auto sum = table_of(out / "summary.csv");
    ASSERT_EQ(sum.size(), 12u);
    std::map<std::string, std::map<std::string, std::string>> by_case;
    for (const auto& row : sum) by_case[row.at("case")] = row;
    for (const std::string& n : {name(0, 1, 2), name(1, 1, 3)}) {
        const auto& row = by_case.at(n);
        EXPECT_EQ(row.at("status"), "not run") << n;
        for (const char* col : {"W", "dissipated_energy", "peak_force", "run_seconds", "W_settled", "settled_cycles",
                                "friction_share", "grains", "packing_fraction", "warnings"})
            EXPECT_EQ(row.at(col), "") << n << " " << col;
    }
    const auto& ok = by_case.at(name(1, 0, 2));
    EXPECT_EQ(ok.at("status"), "ok");
    EXPECT_EQ(std::stod(ok.at("W")), fake_W(1, 0, 2));
    EXPECT_EQ(ok.at("settled_cycles"), "4");
    EXPECT_EQ(ok.at("run_seconds"), "12.5");
    EXPECT_EQ(ok.at("warnings"), "a hand-made record");
    EXPECT_NEAR(std::stod(ok.at("friction_share")), 0.66 / 0.96, 1e-12);  // 0.5 + 0.1 + 0.03 * 2 of 0.66 + 0.3 + 0
    EXPECT_EQ(by_case.at(name(1, 1, 2)).at("friction_share"), "");  // no ledger at 0.06 MPa
    // summary_cases.csv: the statistics over the finished runs only.
    const auto cases = table_of(out / "summary_cases.csv");
    ASSERT_EQ(cases.size(), 4u);
    EXPECT_EQ(cases[3].at("seeds"), "3");
    EXPECT_EQ(cases[3].at("ok"), "2");
    EXPECT_EQ(std::stod(cases[3].at("W_mean")), 0.5 * (fake_W(1, 1, 1) + fake_W(1, 1, 2)));

    // summary_paired.csv against summary.csv by hand.
    const auto paired = table_of(out / "summary_paired.csv");
    EXPECT_EQ(lines_of(out / "summary_paired.csv")[0],
              "key,value,reference,group,quantity,n,diff_mean,diff_sd,diff_ci95,ref_mean,rel_diff");
    // friction: 2 groups (one per underpressure), underpressure: 2 (one per friction); 6 quantities.
    ASSERT_EQ(paired.size(), 24u);
    auto value = [&](int f, int p, int s, const std::string& q) {
        const auto& row = by_case.at(name(f, p, s));
        return row.at("status") == "ok" && !row.at(q).empty() ? std::stod(row.at(q)) : NAN;
    };
    auto find = [&](const std::string& key, const std::string& group, const std::string& q) {
        for (const auto& row : paired)
            if (row.at("key") == key && row.at("group") == group && row.at("quantity") == q) return row;
        ADD_FAILURE() << "no row " << key << " " << group << " " << q;
        return std::map<std::string, std::string>{};
    };
    std::size_t rows_checked = 0;
    for (int axis = 0; axis < 2; ++axis)
        for (int other = 0; other < 2; ++other)
            for (const std::string& q : vpp::kPairedQuantities) {
                const std::string key = axis == 0 ? "grains.friction" : "process.underpressure";
                const std::string group = axis == 0 ? std::string("process.underpressure=") + dp[other]
                                                    : std::string("grains.friction=") + friction[other];
                const auto row = find(key, group, q);
                if (row.empty()) continue;
                EXPECT_EQ(row.at("value"), axis == 0 ? "0.6" : "60000");
                EXPECT_EQ(row.at("reference"), axis == 0 ? "0.3" : "20000");
                std::vector<double> d, ref;
                for (int s = 1; s <= 3; ++s) {
                    const double x = axis == 0 ? value(1, other, s, q) : value(other, 1, s, q);
                    const double y = axis == 0 ? value(0, other, s, q) : value(other, 0, s, q);
                    if (std::isnan(x) || std::isnan(y)) continue;
                    d.push_back(x - y);
                    ref.push_back(y);
                }
                const vpp::Interval iv = vpp::mean_interval(d);
                SCOPED_TRACE(key + " " + group + " " + q);
                ASSERT_EQ(row.at("n"), std::to_string(d.size()));
                auto expect = [&](const char* col, double v) {
                    if (std::isnan(v)) EXPECT_EQ(row.at(col), "") << col;
                    else EXPECT_NEAR(std::stod(row.at(col)), v, 1e-12 * (1 + std::abs(v))) << col;
                };
                expect("diff_mean", iv.mean);
                expect("diff_sd", iv.sd);
                expect("diff_ci95", iv.half);
                const double ref_mean = ref.empty() ? NAN : vpp::mean_interval(ref).mean;
                expect("ref_mean", ref_mean);
                expect("rel_diff", iv.mean / ref_mean);
                ++rows_checked;
            }
    EXPECT_EQ(rows_checked, 24u);
    // Independently of vpp::mean_interval. All three seeds (friction at 0.02 MPa): t_{0.975,2} =
    // 0.95 / sqrt(2 * 0.975 * 0.025) = 4.303, ci = t sd / sqrt(3).
    {
        double d[3], m = 0, ss = 0;
        for (int s = 1; s <= 3; ++s) m += (d[s - 1] = fake_W(1, 0, s) - fake_W(0, 0, s)) / 3.0;
        for (double x : d) ss += (x - m) * (x - m);
        const auto row = find("grains.friction", "process.underpressure=20000", "W");
        EXPECT_EQ(row.at("n"), "3");
        EXPECT_NEAR(std::stod(row.at("diff_mean")), m, 1e-9);
        EXPECT_NEAR(std::stod(row.at("diff_ci95")), 0.95 / std::sqrt(2 * 0.975 * 0.025) * std::sqrt(ss / 2) / std::sqrt(3.0),
                    1e-9);
    }
    // Two seeds (underpressure at friction 0.3: seed 2 did not run at 0.06 MPa): t_{0.975,1} =
    // tan(0.475 pi) = 12.706, ci = t |d1 - d3| / 2; the reference mean over seeds 1 and 3 only.
    {
        const double d1 = fake_peak(0, 1, 1) - fake_peak(0, 0, 1), d3 = fake_peak(0, 1, 3) - fake_peak(0, 0, 3);
        const auto row = find("process.underpressure", "grains.friction=0.3", "peak_force");
        EXPECT_EQ(row.at("n"), "2");
        EXPECT_NEAR(std::stod(row.at("diff_ci95")), std::tan(0.475 * M_PI) * std::abs(d1 - d3) / 2.0, 1e-9);
        EXPECT_NEAR(std::stod(row.at("ref_mean")), 0.5 * (fake_peak(0, 0, 1) + fake_peak(0, 0, 3)), 1e-9);
    }
    // One seed paired (friction at 0.06 MPa: seed 1 only): sd and ci95 empty; no ledger there: n = 0.
    EXPECT_EQ(find("grains.friction", "process.underpressure=60000", "W").at("n"), "1");
    EXPECT_EQ(find("grains.friction", "process.underpressure=60000", "W").at("diff_ci95"), "");
    const auto none = find("grains.friction", "process.underpressure=60000", "friction_share");
    EXPECT_EQ(none.at("n"), "0");
    for (const char* col : {"diff_mean", "diff_sd", "diff_ci95", "ref_mean", "rel_diff"}) EXPECT_EQ(none.at(col), "") << col;
}

TEST_F(Study, SweepResumesAfterBeingKilled) {
    const fs::path study = scratch("two_kill.toml"), out = scratch("killed");
    write_file(study, kTwoFrictions);
    const fs::path c1 = out / "grains.friction=0.3", c2 = out / "grains.friction=0.6";
    // One job: the preparing case first, then the branch. Kill the sweep while the branch runs.
    const std::string cmd = "exec " + kBinary + " sweep " + study.string() + " --out " + out.string() +
                            " --jobs 1 --no-plot --quiet --checkpoint-every 0.03 > /dev/null 2>&1";
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd.c_str(), (char*)nullptr);
        _exit(127);
    }
    const auto t0 = std::chrono::steady_clock::now();
    bool branch_started = false;
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 120.0 * time_scale()) {
        if (fs::exists(c1 / "summary.json") && fs::exists(c2 / "run.ckpt")) {
            branch_started = true;
            break;
        }
        if (waitpid(pid, nullptr, WNOHANG) == pid) break;  // finished (too fast to kill) or died
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    ASSERT_TRUE(branch_started) << "the sweep did not reach its second case";
    ASSERT_FALSE(fs::exists(c2 / "summary.json")) << "the second case finished before the kill";
    ASSERT_FALSE(fs::exists(out / "summary.csv"));
    ASSERT_TRUE(fs::exists(out / ".vppdem.lock"));  // stale: the resumed sweep takes it over
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
    for (const fs::path& dir : {out, c1, c2}) EXPECT_FALSE(fs::exists(dir / ".vppdem.lock")) << dir;
}

TEST_F(Study, ASecondSweepIntoAFolderInUseIsRefused) {
    // One sweep at a time writes into a study folder (docs/studies.md, "Resuming"): a second one
    // is refused with the folder and the first's pid; a report may run beside it.
    const fs::path study = scratch("two_in_use.toml"), out = scratch("in_use"), log = scratch("in_use.log");
    write_file(study, kTwoFrictions);
    const std::string args = "sweep " + study.string() + " --out " + out.string() + " --jobs 1 --no-plot";
    const pid_t first = start(args + " --quiet", log);
    ASSERT_GT(first, 0);
    ASSERT_TRUE(wait_while_running(first, [&] { return fs::exists(out / "grains.friction=0.3" / "run.ckpt"); })) << slurp(log);
    std::optional<Held> stopped(first);  // the small sweep may end within the next step otherwise
    ASSERT_TRUE(stopped->held()) << slurp(log);
    const Outcome second = run(args);
    stopped.reset();
    std::printf("second sweep: exit status %d: %s", WEXITSTATUS(second.status), second.output.c_str());
    EXPECT_EQ(WEXITSTATUS(second.status), 2) << second.output;
    EXPECT_NE(second.output.find("folder '" + out.string() + "' is in use by another run (pid " + std::to_string(first)),
              std::string::npos)
        << second.output;
    const Outcome report = run(args + " --report-only");
    EXPECT_EQ(report.status, 0) << report.output;
    EXPECT_EQ(finish(first), 0) << slurp(log);
    const auto rows = lines_of(out / "summary.csv");
    ASSERT_EQ(rows.size(), 3u);
    for (int k = 1; k <= 2; ++k) EXPECT_EQ(cells(rows[std::size_t(k)])[5], "ok") << rows[std::size_t(k)];
    EXPECT_FALSE(fs::exists(out / ".vppdem.lock"));
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
                          "--set grains.friction=0.45 --set simulation.seed=11 --set simulation.dt_safety=0.45" +
                          kMassScaled + " --no-plot --quiet");
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
    EXPECT_NE(r.output.find("over 2 seed(s)); within its interval: grains.friction in {"), std::string::npos) << r.output;
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
    EXPECT_EQ(data_rows(out / "summary_paired.csv"), 3u * vpp::kPairedQuantities.size());  // 0.3, 0.6, 0.9 against 0

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
                                    "--experiment " + expfile.string() + " --set process.velocity=0.05"}) {
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

    // Issue 48: a unit slip (--force-unit kN on data in N replaced calibration.json) makes the
    // measured peak force 1000 times the simulated: counted failed, the good results kept, and
    // said on stderr with --quiet and in calibration_failed.json "warnings". The cases are done:
    // this only compares.
    {
        std::string cols = columns;
        cols.replace(cols.find(" --force-unit kN"), 16, " --force-unit N");
        const Outcome slip = run("calibrate " + study.string() + " --experiment " + expfile.string() + " --out " +
                                 out.string() + " --no-plot --quiet" + cols);
        EXPECT_EQ(WEXITSTATUS(slip.status), 1) << slip.output;
        EXPECT_NE(slip.output.find("implausible units"), std::string::npos) << slip.output;
        EXPECT_NE(slip.output.find("check --force-unit (now N)"), std::string::npos) << slip.output;
        EXPECT_EQ(slurp(out / "calibration.json"), json_before);
        EXPECT_NE(slurp(out / "calibration_failed.json").find("check --force-unit (now N)"), std::string::npos);
    }
    // The displacement's slip shows against process.amplitude before anything runs: exit 2.
    {
        std::string cols = columns;
        cols.replace(cols.find(" --displacement-unit mm"), 23, " --displacement-unit m");
        const Outcome slip = run("calibrate " + study.string() + " --experiment " + expfile.string() + " --out " +
                                 out.string() + " --no-plot --quiet" + cols);
        EXPECT_EQ(WEXITSTATUS(slip.status), 2) << slip.output;
        EXPECT_NE(slip.output.find("implausible units"), std::string::npos) << slip.output;
        EXPECT_NE(slip.output.find("check --displacement-unit (now m)"), std::string::npos) << slip.output;
        EXPECT_EQ(slurp(out / "calibration.json"), json_before);
    }
    // A stroke 1.5 times the simulated one: a calibration, but warned on stderr with --quiet
    // and in calibration.json (the warning was printed only without --quiet, and not kept).
    std::string longer = "t_s,stroke_mm,load_kN\n";
    for (const auto& r : rows) {
        char line[160];
        std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g\n", r[0], -(1.5e3 * r[1]), -(1e-3 * r[5]));
        longer += line;
    }
    const fs::path longfile = scratch("longer_stroke.csv");
    write_file(longfile, longer);
    const Outcome warned = run("calibrate " + study.string() + " --experiment " + longfile.string() + " --out " +
                               out.string() + " --no-plot --quiet" + columns);
    EXPECT_NE(warned.output.find("simulated stroke"), std::string::npos) << warned.output;
    EXPECT_NE(slurp(out / "calibration.json").find("simulated stroke"), std::string::npos);
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

// --backend batch (docs/gpu.md): the running cases' cycling stepped in lockstep through one batch
// of the batch engine's host backend gives the files of --backend cpu byte for byte: three
// underpressures branching from one preparation, two at a time (so the batch also takes a case
// in and lets one go mid-run); --backend cuda on the emulated device too. --backend cuda without
// a CUDA build or a device is refused before anything is written.
// A study given more cycles (process.cycles raised, here on the command line) continues its
// finished cases from their run.ckpt: each case's records are then those of a sweep run with
// that many cycles from the start, bit for bit; --report-only counts a case that has fewer
// cycles than the study asks as not run. A folder without run.ckpt is refused, not rerun.
TEST_F(Study, MoreCyclesContinueTheFinishedCases) {
    std::string set = kSmallSet;
    const std::string two = "\"process.cycles\" = 2\n";
    set.replace(set.find(two), two.size(), "\"process.cycles\" = 1\n");
    const fs::path one = scratch("more_cycles.toml"), whole_study = scratch("more_cycles_whole.toml");
    const std::string grid = "[grid]\n\"process.underpressure\" = [0.04e6, 0.08e6]\n";
    write_file(one, set + grid);
    write_file(whole_study, kSmallSet + grid);
    const fs::path out = scratch("more_cycles"), whole = scratch("more_cycles_whole");
    ASSERT_EQ(run("sweep " + one.string() + " --out " + out.string() + " --jobs 1 --no-plot --quiet").status, 0);
    // Asked for 2 before it ran them: both cases not run yet.
    const Outcome before = run("sweep " + one.string() + " --out " + out.string() + " --report-only --set process.cycles=2");
    ASSERT_EQ(before.status, 0) << before.output;
    EXPECT_NE(before.output.find("0 of 2 cases finished"), std::string::npos) << before.output;
    const Outcome more = run("sweep " + one.string() + " --out " + out.string() + " --jobs 1 --no-plot --set process.cycles=2");
    ASSERT_EQ(more.status, 0) << more.output;
    EXPECT_EQ(more.output.find("done earlier"), std::string::npos) << more.output;
    ASSERT_EQ(run("sweep " + whole_study.string() + " --out " + whole.string() + " --jobs 1 --no-plot --quiet").status, 0);
    int cases = 0;
    for (const auto& e : fs::directory_iterator(whole)) {
        if (!e.is_directory()) continue;
        ++cases;
        for (const char* f : {"forces.csv", "cycles.csv", "energy.csv"})
            EXPECT_EQ(slurp(e.path() / f), slurp(out / e.path().filename() / f)) << e.path().filename() << "/" << f;
    }
    EXPECT_EQ(cases, 2);
    const auto rows = table_of(out / "summary.csv"), ref = table_of(whole / "summary.csv");
    ASSERT_EQ(rows.size(), 2u);
    ASSERT_EQ(ref.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(rows[k].at("W"), ref[k].at("W"));
    // Again: finished now, nothing runs.
    const Outcome again = run("sweep " + one.string() + " --out " + out.string() + " --jobs 1 --no-plot --set process.cycles=2");
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("done earlier"), std::string::npos) << again.output;
    // Records without run.ckpt (published elsewhere): refused, nothing replaced.
    const fs::path c = out / "process.underpressure=40000";
    ASSERT_TRUE(fs::exists(c / "run.ckpt")) << entries(out).size();
    fs::remove(c / "run.ckpt");
    const std::string forces = slurp(c / "forces.csv");
    const Outcome bare = run("sweep " + one.string() + " --out " + out.string() + " --jobs 1 --no-plot --set process.cycles=3");
    EXPECT_NE(bare.status, 0);
    EXPECT_NE(bare.output.find("no run.ckpt to continue from to 3"), std::string::npos) << bare.output;
    EXPECT_EQ(slurp(c / "forces.csv"), forces);
}

// A study run again with more seeds reuses the run it made without them: the seed-less folder is
// the run of seed 1 (the config's seed), renamed to that case's name and skipped; only seed 2 runs.
TEST_F(Study, RunAgainWithSeedsReusesTheRunMadeWithout) {
    std::string set = kSmallSet;
    const std::string two = "\"process.cycles\" = 2\n";
    set.replace(set.find(two), two.size(), "\"process.cycles\" = 1\n");
    const fs::path study = scratch("reseed.toml"), out = scratch("reseed");
    write_file(study, set + "[grid]\n\"grains.friction\" = [0.3]\n");
    const std::string args = "sweep " + study.string() + " --out " + out.string() + " --jobs 1 --no-plot";
    ASSERT_EQ(run(args + " --quiet").status, 0);
    const fs::path bare = out / "grains.friction=0.3";
    ASSERT_TRUE(fs::exists(bare / "forces.csv"));
    const std::string forces = slurp(bare / "forces.csv");
    // Of other settings, the seed-less folder is not taken (the sweep would run the case anew).
    const vpp::Study changed = vpp::load_study(study.string(), {"process.amplitude=0.0015"}, 2);
    EXPECT_TRUE(vpp::adopt_seedless_runs(out, changed, vpp::expand_study(changed)).empty());
    EXPECT_TRUE(fs::exists(bare / "forces.csv"));
    // Of the same settings, it is seed 1's run: renamed, skipped, only seed 2 runs.
    const Outcome again = run(args + " --seeds 2 --progress-every 0.01");
    ASSERT_EQ(again.status, 0) << again.output;
    // The study's progress line while seed 2 runs (seed 1 done earlier).
    EXPECT_NE(again.output.find("sweep: 1 of 2 cases done, running: grains.friction=0.3_simulation.seed=2 (prepare: fill"),
              std::string::npos)
        << again.output;
    EXPECT_NE(again.output.find("1 run(s) of this study without seeds reused as their seed's: "
                                "grains.friction=0.3_simulation.seed=1"),
              std::string::npos)
        << again.output;
    EXPECT_NE(again.output.find("grains.friction=0.3_simulation.seed=1: done earlier"), std::string::npos)
        << again.output;
    EXPECT_FALSE(fs::exists(bare));  // not left beside the new names
    EXPECT_EQ(slurp(out / "grains.friction=0.3_simulation.seed=1" / "forces.csv"), forces);
    EXPECT_TRUE(fs::exists(out / "grains.friction=0.3_simulation.seed=2" / "summary.json"));
}

TEST_F(Study, TheBatchBackendWritesTheCpuBackendsFiles) {
    std::string set = kSmallSet;
    const std::string two = "\"process.cycles\" = 2\n";
    set.replace(set.find(two), two.size(), "\"process.cycles\" = 1\n");
    const fs::path study = scratch("backend.toml"), cpu = scratch("backend_cpu"), batch = scratch("backend_batch");
    const std::string grid = "[grid]\n\"process.underpressure\" = [0.04e6, 0.06e6, 0.08e6]\n";
    write_file(study, set + grid);
    const Outcome a = run("sweep " + study.string() + " --out " + cpu.string() + " --jobs 1 --no-plot");
    ASSERT_EQ(a.status, 0) << a.output;
    // The batch sweeps take the CPU sweep's samples (samples_from), so that their two workers
    // start cycling together: a worker that had to wait for another's preparation could, on a
    // loaded machine, start after the other's short run had ended (CI once saw "up to 1 runs at
    // once"). Two cases sharing the batch is still a matter of the threads' timing, so a sweep
    // where they did not is run again into a new folder (at most 3 times).
    const fs::path from_cpu = scratch("backend_from_cpu.toml");
    write_file(from_cpu, "samples_from = \"" + cpu.string() + "\"\n" + set + grid);
    const auto shared_sweep = [&](const std::string& env, const fs::path& out, const std::string& backend) {
        Outcome o;
        for (int attempt = 0; attempt < 3; ++attempt) {
            const fs::path dir = attempt == 0 ? out : fs::path(out.string() + "_" + std::to_string(attempt));
            o = shell(env + kBinary + " sweep " + from_cpu.string() + " --out " + dir.string() + " --jobs 2 --backend " +
                      backend + " --no-plot");
            if (o.status != 0 || o.output.find("up to 2 runs at once") != std::string::npos || attempt == 2) {
                if (dir != out) fs::rename(dir, out);
                break;
            }
            fs::remove_all(dir);
        }
        return o;
    };
    const Outcome b = shared_sweep("", batch, "batch");
    ASSERT_EQ(b.status, 0) << b.output;
    EXPECT_NE(b.output.find("matched by preparation): 1 of 1 preparation(s)"), std::string::npos) << b.output;
    int cases = 0;
    for (const auto& e : fs::directory_iterator(cpu)) {
        if (!e.is_directory()) continue;
        ++cases;
        const fs::path other = batch / e.path().filename();
        for (const char* f : {"forces.csv", "cycles.csv", "energy.csv"})
            EXPECT_EQ(slurp(e.path() / f), slurp(other / f)) << e.path().filename() << "/" << f;
        // summary.json but for the wall-clock time and the folder it started from.
        const auto without_time = [](const fs::path& p) {
            std::string out;
            for (const std::string& l : lines_of(p))
                if (l.find("run_seconds") == std::string::npos && l.find("\"from\"") == std::string::npos) out += l + "\n";
            return out;
        };
        EXPECT_EQ(without_time(e.path() / "summary.json"), without_time(other / "summary.json")) << e.path().filename();
    }
    EXPECT_EQ(cases, 3);
    // Two cases did share the batch.
    EXPECT_NE(b.output.find("up to 2 runs at once"), std::string::npos) << b.output;
    // --backend cuda on the emulated device (the device backend's kernels and its exchange with
    // World, run on the host): the same files again.
    // The device runs each case's steps between its samples by itself (chunks of up to 256 steps,
    // the window's forces summed on the device): a case's cycling is then over before the next
    // one has left its vacuum stage, so the sharing is checked in chunks of one step
    // (VPPDEM_CHUNK=1: the same exchange, steps as slow as before).
    const fs::path emulated = scratch("backend_emulated"), emulated1 = scratch("backend_emulated_chunk1");
    const Outcome d = shell("VPPDEM_EMULATE_DEVICE=1 " + kBinary + " sweep " + from_cpu.string() + " --out " +
                            emulated.string() + " --jobs 2 --backend cuda --no-plot");
    ASSERT_EQ(d.status, 0) << d.output;
    const Outcome d1 = shared_sweep("VPPDEM_EMULATE_DEVICE=1 VPPDEM_CHUNK=1 ", emulated1, "cuda");
    ASSERT_EQ(d1.status, 0) << d1.output;
    EXPECT_NE(d1.output.find("up to 2 runs at once"), std::string::npos) << d1.output;
    for (const fs::path& dir : {emulated, emulated1})
        for (const auto& e : fs::directory_iterator(cpu)) {
            if (!e.is_directory()) continue;
            for (const char* f : {"forces.csv", "cycles.csv", "energy.csv"})
                EXPECT_EQ(slurp(e.path() / f), slurp(dir / e.path().filename() / f)) << dir.filename() << "/" << e.path().filename() << "/" << f;
        }
    // Without a CUDA build (or without a device) --backend cuda is refused before anything is
    // written, with exit status 2, naming the option to build with (or the missing device).
    const fs::path none = scratch("backend_cuda");
    const Outcome c = shell("env -u VPPDEM_EMULATE_DEVICE " + kBinary + " sweep " + study.string() + " --out " + none.string() +
                            " --backend cuda --no-plot");
    EXPECT_TRUE(WIFEXITED(c.status) && WEXITSTATUS(c.status) == 2) << c.status << c.output;
    EXPECT_NE(c.output.find("--backend cuda"), std::string::npos) << c.output;
    EXPECT_TRUE(c.output.find("-DVPPDEM_CUDA=ON") != std::string::npos || c.output.find("no CUDA device") != std::string::npos)
        << c.output;
    EXPECT_FALSE(fs::exists(none));
}

// Issue 48: a sweep into a folder of an earlier sweep, with a changed key that acts during the
// preparation but is no geometry key (grains.young), branched its new case from the old sample
// (W 133.77 where a fresh run of that case gives 204.33). The branch now checks every key that
// acts before prepared.ckpt and refuses, naming the key, as it refuses a changed grains.radius.
TEST_F(Study, ABranchFromASampleOfOtherPreparationSettingsIsRefused) {
    const fs::path first = scratch("young1.toml"), second = scratch("young2.toml"), out = scratch("young");
    fs::remove_all(out);
    write_file(first, kSmallSet + "[grid]\n\"grains.friction\" = [0.3]\n");
    const Outcome a = run("sweep " + first.string() + " --out " + out.string() + " --no-plot --quiet --jobs 1");
    ASSERT_EQ(a.status, 0) << a.output;
    write_file(second, kSmallSet + "\"grains.young\" = 2.3e10\n[grid]\n\"grains.friction\" = [0.3, 0.6]\n");
    const Outcome b = run("sweep " + second.string() + " --out " + out.string() + " --no-plot --jobs 1");
    EXPECT_EQ(WEXITSTATUS(b.status), 1) << b.output;
    const fs::path branch = out / "grains.friction=0.6";
    ASSERT_TRUE(fs::exists(branch / "FAILED")) << b.output;
    const std::string why = slurp(branch / "FAILED");
    EXPECT_NE(why.find("grains.young = 2.3e+09 (the config asks for 2.3e+10"), std::string::npos) << why;
    EXPECT_NE(why.find("acts during the preparation"), std::string::npos) << why;
    EXPECT_FALSE(fs::exists(branch / "summary.json"));
}

// Issue 46: a study takes its prepared samples from another study's folder by name
// (samples_from): its cases branch from the sample that fits them, with the bits of a branch in
// that study's own folder; a group no sample fits prepares its own; samples_match = "geometry"
// lets a case cycle a sample with preparation settings of its own (the time-step study).
TEST_F(Study, ACaseBranchesFromAnotherStudysSampleByName) {
    const fs::path root = scratch("samples");
    fs::remove_all(root);
    const fs::path a = root / "a", b = root / "b", d = root / "d", g = root / "g";
    write_file(root / "a.toml", kTwoFrictions);
    const Outcome ra = run("sweep " + (root / "a.toml").string() + " --out " + a.string() + " --no-plot --quiet --jobs 1");
    ASSERT_EQ(ra.status, 0) << ra.output;

    write_file(root / "b.toml", "samples_from = \"a\"\n" + kSmallSet + "[grid]\n\"grains.friction\" = [0.6]\n");
    // --list names the sample each group would branch from.
    const Outcome rl = run("sweep " + (root / "b.toml").string() + " --out " + b.string() + " --list");
    ASSERT_EQ(rl.status, 0) << rl.output;
    EXPECT_NE(rl.output.find("grains.friction=0.6  (branches from " + (a / "grains.friction=0.3" / "prepared.ckpt").string() + ")"),
              std::string::npos) << rl.output;
    EXPECT_FALSE(fs::exists(b));  // --list writes nothing
    const Outcome rb = run("sweep " + (root / "b.toml").string() + " --out " + b.string() + " --no-plot --jobs 1");
    ASSERT_EQ(rb.status, 0) << rb.output;
    EXPECT_NE(rb.output.find("1 of 1 preparation(s)"), std::string::npos) << rb.output;
    const fs::path bc = b / "grains.friction=0.6";
    EXPECT_FALSE(fs::exists(bc / "prepared.ckpt"));  // it prepared nothing
    EXPECT_NE(slurp(bc / "summary.json").find("grains.friction=0.3/prepared.ckpt"), std::string::npos);
    EXPECT_EQ(slurp(bc / "cycles.csv"), slurp(a / "grains.friction=0.6" / "cycles.csv"));
    EXPECT_EQ(slurp(bc / "forces.csv"), slurp(a / "grains.friction=0.6" / "forces.csv"));

    // Another grain stiffness acts during the preparation: no sample fits; it prepares its own.
    write_file(root / "d.toml", "samples_from = \"a\"\n" + kSmallSet + "\"grains.young\" = 2.3e10\n[grid]\n"
                                "\"grains.friction\" = [0.3]\n");
    const Outcome rd = run("sweep " + (root / "d.toml").string() + " --out " + d.string() + " --no-plot --jobs 1");
    ASSERT_EQ(rd.status, 0) << rd.output;
    EXPECT_NE(rd.output.find("grains.young = 2.3e+09 (the case: 2.3e+10)"), std::string::npos) << rd.output;
    EXPECT_NE(rd.output.find("0 of 1 preparation(s)"), std::string::npos) << rd.output;
    EXPECT_TRUE(fs::exists(d / "grains.friction=0.3" / "prepared.ckpt"));

    // A list of folders, searched in its order: d's sample (grains.young 2.3e9 against d's 2.3e10)
    // does not fit, a's does; the branch is b's bit for bit.
    const fs::path b2 = root / "b2";
    write_file(root / "b2.toml", "samples_from = [\"d\", \"a\"]\n" + kSmallSet + "[grid]\n\"grains.friction\" = [0.6]\n");
    const Outcome rb2 = run("sweep " + (root / "b2.toml").string() + " --out " + b2.string() + " --no-plot --jobs 1");
    ASSERT_EQ(rb2.status, 0) << rb2.output;
    EXPECT_NE(rb2.output.find("1 of 1 preparation(s)"), std::string::npos) << rb2.output;
    EXPECT_NE(slurp(b2 / "grains.friction=0.6" / "summary.json").find("/a/grains.friction=0.3/prepared.ckpt"),
              std::string::npos);
    EXPECT_EQ(slurp(b2 / "grains.friction=0.6" / "cycles.csv"), slurp(bc / "cycles.csv"));

    // By geometry alone: another time step (0.3 against the tests' 0.45) cycles a's sample (no
    // preparation of its own).
    write_file(root / "g.toml", "samples_from = \"a\"\nsamples_match = \"geometry\"\n" + kSmallSetAnyStep +
                                    "\"simulation.dt_safety\" = 0.3\n[grid]\n\"grains.friction\" = [0.3]\n");
    const Outcome rg = run("sweep " + (root / "g.toml").string() + " --out " + g.string() + " --no-plot --jobs 1");
    ASSERT_EQ(rg.status, 0) << rg.output;
    EXPECT_FALSE(fs::exists(g / "grains.friction=0.3" / "prepared.ckpt"));
    EXPECT_NE(slurp(g / "grains.friction=0.3" / "summary.json").find("grains.friction=0.3/prepared.ckpt"),
              std::string::npos);
    EXPECT_NE(slurp(g / "grains.friction=0.3" / "cycles.csv"), slurp(a / "grains.friction=0.3" / "cycles.csv"));

    // Bad values: exit 2, naming the key, nothing written.
    write_file(root / "bad.toml", "samples_from = \"nowhere\"\n" + kTwoFrictions);
    const Outcome r1 = run("sweep " + (root / "bad.toml").string() + " --out " + (root / "bad").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(r1.status), 2) << r1.output;
    EXPECT_NE(r1.output.find("samples_from"), std::string::npos) << r1.output;
    write_file(root / "bad2.toml", "samples_match = \"geometry\"\n" + kTwoFrictions);
    const Outcome r2 = run("sweep " + (root / "bad2.toml").string() + " --out " + (root / "bad2").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(r2.status), 2) << r2.output;
    EXPECT_NE(r2.output.find("samples_match"), std::string::npos) << r2.output;
    write_file(root / "bad4.toml", "samples_from = [\"a\", 3]\n" + kTwoFrictions);
    const Outcome r4 = run("sweep " + (root / "bad4.toml").string() + " --out " + (root / "bad4").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(r4.status), 2) << r4.output;
    EXPECT_NE(r4.output.find("key 'samples_from' = ['a', 3]: must be a folder name or path"), std::string::npos)
        << r4.output;
    EXPECT_FALSE(fs::exists(root / "bad4"));
    write_file(root / "bad3.toml", "samples_from = \"a\"\nsamples_match = \"size\"\n" + kTwoFrictions);
    const Outcome r3 = run("sweep " + (root / "bad3.toml").string() + " --out " + (root / "bad3").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(r3.status), 2) << r3.output;
    EXPECT_NE(r3.output.find("\"preparation\" or \"geometry\""), std::string::npos) << r3.output;
    fs::remove_all(root);
}

// Issue 46: a branch run by a script before studies had samples_from (the paper's time-step runs:
// `vppdem damper --from SAMPLE --set ...`, its case.toml the one command it ran) is the study's
// case when the command's settings are the case's and every other key of the case is geometry,
// taken from the sample: the sweep counts it as finished and runs nothing. The sweep's own branch
// of that case gives the script's run bit for bit; a command with another setting is refused.
TEST_F(Study, AScriptsBranchRunIsTheStudysCaseWhenItsSettingsAre) {
    const fs::path root = scratch("legacy_branch");
    fs::remove_all(root);
    write_file(root / "base.toml", kSmallSet + "[grid]\n\"grains.friction\" = [0.3]\n");
    const Outcome rb = run("sweep " + (root / "base.toml").string() + " --out " + (root / "base").string() +
                           " --no-plot --quiet --jobs 1");
    ASSERT_EQ(rb.status, 0) << rb.output;
    const fs::path sample = root / "base" / "grains.friction=0.3" / "prepared.ckpt";
    ASSERT_TRUE(fs::exists(sample));

    // The script's run, its case.toml the command (0.06e6 written as the script wrote it).
    const std::string sets = "--set simulation.dt_safety=0.45 --set process.velocity=0.1 --set process.amplitude=0.002 "
                             "--set process.cycles=2 --set process.samples_per_cycle=80 --set simulation.threads=1 "
                             "--set process.underpressure=0.06e6";
    const fs::path legacy = root / "pub" / "simulation.dt-safety=0.45";
    const std::string command = "damper --from " + sample.string() + " --out " + legacy.string() + " " + sets +
                                " --no-plot --quiet";
    const Outcome rl = run(command);
    ASSERT_EQ(rl.status, 0) << rl.output;
    write_file(legacy / "case.toml", "command = \"vppdem " + command + "\"\n");

    const std::string study = "samples_from = \"base\"\nsamples_match = \"geometry\"\n" + kSmallSetAnyStep +
                              "\"process.underpressure\" = 60000.0\n[grid]\n\"simulation.dt_safety\" = [0.45]\n";
    write_file(root / "ts.toml", study);
    const Outcome rt = run("sweep " + (root / "ts.toml").string() + " --out " + (root / "ts").string() + " --publish " +
                           (root / "pub").string() + " --no-plot --jobs 1");
    ASSERT_EQ(rt.status, 0) << rt.output;
    EXPECT_NE(rt.output.find("simulation.dt-safety=0.45: done earlier"), std::string::npos) << rt.output;
    EXPECT_FALSE(fs::exists(root / "ts" / "simulation.dt-safety=0.45" / "forces.csv")) << rt.output;  // nothing ran

    // The sweep's own branch: the script's bits.
    const Outcome rs = run("sweep " + (root / "ts.toml").string() + " --out " + (root / "ts2").string() +
                           " --no-plot --quiet --jobs 1");
    ASSERT_EQ(rs.status, 0) << rs.output;
    EXPECT_EQ(slurp(root / "ts2" / "simulation.dt-safety=0.45" / "cycles.csv"), slurp(legacy / "cycles.csv"));
    EXPECT_EQ(slurp(root / "ts2" / "simulation.dt-safety=0.45" / "forces.csv"), slurp(legacy / "forces.csv"));

    // Another setting in the command (3 cycles): not this study's case.
    fs::create_directories(root / "pub3");
    fs::copy(root / "pub", root / "pub3", fs::copy_options::recursive);
    std::string other = command;
    other.replace(other.find("process.cycles=2"), 16, "process.cycles=3");
    write_file(root / "pub3" / "simulation.dt-safety=0.45" / "case.toml", "command = \"vppdem " + other + "\"\n");
    const Outcome r3 = run("sweep " + (root / "ts.toml").string() + " --out " + (root / "ts3").string() + " --publish " +
                           (root / "pub3").string() + " --no-plot --jobs 1");
    EXPECT_NE(r3.status, 0) << r3.output;
    EXPECT_NE(r3.output.find("holds a case run with other settings"), std::string::npos) << r3.output;
    fs::remove_all(root);
}

// Issue 46: a study's second leg (`continues`): the finished runs of another study, copied and
// continued to more cycles, give the bits of a study that ran them that long from the start; the
// first study's runs stay as they were; a case still running there is refused before anything is
// copied; a case that study lacks runs anew.
TEST_F(Study, ASecondLegContinuesCopiesOfAnotherStudysRuns) {
    const fs::path root = scratch("continues");
    fs::remove_all(root);
    const std::string grid = "[grid]\n\"grains.friction\" = [0.3]\n";
    write_file(root / "first.toml", kSmallSet + grid);
    const Outcome r1 = run("sweep " + (root / "first.toml").string() + " --out " + (root / "first").string() +
                           " --no-plot --quiet --jobs 1");
    ASSERT_EQ(r1.status, 0) << r1.output;
    const fs::path first = root / "first" / "grains.friction=0.3";
    const std::string first_cycles = slurp(first / "cycles.csv");

    // The leg: 3 cycles instead of 2 (kSmallSet's process.cycles, overridden by the later key).
    std::string three = kSmallSet;
    three.replace(three.find("\"process.cycles\" = 2"), 20, "\"process.cycles\" = 3");
    write_file(root / "leg.toml", "continues = \"first\"\n" + three + "[grid]\n\"grains.friction\" = [0.3, 0.6]\n");

    // A run still going in the first study: refused, nothing copied.
    fs::create_directories(root / "first" / "grains.friction=0.6");
    write_file(root / "first" / "grains.friction=0.6" / "run.ckpt", "in flight");
    const Outcome rr = run("sweep " + (root / "leg.toml").string() + " --out " + (root / "leg").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(rr.status), 2) << rr.output;
    EXPECT_NE(rr.output.find("holds runs still going (run.ckpt, no summary.json): grains.friction=0.6"),
              std::string::npos) << rr.output;
    EXPECT_FALSE(fs::exists(root / "leg" / "grains.friction=0.3"));
    fs::remove_all(root / "first" / "grains.friction=0.6");

    const Outcome rl = run("sweep " + (root / "leg.toml").string() + " --out " + (root / "leg").string() +
                           " --no-plot --jobs 1");
    ASSERT_EQ(rl.status, 0) << rl.output;
    EXPECT_NE(rl.output.find("1 finished run(s) copied to continue"), std::string::npos) << rl.output;
    EXPECT_NE(rl.output.find("1 case(s) not there with a run.ckpt run anew: grains.friction=0.6"), std::string::npos)
        << rl.output;
    EXPECT_EQ(slurp(first / "cycles.csv"), first_cycles);  // the first study's run as it was
    EXPECT_EQ(lines_of(root / "leg" / "grains.friction=0.3" / "cycles.csv").size(), 4u);  // header + 3 cycles

    // The same leg from the start: the same bits.
    write_file(root / "three.toml", three + grid);
    const Outcome r3 = run("sweep " + (root / "three.toml").string() + " --out " + (root / "three").string() +
                           " --no-plot --quiet --jobs 1");
    ASSERT_EQ(r3.status, 0) << r3.output;
    EXPECT_EQ(slurp(root / "leg" / "grains.friction=0.3" / "cycles.csv"),
              slurp(root / "three" / "grains.friction=0.3" / "cycles.csv"));
    EXPECT_EQ(slurp(root / "leg" / "grains.friction=0.3" / "forces.csv"),
              slurp(root / "three" / "grains.friction=0.3" / "forces.csv"));

    // Bad values: exit 2, naming the key.
    write_file(root / "bad.toml", "continues = \"nowhere\"\n" + three + grid);
    const Outcome rb = run("sweep " + (root / "bad.toml").string() + " --out " + (root / "bad").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(rb.status), 2) << rb.output;
    EXPECT_NE(rb.output.find("key 'continues' = \"nowhere\": no folder"), std::string::npos) << rb.output;
    write_file(root / "bad2.toml", "continues = 3\n" + three + grid);
    const Outcome rb2 = run("sweep " + (root / "bad2.toml").string() + " --out " + (root / "bad2").string() + " --no-plot");
    EXPECT_EQ(WEXITSTATUS(rb2.status), 2) << rb2.output;
    EXPECT_NE(rb2.output.find("key 'continues' = 3: must be a folder name or path"), std::string::npos) << rb2.output;
    fs::remove_all(root);
}

// Issue 46: --publish keeps the small records of the finished cases (case.toml, summary.json,
// cycles.csv, build.json) and the tables in a results folder, and a sweep into a new run folder
// takes them back as finished: it runs nothing and writes the same tables.
TEST_F(Study, PublishKeepsTheSmallRecordsAndAnotherFolderResumesFromThem) {
    const fs::path study = scratch("publish.toml"), out = scratch("publish_out"), again = scratch("publish_again"),
                   results = scratch("publish_results");
    for (const fs::path& p : {out, again, results}) fs::remove_all(p);
    write_file(study, kTwoFrictions);
    const Outcome r = run("sweep " + study.string() + " --out " + out.string() + " --publish " + results.string() +
                          " --jobs 1 --no-plot");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("published into " + results.string() + " (2 of 2 cases there)"), std::string::npos) << r.output;
    for (const char* c : {"grains.friction=0.3", "grains.friction=0.6"}) {
        EXPECT_EQ(entries(results / c), (std::vector<std::string>{"build.json", "case.toml", "cycles.csv", "summary.json"}))
            << c;
        for (const char* f : {"case.toml", "cycles.csv", "summary.json", "build.json"})
            EXPECT_EQ(slurp(results / c / f), slurp(out / c / f)) << c << "/" << f;
    }
    for (const char* f : {"summary.csv", "summary_cases.csv"}) EXPECT_EQ(slurp(results / f), slurp(out / f)) << f;

    const Outcome b = run("sweep " + study.string() + " --out " + again.string() + " --publish " + results.string() +
                          " --jobs 1 --no-plot");
    ASSERT_EQ(b.status, 0) << b.output;
    EXPECT_NE(b.output.find("2 finished case(s) restored"), std::string::npos) << b.output;
    EXPECT_NE(b.output.find("done earlier"), std::string::npos) << b.output;
    EXPECT_FALSE(fs::exists(again / "grains.friction=0.3" / "prepared.ckpt"));  // nothing ran
    EXPECT_EQ(slurp(again / "summary.csv"), slurp(out / "summary.csv"));

    // What scripts/publish.sh did in bash, now --publish's (issue 59, item 4):
    // 1. --report-only --publish into an empty folder puts the records back too (a build without
    //    --publish then resumes from them: scripts/paper_studies.sh's pinned builds) and
    //    republishes the study as it was, byte for byte.
    auto files_of = [](const fs::path& dir) {
        std::map<std::string, std::string> m;
        for (const auto& e : fs::recursive_directory_iterator(dir))
            if (e.is_regular_file()) m[fs::relative(e.path(), dir).string()] = slurp(e.path());
        return m;
    };
    const auto published = files_of(results);
    const fs::path empty = scratch("publish_empty");
    fs::remove_all(empty);
    fs::create_directories(empty);
    const Outcome e = run("sweep " + study.string() + " --out " + empty.string() + " --report-only --publish " +
                          results.string());
    ASSERT_EQ(e.status, 0) << e.output;
    EXPECT_NE(e.output.find("2 finished case(s) restored"), std::string::npos) << e.output;
    EXPECT_NE(e.output.find("2 of 2 cases finished"), std::string::npos) << e.output;
    for (const char* f : {"case.toml", "cycles.csv", "summary.json", "build.json"})
        EXPECT_EQ(slurp(empty / "grains.friction=0.3" / f), slurp(out / "grains.friction=0.3" / f)) << f;
    EXPECT_EQ(slurp(empty / "summary.csv"), slurp(out / "summary.csv"));
    EXPECT_EQ(files_of(results), published);
    // 2. The run folder's COMMAND (the note a script writes of a build without --publish) is
    //    published with the records, and again only when it changed.
    write_file(out / "COMMAND", "vppdem sweep publish.toml (pinned build abc)\n");
    ASSERT_EQ(run("sweep " + study.string() + " --out " + out.string() + " --report-only --quiet --publish " +
                  results.string()).status, 0);
    EXPECT_EQ(slurp(results / "COMMAND"), "vppdem sweep publish.toml (pinned build abc)\n");
    // 3. An assembled study folder (scripts/paper_report.sh: copies of published runs without
    //    their case.toml, sources.csv naming them, the study's COMMAND): its tables, sources.csv
    //    and COMMAND are published, its case folders are not (they stay where they came from).
    const fs::path assembly = scratch("publish_assembly"), report = scratch("publish_report");
    for (const fs::path& p : {assembly, report}) fs::remove_all(p);
    for (const char* c : {"grains.friction=0.3", "grains.friction=0.6"}) {
        fs::create_directories(assembly / c);
        for (const char* f : {"cycles.csv", "summary.json"}) fs::copy_file(results / c / f, assembly / c / f);
    }
    write_file(assembly / "sources.csv", "case,source\ngrains.friction=0.3,x/grains.friction=0.3\n");
    write_file(assembly / "COMMAND", "the study's command\n");
    const Outcome a = run("sweep " + study.string() + " --out " + assembly.string() + " --report-only --quiet --publish " +
                          report.string());
    ASSERT_EQ(a.status, 0) << a.output;
    EXPECT_EQ(entries(report), (std::vector<std::string>{"COMMAND", "sources.csv", "summary.csv", "summary_cases.csv"}));
    EXPECT_EQ(slurp(report / "summary.csv"), slurp(assembly / "summary.csv"));
    EXPECT_EQ(table_of(report / "summary.csv").size(), 2u);
    for (const auto& row : table_of(report / "summary.csv")) EXPECT_EQ(row.at("status"), "ok");
    for (const fs::path& p : {empty, assembly, report}) fs::remove_all(p);
}

}  // namespace test_study
