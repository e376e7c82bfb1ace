// The scripts that regenerate and publish the studies and the kill-and-resume tool, run as the lead
// runs them, on the tests' small damper or on stand-in binaries: scripts/trust_studies.sh,
// scripts/publish.sh, scripts/paper_studies.sh, tools/kill_resume.py (the built binary killed and
// resumed). The Python reports they feed (vppdem.report's paired_velocity, paper, rules,
// grain_shapes; scripts/paper_report.sh's page) and tools/synthetic_experiment.py are tested in
// Python: tests/python/test_report_*.py, test_synthetic_experiment.py (issue 59, item 4). The suite
// keeps its name, Tools (CMakeLists.txt's long tier and docs/ name its tests).
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"

namespace {

using namespace cli_test;

const std::string kPython = "/usr/bin/python3 ";
const fs::path kSource = VPPDEM_SOURCE_DIR;

std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
    if (!line.empty() && line.back() == ',') out.push_back("");
    return out;
}

// Rows of a CSV as maps from column name to text.
std::vector<std::map<std::string, std::string>> rows_of(const fs::path& p) {
    std::istringstream in(slurp(p));
    std::string line;
    std::getline(in, line);
    const auto h = fields(line);
    std::vector<std::map<std::string, std::string>> out;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        const auto f = fields(line);
        std::map<std::string, std::string> r;
        for (std::size_t k = 0; k < h.size() && k < f.size(); ++k) r[h[k]] = f[k];
        out.push_back(r);
    }
    return out;
}

}  // namespace

// scripts/trust_studies.sh on the small damper (its SETS knob), one study, two seeds, one cycle:
// the study runs, its summaries and figures land in DOCS, and SOURCES.md names the command.
TEST(Tools, TrustStudiesScriptRunsAStudyAndPublishesIt) {
    const fs::path d = scratch_path("tools", "trust");
    fs::remove_all(d);
    const std::string env = "VPPDEM=" + kBinary + " OUT=" + (d / "out").string() + " DOCS=" + (d / "docs").string() +
                            " SEEDS=2 CYCLES=1 VELOCITY=0.1 SETS='--set damper.radius=0.012 --set damper.height=0.03 "
                            "--set grains.volume_fraction=0.45 --set process.amplitude=0.0005 "
                            "--set process.samples_per_cycle=40 --set simulation.threads=1' ";
    const std::string script = "bash " + (kSource / "scripts/trust_studies.sh").string();
    const Outcome r = shell(env + script + " underpressure");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* f : {"study_underpressure_W.png", "study_underpressure_loops.png",
                          "data/study_underpressure_summary.csv", "data/study_underpressure_cases.csv"})
        EXPECT_TRUE(fs::exists(d / "docs" / f)) << f;
    const auto cases = rows_of(d / "docs" / "data" / "study_underpressure_cases.csv");
    ASSERT_EQ(cases.size(), 4u);  // four underpressures, two seeds each
    for (const auto& c : cases) {
        EXPECT_EQ(c.at("seeds"), "2");
        EXPECT_EQ(c.at("W_n"), "2");
    }
    const std::string sources = slurp(d / "docs" / "data" / "SOURCES.md");
    EXPECT_NE(sources.find("sweep studies/trust/underpressure.toml --out " + (d / "out").string() + "/underpressure "
                           "--seeds 2 --set process.cycles=1"),
              std::string::npos) << sources;
    // Bad knobs: named, nothing run.
    const Outcome bad = shell(env + "SEEDS=0 " + script + " underpressure");
    EXPECT_EQ(WEXITSTATUS(bad.status), 2) << bad.output;
    EXPECT_NE(bad.output.find("SEEDS = '0'"), std::string::npos) << bad.output;
    const Outcome unknown = shell(env + script + " frictoin");
    EXPECT_NE(unknown.status, 0);
    EXPECT_NE(unknown.output.find("unknown study 'frictoin'"), std::string::npos) << unknown.output;
    fs::remove_all(d);
}

// tools/kill_resume.py into a fresh scratch folder `name` with the built binary and `args`.
static Outcome kill_resume(const std::string& name, const std::string& args) {
    const fs::path d = scratch_path("tools", name);
    fs::remove_all(d);
    const Outcome r = shell(kPython + (kSource / "tools/kill_resume.py").string() + " --vppdem " + kBinary +
                            " --out " + d.string() + " " + args);
    fs::remove_all(d);
    return r;
}

// tools/kill_resume.py, shortened: the small damper killed (SIGKILL) at least 4 times at random
// moments and resumed each time ends with the uninterrupted run's records, byte for byte but the
// wall-clock fields (the full run: 20 kills each for a study and a damper, docs/studies.md).
TEST(Tools, KillResumeEndsWithTheUninterruptedRecords) {
    const Outcome r = kill_resume("kill_resume", "--kills 4 --only damper --seed 3");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("every round ended with the records of the uninterrupted run"), std::string::npos)
        << r.output;
    // At least the 4 kills asked for, over as many rounds as it took (a round ends when its run
    // finishes, and numbers its kills from 1): the table's "kills survived" column.
    const std::size_t row = r.output.find("| damper | ");
    ASSERT_NE(row, std::string::npos) << r.output;
    EXPECT_GE(std::stoi(r.output.substr(row + 11)), 4) << r.output;
    // Bad input is named.
    const Outcome bad = shell(kPython + (kSource / "tools/kill_resume.py").string() + " --kills 0");
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.output.find("--kills = 0"), std::string::npos) << bad.output;
}

// tools/kill_resume.py --only stages: the small damper checkpointing only where it must (each
// stage's start, each re-fill), each of those checkpoints resumed in a folder of its own, ends
// with the uninterrupted run's records. The states saved there were changed by hand before the
// next step (grains added, the funnel removed): a kill right after the re-fill's checkpoint once
// left a run.ckpt that would not load ("candidate list of the wrong shape").
TEST(Tools, KillResumeResumesEveryCheckpointARunForces) {
    const Outcome r = kill_resume("kill_resume_stages", "--only stages");
    ASSERT_EQ(r.status, 0) << r.output;
    // fill, at least one re-fill, compress, prepared, vacuum, cycle, done: at least 6 (measured: 7).
    const std::size_t at = r.output.find(" checkpoints written where the run forces them");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::size_t line = r.output.rfind('\n', at) + 1;
    EXPECT_GE(std::stoi(r.output.substr(line + std::string("stages: ").size())), 6) << r.output;
    EXPECT_NE(r.output.find("every round ended with the records of the uninterrupted run"), std::string::npos)
        << r.output;
}

// scripts/publish.sh, what the study scripts share beside `vppdem sweep --publish` (which alone
// publishes a study's records: Study.PublishKeepsTheSmallRecordsAndAnotherFolderResumesFromThem):
// a report output's copy into docs/ through a temporary name, its row in SOURCES.md (one per file
// set, replaced by a newer one), and the knobs' check; on a folder with a space in its path, as a
// user's home may have. And a study script's unknown argument, named.
TEST(Tools, PublishShCopiesAReportsOutputsAndRecordsTheirCommand) {
    const fs::path d = scratch_path("tools", "publish sh");
    fs::remove_all(d);
    fs::create_directories(d / "docs");
    write_file(d / "figure.png", "png");
    // In bash (the scripts' shell), from the scratch folder.
    auto in_bash = [&](const std::string& body) {
        write_file(d / "t.sh", "set -euo pipefail\ncd \"$(dirname \"$0\")\"\nDOCS=docs\nsource '" +
                                   (kSource / "scripts/publish.sh").string() + "'\n" + body + "\n");
        return shell("bash '" + (d / "t.sh").string() + "'");
    };
    Outcome r = in_bash("publish figure.png docs/a.png; record 'a.png' 'make a'; record 'b.png' 'make b'; "
                        "record 'a.png' 'make a again'; ls docs");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output, "a.png\ndata\n");
    EXPECT_EQ(slurp(d / "docs" / "a.png"), "png");
    const std::string sources = slurp(d / "docs" / "data" / "SOURCES.md");
    EXPECT_EQ(sources.find("`make a` |"), std::string::npos) << sources;
    EXPECT_NE(sources.find("| a.png | `make a again` |"), std::string::npos) << sources;
    EXPECT_NE(sources.find("| b.png | `make b` |"), std::string::npos) << sources;
    r = in_bash("SEEDS=0; whole_knobs me SEEDS");
    EXPECT_EQ(WEXITSTATUS(r.status), 2);
    EXPECT_NE(r.output.find("me: SEEDS = '0': must be an integer >= 1"), std::string::npos) << r.output;
    // An unknown argument is named, nothing run.
    r = shell("bash '" + (kSource / "scripts/grain_shapes.sh").string() + "' --publish-onyl");
    EXPECT_EQ(WEXITSTATUS(r.status), 2);
    EXPECT_NE(r.output.find("unknown argument(s) '--publish-onyl'"), std::string::npos) << r.output;
    fs::remove_all(d);
}

// scripts/paper_studies.sh, a thin wrapper since the studies' branching and continuing moved into
// study files (samples_from, continues: Study.ACaseBranchesFromAnotherStudysSampleByName,
// Study.ASecondLegContinuesCopiesOfAnotherStudysRuns) and the publishing into --publish, on
// stand-in binaries that print their arguments: a pinned study runs with its pinned binary between
// two of this build's `--report-only --publish` (the first puts the published records back, the
// second publishes the runs and the COMMAND, which names the pinned commit); the study files with
// the newer keys (timestep, friction_8 and friction_8_seeds) are one command of this build with
// --publish (the leg with --mix-builds); a pinned binary of another commit than a study's
// published runs, or without a COMMIT file, is refused before anything runs; --publish-only runs
// this build's report alone; an unknown study is named.
TEST(Tools, PaperStudiesRunEachStudyFileWithItsBuildAndPublish) {
    const fs::path d = scratch_path("tools", "paper studies");
    fs::remove_all(d);
    const fs::path pinned = d / "pin ned", now = d / "now", out = d / "out", data = d / "data";
    auto stand_in = [](const fs::path& dir, const std::string& tag) {
        fs::create_directories(dir);
        write_file(dir / "vppdem", "#!/bin/sh\necho " + tag + " \"$@\"\n");
        fs::permissions(dir / "vppdem", fs::perms::owner_all);
    };
    stand_in(pinned, "PINNED");
    stand_in(now, "NOW");
    write_file(pinned / "COMMIT", "abc\n");
    fs::create_directories(data / "friction" / "c1");
    for (const char* f : {"case.toml", "summary.json", "cycles.csv"}) write_file(data / "friction" / "c1" / f, f);
    write_file(data / "friction" / "COMMAND", "vppdem sweep friction (pinned build abc)\n");
    const std::string env = "OUT='" + out.string() + "' DATA='" + data.string() + "' VPPDEM='" +
                            (pinned / "vppdem").string() + "' VPPDEM_NOW='" + (now / "vppdem").string() + "' ";
    const std::string script = "bash '" + (kSource / "scripts/paper_studies.sh").string() + "'";
    Outcome r = shell(env + script + " friction timestep friction_8");
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string o = out.string(), p = data.string();
    const std::string pinned_run = "PINNED sweep studies/paper/friction.toml --out " + o + "/friction --no-plot",
                      report = "NOW sweep studies/paper/friction.toml --out " + o +
                               "/friction --report-only --mix-builds --publish " + p + "/friction --no-plot --quiet";
    for (const std::string& want :
         {pinned_run, report,
          "NOW sweep studies/paper/timestep.toml --out " + o + "/timestep --publish " + p + "/timestep --no-plot",
          "NOW sweep studies/paper/friction_8.toml --out " + o + "/friction_8 --publish " + p +
              "/friction_8 --mix-builds --no-plot"})
        EXPECT_NE(r.output.find(want), std::string::npos) << want << "\n" << r.output;
    // The records put back before the pinned run, its runs published after it.
    const std::size_t ran = r.output.find(pinned_run);
    EXPECT_LT(r.output.find(report), ran) << r.output;
    EXPECT_NE(r.output.find(report, ran), std::string::npos) << r.output;
    EXPECT_NE(slurp(out / "friction" / "COMMAND").find(pinned_run.substr(7) + " (pinned build abc)"), std::string::npos)
        << slurp(out / "friction" / "COMMAND");
    // Another commit than the published runs': refused, nothing run.
    write_file(data / "damping" / "COMMAND", "vppdem sweep damping (pinned build old)\n");
    r = shell(env + script + " damping");
    EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
    EXPECT_NE(r.output.find("came from the pinned build old; this binary's COMMIT says abc"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("PINNED"), std::string::npos) << r.output;
    fs::remove(pinned / "COMMIT");
    r = shell(env + script + " friction");
    EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
    EXPECT_NE(r.output.find("no COMMIT file beside the binary"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("PINNED"), std::string::npos) << r.output;
    write_file(pinned / "COMMIT", "abc\n");
    // --publish-only: this build's report and publishing alone.
    r = shell(env + script + " --publish-only friction");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("PINNED"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("NOW sweep studies/paper/friction.toml --out " + o + "/friction --report-only"),
              std::string::npos) << r.output;
    r = shell(env + script + " frictoin");
    EXPECT_EQ(WEXITSTATUS(r.status), 2);
    EXPECT_NE(r.output.find("unknown study 'frictoin'"), std::string::npos) << r.output;
    fs::remove_all(d);
}
