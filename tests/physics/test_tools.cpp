// The Python reports and tools and the regeneration script of the studies (vppdem.report's paired_velocity,
// paper, paper_rules, grain_shapes; tools/synthetic_experiment.py, tools/kill_resume.py, scripts/trust_studies.sh,
// scripts/paper_report.sh), run as the lead runs them, against hand-computed answers or on the tests' small damper.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"

namespace {

using namespace cli_test;

const std::string kPython = "/usr/bin/python3 ";
const fs::path kSource = VPPDEM_SOURCE_DIR;
// `python3 -m vppdem.report NAME ...`: the package's reports from the source tree (no compiled module).
const std::string kReport = "PYTHONPATH=" + (kSource / "src" / "python").string() + " " + kPython + "-m vppdem.report ";

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

// Three seeds whose packings differ by +-10 J/m^2 (far more than the velocity effect): the
// unpaired intervals overlap everywhere, the paired differences do not. W(v, s) = base_s +
// offset(v, s) with offsets 0 (0.005 m/s), 1, 2, 0 (0.05 m/s), 10, 11, 9 (0.1 m/s): at 0.05 m/s the
// differences 1, 2, 0 have mean 1, sd 1 and the interval 1 +- t_{0.975,2} / sqrt(3) = 1 +- 2.484,
// which holds 0; at 0.1 m/s 10 +- 2.484, which does not. The converged velocity is 0.05 m/s.
TEST(Tools, PairedVelocityIntervalsByHand) {
    const fs::path d = scratch_path("tools", "paired");
    fs::remove_all(d);
    std::string csv = "process.underpressure,process.velocity,simulation.seed,W,dissipated_energy,peak_force,run_seconds,"
                      "status,case,W_settled,settled_cycles,first_settled_cycle,friction_share,damping_share,grains,"
                      "packing_fraction,warnings\n";
    const double base[3] = {100, 110, 90};
    const std::map<std::string, std::vector<double>> offset = {
        {"0.1", {10, 11, 9}}, {"0.05", {1, 2, 0}}, {"0.005", {0, 0, 0}}};
    for (const auto& [v, off] : offset)
        for (int s = 0; s < 3; ++s)
            csv += "60000," + v + "," + std::to_string(s + 1) + "," + std::to_string(base[s] + off[std::size_t(s)]) +
                   ",1,500,1,ok,c" + v + "_" + std::to_string(s) + ",,0,,,,60,0.6,\n";
    write_file(d / "summary.csv", csv);
    const Outcome r = shell(kReport + "paired_velocity " + d.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("W: fastest velocity within the paired 95% interval of 0.005 m/s (and every slower one): "
                            "0.05 m/s"), std::string::npos) << r.output;
    const double t2 = 0.95 / std::sqrt(2 * 0.975 * 0.025);  // t_{0.975,2}, closed form
    int seen = 0;
    for (const auto& row : rows_of(d / "paired_velocity.csv")) {
        if (row.at("quantity") != "W") continue;
        const std::string v = row.at("velocity");
        EXPECT_EQ(row.at("n"), "3");
        EXPECT_EQ(row.at("diff_n"), "3");
        if (v == "0.05") {
            ++seen;
            EXPECT_NEAR(std::stod(row.at("diff_mean")), 1.0, 1e-9);
            EXPECT_NEAR(std::stod(row.at("diff_sd")), 1.0, 1e-9);
            EXPECT_NEAR(std::stod(row.at("diff_ci95")), t2 / std::sqrt(3.0), 1e-8);
            EXPECT_EQ(row.at("within"), "1");
            EXPECT_EQ(row.at("converged"), "1");
            // Unpaired: 101, 112, 90: mean 101, sd 11, half width t2 * 11 / sqrt(3).
            EXPECT_NEAR(std::stod(row.at("mean")), 101.0, 1e-9);
            EXPECT_NEAR(std::stod(row.at("ci95")), t2 * 11.0 / std::sqrt(3.0), 1e-7);
        } else if (v == "0.1") {
            ++seen;
            EXPECT_NEAR(std::stod(row.at("diff_mean")), 10.0, 1e-9);
            EXPECT_EQ(row.at("within"), "0");
            EXPECT_EQ(row.at("converged"), "0");
        }
    }
    EXPECT_EQ(seen, 2);
    EXPECT_TRUE(fs::exists(d / "paired_velocity.png"));
    // A sweep without seeds cannot be paired: said so, nonzero exit.
    write_file(d / "noseed" / "summary.csv", "process.velocity,W,status\n0.1,5,ok\n");
    const Outcome bad = shell(kReport + "paired_velocity " + (d / "noseed").string());
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.output.find("simulation.seed"), std::string::npos) << bad.output;
    fs::remove_all(d);
}

// The synthetic rig record: mm, kN, compression negative, from an offset origin; without noise
// it is the run's force_zeroed and displacement exactly (to the 9 digits written).
TEST(Tools, SyntheticExperimentIsTheRunAsARigWritesIt) {
    const fs::path d = scratch_path("tools", "synthetic");
    fs::remove_all(d);
    write_file(d / "forces.csv", "time,displacement,force_total,force_grains,force_foil,force_zeroed,cycle\n"
                                 "0,0,5,6,-1,0,1\n0.1,0.002,85,80,5,80,1\n0.2,0,7,8,-1,2,1\n");
    const Outcome r = shell(kPython + (kSource / "tools/synthetic_experiment.py").string() + " " +
                            (d / "forces.csv").string() + " " + (d / "exp.csv").string() +
                            " --disp-noise 0 --force-noise 0");
    ASSERT_EQ(r.status, 0) << r.output;
    std::istringstream in(slurp(d / "exp.csv"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line.rfind("# synthetic record", 0), 0u) << line;
    std::getline(in, line);
    EXPECT_EQ(line, "t_s,stroke_mm,load_kN");
    std::getline(in, line);
    EXPECT_EQ(line, "0,-12.5,-0");
    std::getline(in, line);
    EXPECT_EQ(line, "0.1,-14.5,-0.08");
    EXPECT_FALSE(fs::exists(d / "exp.csv.part"));
    fs::remove_all(d);
}

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

// scripts/paper_report.sh on hand-made records of the underpressure study (25.5 mm, four dp x 3
// seeds, 5 flat cycles each: every run stationary): W(dp, s) = 500 + 10 s + k (dp - 0.02 MPa)
// + e(dp, s), with e = 0 at 0.02 MPa and 0, 6, 12 over the seeds above it. The paired difference
// of 0.06 MPa from 0.02 MPa is then 1000 + {0, 6, 12}: mean 1006, sd 6, 95% half width
// t_{0.975,2} 6 / sqrt(3) = 4.3027 * 3.4641 = 14.9 J/m^2 (the seeds' +-10 J/m^2 offsets cancel).
// Every dp is higher than 0.02 MPa beyond its interval: C1 is reproduced, provisionally (the
// repository's radius study plans 5 seeds; its means say '(n 3 of 5)'). The page, its figure
// and the published tables are written; the study without runs stays open.
// vppdem.report.paper's verdicts against a tolerance (a fraction of the reference's mean), on
// hand-made paired rows with a reference of 1000 J/m^2 and 5% (50 J/m^2): 10 +- 20 lies within,
// 100 +- 20 beyond, 60 +- 40 is resolved but reaches inside, 30 +- 40 unresolved, one seed pending.
// The planned runs come from the repository's study files (friction: 7 frictions x 3 seeds).
// A mean says how many of the planned seeds it holds; one run has no interval.
TEST(Tools, PaperReportBandsADifferenceAgainstATolerance) {
    const std::string code =
        "import sys; sys.path.insert(0, 'src/python'); from vppdem.report import paper as p\n"
        "row = lambda d, h, n=3: {'n': str(n), 'diff_mean': str(d), 'diff_ci95': str(h), 'ref_mean': '1000'}\n"
        "print([p.band(row(10, 20), 0.05), p.band(row(100, 20), 0.05), p.band(row(60, 40), 0.05),\n"
        "       p.band(row(30, 40), 0.05), p.band(row(10, 20, 1), 0.05), p.band(None, 0.05)])\n"
        "print(p.rel_interval(row(45, 302)))\n"
        "print(p.planned_runs('friction'), p.planned_runs('damping'), p.planned_runs('young'))\n"
        "one = {'W_n': '1', 'W_mean': '1820', 'W_ci95': ''}\n"
        "print(p.ci_text(dict(one, planned_seeds=3)) + ';' + p.ci_text(one, unit='J') + ';' +\n"
        "      p.ci_text({'W_n': '2', 'W_mean': '10', 'W_ci95': '4', 'planned_seeds': 3}))\n";
    write_file(scratch_path("tools", "band.py"), code);
    const Outcome r = shell("cd " + kSource.string() + " && " + kPython + scratch_path("tools", "band.py").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("['within', 'beyond', 'resolved', 'unresolved', None, None]"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("-26% to +35%"), std::string::npos) << r.output;  // (45 -+ 302) / 1000
    EXPECT_NE(r.output.find("21 18 15"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1820 (one run of 3);1820 J (one run);10 +- 4 (n 2 of 3)"), std::string::npos) << r.output;
    fs::remove(scratch_path("tools", "band.py"));
}

// vppdem.report's statistics (stats: Welch, paired) and the page's decision rules (paper_rules, issue 44),
// against hand-computed values.
// Welch-Satterthwaite: sds 1 and sqrt(10) over 3 and 5 runs ({1, 2, 3} against {2, 4, 6, 8, 10}):
// v = 1/3 and 2, dof = (7/3)^2 / ((1/3)^2 / 2 + 2^2 / 4) = 98/19 = 5.1579; sds 2 and 4 over 3 and 5:
// (68/15)^2 / ((4/3)^2 / 2 + (16/5)^2 / 4) = 4624/776 = 5.9588. The difference 6 - 2 = 4 with the
// half width t_{0.975, 98/19} sqrt(7/3) (t between t_{0.975,6} = 2.447 and t_{0.975,5} = 2.571).
// Paired: differences {1, 2, 3}: 2 +- 4.303 / sqrt(3) = 2 +- 2.484.
TEST(Tools, PaperRulesWelchAndPairedByHand) {
    const std::string code =
        "import sys; sys.path.insert(0, 'src/python'); from vppdem.report import paper_rules as r, stats as st\n"
        "print('dof %.10f %.10f' % (st.welch_dof(1, 3, 10 ** 0.5, 5), st.welch_dof(2, 3, 4, 5)))\n"
        "d = st.welch([1, 2, 3], [2, 4, 6, 8, 10])\n"
        "print('welch %.10f %.10f %.10f %.6f' % (d.d, d.dof, d.h / (7 / 3) ** 0.5, st.t_quantile(0.975, 98 / 19)))\n"
        "p = st.paired({1: 10, 2: 20, 3: 30}, {1: 11, 2: 22, 3: 33})\n"
        "print('paired %.6f %.6f %s %s' % (p.d, p.h, p.test, p.n))\n"
        "print('test', r.difference('Welch', {1: 1, 2: 2, 3: 3}, {1: 2, 2: 4, 3: 6, 4: 8, 5: 10}).test,\n"
        "      r.difference('paired', {1: 1}, {1: 2}).test)\n";
    write_file(scratch_path("tools", "rules_welch.py"), code);
    const Outcome r = shell("cd " + kSource.string() + " && " + kPython + scratch_path("tools", "rules_welch.py").string());
    ASSERT_EQ(r.status, 0) << r.output;
    std::istringstream in(r.output);
    std::string tag;
    double a = 0, b = 0, c = 0, t = 0;
    in >> tag >> a >> b;
    EXPECT_EQ(tag, "dof");
    EXPECT_NEAR(a, 98.0 / 19.0, 1e-9);
    EXPECT_NEAR(b, 4624.0 / 776.0, 1e-9);
    in >> tag >> a >> b >> c >> t;
    EXPECT_EQ(tag, "welch");
    EXPECT_NEAR(a, 4.0, 1e-12);
    EXPECT_NEAR(b, 98.0 / 19.0, 1e-9);
    EXPECT_NEAR(c, t, 1e-6);  // half width = t_{0.975, dof} * sqrt(1/3 + 2)
    EXPECT_GT(t, 2.4469);
    EXPECT_LT(t, 2.5706);
    EXPECT_NE(r.output.find("paired 2.000000 2.484138 paired 3"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("test Welch paired"), std::string::npos) << r.output;
    fs::remove(scratch_path("tools", "rules_welch.py"));
}

// The rules on synthetic data. Equivalence (+-10% of a reference of 1000): 20 +- 30 within, 300 +- 50
// beyond, 80 +- 50 resolved, 50 +- 80 unresolved. Direction (a claim that wants lower): -100 +- 50
// yes, +100 +- 50 against, -10 +- 50 unresolved; a trend claim is not reproduced as soon as one
// difference is resolved against it (C28's 20.5 mm), consistent where one is only unresolved.
// Saturation: later changes {10, 20, 30} over earlier ones {100, 100, 100}: 0.2 +- 0.248
// (saturating); {40, 50, 60}: 0.5 +- 0.248 (undecided); {90, 100, 110}: 1.0 (not saturating).
// Stationary W: W_n = 1000 + 300 0.6^n is recovered exactly with q = 0.6, and the pooled rate of
// three such runs (different W_inf and a) is 0.6; a factor regression y = g + 2 x recovers 2.
TEST(Tools, PaperRulesDecideSyntheticData) {
    const std::string code =
        "import sys; sys.path.insert(0, 'src/python'); from vppdem.report import paper_rules as r, paper as p, stats as st\n"
        "D = lambda d, h: st.Diff('paired', 3, d, h, 2, 1000.0)\n"
        "print('band', [r.band(D(20, 30)), r.band(D(300, 50)), r.band(D(80, 50)), r.band(D(50, 80)), r.band(None)])\n"
        "o = [r.direction(D(-100, 50), -1), r.direction(D(100, 50), -1), r.direction(D(-10, 50), -1)]\n"
        "print('dir', o, p.v_direction(o[:1]), '|', p.v_direction(o), '|', p.v_direction([o[0], o[2]]), '|',\n"
        "      p.v_direction([o[0], None]))\n"
        "print('eq', p.v_equivalence(['within']), '|', p.v_equivalence(['within', 'beyond']), '|',\n"
        "      p.v_equivalence(['within', 'unresolved']))\n"
        "s = [r.saturation(l, [100] * 3) for l in ([10, 20, 30], [40, 50, 60], [90, 100, 110])]\n"
        "print('sat', ['%.3f %.3f %s' % (x[1], x[2], x[3]) for x in s], p.v_saturation(s[0][3]))\n"
        "w = [1000 + 300 * 0.6 ** n for n in range(1, 6)]\n"
        "print('fit %.6f' % r.geometric_fit(w, 0.6)[0], 'stat %.6f %s' % r.stationary(w, 0.6, None, 0.05)[::2])\n"
        "print('settled', r.stationary(w, 0.6, 1234.0, 0.05))\n"
        "runs = [[a + b * 0.6 ** n for n in range(1, 9)] for a, b in ((1000, 300), (1500, -200), (800, 500))]\n"
        "print('rate %.2f' % r.pooled_rate(runs)[0])\n"
        "g = ['a', 'a', 'a', 'b', 'b', 'b']; x = [0.60, 0.61, 0.63, 0.60, 0.62, 0.64]\n"
        "y = [(10 if k == 'a' else 20) + 2 * v + e for k, v, e in zip(g, x, [0] * 6)]\n"
        "print('slope %.2f' % r.factor_regression(g, x, y)[0])\n";
    write_file(scratch_path("tools", "rules_synth.py"), code);
    const Outcome r = shell("cd " + kSource.string() + " && " + kPython + scratch_path("tools", "rules_synth.py").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("band ['within', 'beyond', 'resolved', 'unresolved', None]"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("dir ['yes', 'against', 'unresolved'] reproduced | not reproduced | consistent, not "
                            "established | open (runs pending)"),
              std::string::npos) << r.output;
    EXPECT_NE(r.output.find("eq reproduced | not reproduced | consistent, not established"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("sat ['0.200 0.248 saturating', '0.500 0.248 undecided', '1.000 0.248 not saturating'] "
                            "reproduced"),
              std::string::npos) << r.output;
    EXPECT_NE(r.output.find("fit 1000.000000 stat 1000.000000 extrapolated"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("settled (1234.0, 0.0, 'settled')"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rate 0.60"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("slope 2.00"), std::string::npos) << r.output;
    fs::remove(scratch_path("tools", "rules_synth.py"));
}

TEST(Tools, PaperReportDecidesAClaimFromPairedIntervals) {
    const fs::path d = scratch_path("tools", "paper_report");
    fs::remove_all(d);
    const fs::path data = d / "data";
    // The 25.5 mm rows of seeds first..last (the formula above).
    auto underpressure_rows = [&](int first, int last) {
        for (int dp : {20000, 40000, 60000, 80000})
            for (int s = first; s <= last; ++s) {
                const fs::path c = data / "radius_underpressure" /
                                   ("damper.radius=0.0255_process.underpressure=" + std::to_string(dp) +
                                    "_simulation.seed=" + std::to_string(s));
                fs::create_directories(c);
                const double W = 500 + 10 * s + 0.025 * (dp - 20000) + (dp > 20000 ? 6 * (s - 1) : 0);
                std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
                for (int k = 1; k <= 5; ++k) csv += std::to_string(k) + ",1," + std::to_string(W) + ",100,0\n";
                write_file(c / "cycles.csv", csv);
                write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": 1090}\n");
            }
    };
    underpressure_rows(1, 3);
    const std::string env = "VPPDEM=" + kBinary + " DATA=" + data.string() + " DOCS=" + d.string() + " ";
    const Outcome r = shell(env + "bash " + (kSource / "scripts/paper_report.sh").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string page = slurp(d / "paper_comparison.md");
    EXPECT_NE(page.find("0.06: +1006 +- 15 (+193%)"), std::string::npos) << page;
    EXPECT_NE(page.find("0.02 MPa: 520 +- 25 (n 3 of 5)"), std::string::npos) << page;  // 510, 520, 530: t 10 / sqrt(3) = 24.8
    // The repository's modulus and radius studies run 5 seeds, 3 planned (seeds 4-5 added after a
    // look): the verdicts are decided over the planned 3 (PLANNED in vppdem.report.paper).
    // C1 by the rules: paired, over the 3 seeds the study planned (no added seeds yet: nothing beside).
    EXPECT_NE(page.find("| reproduced: 0.04 MPa +506 +- 15 (+97%); 0.06 MPa +1006 +- 15 (+193%); 0.08 MPa +1506 +- 15 "
                        "(+290%) |"),
              std::string::npos)
        << page;
    EXPECT_NE(page.find("12 of 12 finished 5-cycle runs are stationary"), std::string::npos) << page;
    // The rules at the head; the claims issue 44 added; the stationary-W, packing and friction-share sections.
    for (const char* s : {"## Decision rules", "**Welch t** with the Welch-Satterthwaite degrees of freedom",
                          "+-10% of the reference's mean", "| C31 |", "| C32 |", "| C33 |", "## Stationary W",
                          "## W and the packing", "## Friction share: local damping and loading speed"})
        EXPECT_NE(page.find(s), std::string::npos) << s;
    EXPECT_NE(page.find("| C16 |"), std::string::npos);
    EXPECT_NE(page.find("open (runs pending)"), std::string::npos);  // friction: no runs
    // The studies whose reference cases are another study's runs take them from it: the
    // modulus study's 2.3 GPa is the underpressure study's 0.06 MPa (1510, 1526, 1542: t 16 /
    // sqrt(3) = 39.7), the preparation study's re-fill its 0.02 MPa. (They stayed pending while
    // the assembly's loop variable was shadowed.)
    EXPECT_NE(page.find("2300 MPa: 1526 +- 40"), std::string::npos) << page;
    EXPECT_NE(page.find("0.02 MPa: re-fill 520 +- 25"), std::string::npos) << page;
    EXPECT_TRUE(fs::exists(d / "paper_underpressure_radius.png"));
    const auto paired = rows_of(data / "report" / "radius_underpressure" / "summary_paired.csv");
    bool found = false;
    for (const auto& p : paired)
        if (p.at("key") == "process.underpressure" && p.at("value") == "60000" && p.at("quantity") == "W_settled" &&
            p.at("group") == "damper.radius=0.0255") {
            found = true;
            EXPECT_NEAR(std::stod(p.at("diff_mean")), 1006.0, 1e-9);
            EXPECT_NEAR(std::stod(p.at("diff_ci95")), 4.302652729911275 * 6.0 / std::sqrt(3.0), 1e-6);
        }
    EXPECT_TRUE(found);
    // C9 (insensitive to E_k) is decided, provisionally (the study plans 5), once every modulus has
    // 3 seeds (a paired difference over fewer is shown, marked with its n, and decides nothing). Against the 2.3 GPa
    // runs above (1510, 1526, 1542): 23 MPa 800 + s (resolved, lower), 230 MPa 20 lower in every
    // seed (-20 +- 0: within 10% of 1526), 23 GPa -100, +100, 0 (sd 100, half width 4.303 * 100 /
    // sqrt(3) = 248 > 153: unresolved, reaching past 10%).
    const double ref[3] = {1510, 1526, 1542}, off23g[3] = {-100, 100, 0};
    auto young = [&](const std::string& e, int s, double W) {
        const fs::path c = data / "young" / ("grains.young=" + e + "_simulation.seed=" + std::to_string(s));
        fs::create_directories(c);
        std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
        for (int k = 1; k <= 5; ++k) csv += std::to_string(k) + ",1," + std::to_string(W) + ",100,0\n";
        write_file(c / "cycles.csv", csv);
        write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": 1090}\n");
    };
    for (int s = 1; s <= 3; ++s) {
        young("2.3e+07", s, 800 + s);
        young("2.3e+08", s, ref[s - 1] - 20);
        if (s < 3) young("2.3e+10", s, ref[s - 1] + off23g[s - 1]);
    }
    auto c9 = [&]() {
        const Outcome rr = shell(env + "bash " + (kSource / "scripts/paper_report.sh").string());
        EXPECT_EQ(rr.status, 0) << rr.output;
        const std::string pg = slurp(d / "paper_comparison.md");
        const std::size_t at = pg.find("| C9 |");
        return at == std::string::npos ? std::string() : pg.substr(at, pg.find('\n', at) - at);
    };
    std::string v = c9();
    EXPECT_NE(v.find("23000 MPa: 1518 +- 1372 (n 2 of 5)"), std::string::npos) << v;  // 1410, 1626: 12.71 * 152.7 / sqrt(2)
    EXPECT_NE(v.find("| open (runs pending) |"), std::string::npos) << v;  // 23 GPa: 2 of 3 seeds
    // Welch (each modulus its own samples) over the seeds in, shown; 23 GPa short of its 3 planned seeds:
    // not decided. 230 MPa: sds 16 and 16 over 3, se 13.06, dof 4: 2.776 * 13.06 = 36.
    EXPECT_NE(v.find("against 2.3 GPa (Welch, all seeds): 23 MPa -724 +- 40 (-47%); 230 MPa -20 +- 36 (-1%); "
                     "23000 MPa -8 +- 1331 (-1%)"),
              std::string::npos) << v;
    young("2.3e+10", 3, ref[2] + off23g[2]);
    v = c9();
    // 230 MPa within 10% of 1526 (-20 +- 36), 23 GPa not resolved, reaching past 10% (+0 +- 263, Welch dof 2.09).
    EXPECT_NE(v.find("| consistent, not established: 23 MPa -724 +- 40 (-47%); 230 MPa -20 +- 36 (-1%); 23000 MPa +0 +- "
                     "263 (+0%) |"),
              std::string::npos) << v;
    // C28 (a wider damper has lower W) per radius against 25.5 mm, at each dp: 30.5 mm is
    // W_25.5 - 300 - 10 s (-320 +- 24.8: below, resolved, the paper's direction at 4 of 4 dp);
    // 20.5 mm is W_25.5 - 20 + {50, -50, 0} (-20 +- 4.303 * 50 / sqrt(3) = 124: not resolved).
    // Both below in the mean: W peaks at 25.5 mm, and the page says its samples are the densest
    // only where their packing fraction is the largest. C26 (the loop energy grows with the
    // radius) on energies of W / 1000 J: 30.5 mm lower, resolved (against the paper), 20.5 mm not
    // resolved.
    auto radius = [&](double pack20) {
        for (int dp : {20000, 40000, 60000, 80000})
            for (int s = 1; s <= 3; ++s)
                for (const char* r : {"0.0205", "0.0255", "0.0305"}) {
                    const fs::path c = data / "radius_underpressure" /
                                       ("damper.radius=" + std::string(r) + "_process.underpressure=" +
                                        std::to_string(dp) + "_simulation.seed=" + std::to_string(s));
                    const double W25 = 500 + 10 * s + 0.025 * (dp - 20000) + (dp > 20000 ? 6 * (s - 1) : 0);
                    const std::string rs = r;
                    const double W = rs == "0.0255"   ? W25
                                     : rs == "0.0305" ? W25 - 300 - 10 * s
                                                      : W25 - 20 + 50 * ((s == 1) - (s == 2));
                    const double pack = rs == "0.0255" ? 0.62 : rs == "0.0305" ? 0.60 : pack20;
                    fs::create_directories(c);
                    std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
                    for (int k = 1; k <= 5; ++k)
                        csv += std::to_string(k) + "," + std::to_string(W / 1000) + "," + std::to_string(W) + ",100,0\n";
                    write_file(c / "cycles.csv", csv);
                    write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": 1090, \"preparation\": "
                                                   "{\"packing_fraction\": " + std::to_string(pack) + "}}\n");
                }
        const Outcome rr = shell(env + "bash " + (kSource / "scripts/paper_report.sh").string());
        EXPECT_EQ(rr.status, 0) << rr.output;
        const std::string pg = slurp(d / "paper_comparison.md");
        const std::size_t at = pg.find("| C26 |");
        return at == std::string::npos ? std::string() : pg.substr(at, pg.find("| C29 |", at) - at);
    };
    // By the rules: Welch (each radius its own samples). 30.5 mm at 0.06 MPa: 1200, 1206, 1212 against
    // 1510, 1526, 1542: -320, se sqrt((36 + 256) / 3) = 9.87, Welch dof 2.55, +- 35: below, resolved (the
    // paper's direction); 20.5 mm: 1540, 1456, 1522 (sd 44.2): -20, se 27.2, dof 2.51, +- 97: not
    // resolved. C28 is consistent, not established (nothing against it resolved); C26 (the energy grows
    // with the radius) not reproduced: 30.5 mm's energy lower, resolved, at every dp.
    const std::string c28v =
        "| consistent, not established: 0.02 MPa 30.5 mm -320 +- 25 (-62%) [yes]; 0.02 MPa 20.5 mm -20 +- 107 (-4%) "
        "[unresolved]; 0.04 MPa 30.5 mm -320 +- 35 (-31%) [yes];";
    const std::string peak = ". The mean W peaks at 25.5 mm at every dp. Confound: the radii's samples differ in packing";
    v = radius(0.61);
    EXPECT_NE(v.find("0.06 MPa, 30.5 mm: -320 +- 35 ("), std::string::npos) << v;
    EXPECT_NE(v.find("0.06 MPa, 20.5 mm: -20 +- 97 ("), std::string::npos) << v;
    EXPECT_NE(v.find("20.5 / 25.5 / 30.5 mm: 0.610 +- 0.000 (n 3 of 5) / 0.620 +- 0.000 (n 3 of 5) / 0.600 +- 0.000 (n 3 of 5)"),
              std::string::npos) << v;
    EXPECT_NE(v.find(c28v), std::string::npos) << v;
    EXPECT_NE(v.find(peak), std::string::npos) << v;
    EXPECT_NE(v.find("summary.json 'preparation'), and W peaks with it (section"), std::string::npos) << v;
    EXPECT_NE(v.find("| not reproduced: 0.02 MPa 30.5 mm -0.32 +- 0.02 (-62%) [against]; 0.02 MPa 20.5 mm -0.02 +- 0.11 "
                     "(-4%) [unresolved];"),
              std::string::npos) << v;
    v = radius(0.63);  // the 20.5 mm samples the densest: W does not follow the packing here
    EXPECT_NE(v.find(c28v), std::string::npos) << v;
    EXPECT_NE(v.find("summary.json 'preparation') (section"), std::string::npos) << v;
    // Seeds 4 and 5 of the 25.5 mm rows: C1 is decided over all 5 (0.06 MPa from 0.02 MPa: 1000 +
    // 6 (s - 1), mean 1012, sd 9.49, t_{0.975,4} 2.776 * 9.49 / sqrt(5) = 11.8; 0.02 MPa's mean 530),
    // no longer provisional, while C26 and C28 (20.5 and 30.5 mm over 3) still are. The time step's
    // seeds 1-5 against the radius study's 25.5 mm, 0.06 MPa runs (the friction study's mu 0.6,
    // its first reference, has none here): W 1494 + 16 s - 20 - s, paired -21 ... -25, mean -23,
    // sd 1.58, 2.776 * 1.58 / sqrt(5) = 2.0, within 5% of 1542: C5 reproduced over all 5.
    underpressure_rows(4, 5);
    for (int s = 1; s <= 5; ++s) {
        const fs::path c = data / "timestep" / ("simulation.dt-safety=0.25_simulation.seed=" + std::to_string(s));
        fs::create_directories(c);
        const double W = 1494 + 16 * s - 20 - s;
        write_file(c / "cycles.csv", "cycle,dissipated_energy,W,peak_force,min_force\n1,1," + std::to_string(W) +
                                         ",100,0\n2,1," + std::to_string(W) + ",100,0\n");
        write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": 1090}\n");
    }
    {
        const Outcome rr = shell(env + "bash " + (kSource / "scripts/paper_report.sh").string());
        ASSERT_EQ(rr.status, 0) << rr.output;
        const std::string pg = slurp(d / "paper_comparison.md");
        const std::size_t at = pg.find("| C1 |");
        const std::string c1 = at == std::string::npos ? std::string() : pg.substr(at, pg.find('\n', at) - at);
        EXPECT_NE(c1.find("0.06: +1012 +- 12 (+191%);"), std::string::npos) << c1;
        EXPECT_NE(c1.find("0.02 MPa: 530 +- 20;"), std::string::npos) << c1;  // 510 ... 550: 2.776 * 15.8 / sqrt(5)
        // C1 decided over the 3 planned seeds, all 5 beside it; C28 still over 3 (20.5 and 30.5 mm have 3).
        EXPECT_NE(c1.find("| reproduced: 0.04 MPa +506 +- 15 (+97%); 0.06 MPa +1006 +- 15 (+193%); 0.08 MPa +1506 +- 15 "
                          "(+290%) [seeds 4-5 added after a look, all 5 seeds: reproduced: 0.04 MPa +512 +- 12 (+97%);"),
                  std::string::npos) << c1;
        EXPECT_NE(pg.find(c28v), std::string::npos) << pg;
        // C5 over the time step's 2 planned seeds (-21, -22: -21.5 +- 12.71 * 0.707 / sqrt(2) = 6.4, within 10%),
        // all 5 beside (-23 +- 2).
        EXPECT_NE(pg.find("paired: -23 +- 2 (-1%); converged W: pending (section 'Time step converged') | paired t; "
                          "equivalence +-10%; W of cycle 2 at both; 2 planned seeds | "
                          "reproduced: dt_safety 0.25 against 0.45 -22 +- 6 (-1%) [seeds 3-5 added after a look, all 5 "
                          "seeds: reproduced: dt_safety 0.25 against 0.45 -23 +- 2 (-1%)]"),
                  std::string::npos) << pg;
    }
    fs::remove_all(d);
}

// The time step's convergence (issue 44, item 2; vppdem.report.paper timestep_section, vppdem.report.paper_rules
// richardson / level_bias / converged_level) on synthetic runs with a known answer: W_i(s) = 1500 + 300 s^2 +
// off_i + e_i(s), seed offsets off_i = 40 (i - 3) (mean 0), a deterministic noise e within +-0.5 J/m2. The
// converged W0_i = 1500 + off_i, mean 1500; the order 2; the biases 300 s^2 / W0_i: 0.45 +4.1%, 0.3 +1.8%,
// 0.25 +1.3%, 0.2 +0.8%, 0.1 +0.2%: the default rule (the largest level within 2%) picks 0.3, whose whole 95%
// interval lies within 2%: the default (src/vpp/settings/settings.cpp, 0.3 since the study) is that level. The reference 0.45 is the
// radius study's 25.5 mm, 0.06 MPa runs (their cycle 2), the other levels the time step's own runs. While levels
// are missing the section names them pending and extrapolates over the seeds with every level only.
TEST(Tools, PaperReportExtrapolatesTheTimeStep) {
    // The rules alone, to more digits: the model above, and a first-order one (W0 1500, a 250: biases
    // 0.45 +7.5%, 0.1 +1.7%: the default 0.1).
    const std::string code =
        "import sys; sys.path.insert(0, 'src/python'); from vppdem.report import paper_rules as r, stats as st\n"
        "L = [0.45, 0.3, 0.25, 0.2, 0.1]\n"
        "e = lambda i, k: 0.25 * ((3 * i + 7 * k) % 5 - 2)\n"
        "for p, a in ((2, 300), (1, 250)):\n"
        "    runs = {i: {s: 1500 + a * s ** p + 40 * (i - 3) + e(i, k) for k, s in enumerate(L)} for i in range(1, 6)}\n"
        "    f = r.richardson(runs)\n"
        "    b = r.level_bias(runs, f['w0'])\n"
        "    c = r.converged_level(b)\n"
        "    print('fit %d %.4f %.4f %.4f %.4f %g %s %.4f' % (p, f['mean'][1], f['p'], f['p_lo'], f['p_hi'], c[0], c[1],\n"
        "          b[0.45][1]))\n"
        "print('short', r.richardson({1: {0.45: 1, 0.25: 2}, 2: {0.45: 1, 0.25: 2}}), r.converged_level({0.1: (5, 0.03, 0, 0.01)}))\n";
    write_file(scratch_path("tools", "rules_ts.py"), code);
    const Outcome rr = shell("cd " + kSource.string() + " && " + kPython + scratch_path("tools", "rules_ts.py").string());
    ASSERT_EQ(rr.status, 0) << rr.output;
    std::istringstream in(rr.output);
    for (int want : {2, 1}) {
        std::string tag, tight;
        int p = 0;
        double w0 = 0, ph = 0, plo = 0, phi = 0, chosen = 0, b45 = 0;
        in >> tag >> p >> w0 >> ph >> plo >> phi >> chosen >> tight >> b45;
        EXPECT_EQ(tag, "fit");
        EXPECT_EQ(p, want);
        EXPECT_NEAR(w0, 1500.0, 0.5) << rr.output;  // the noise's +-0.5 moves W0 by a fraction of it
        EXPECT_NEAR(ph, want, 0.05) << rr.output;
        EXPECT_LE(plo, want);
        EXPECT_GE(phi, want);
        EXPECT_LT(phi - plo, 0.3) << rr.output;
        EXPECT_NEAR(chosen, want == 2 ? 0.3 : 0.1, 1e-12) << rr.output;
        EXPECT_EQ(tight, "True");
        EXPECT_NEAR(b45, want == 2 ? 0.0405 : 0.075, 0.002) << rr.output;  // 300 0.45^2 / 1500, 250 0.45 / 1500
    }
    EXPECT_NE(rr.output.find("short None (None, False, [])"), std::string::npos) << rr.output;
    fs::remove(scratch_path("tools", "rules_ts.py"));

    // The page, from published runs.
    const fs::path d = scratch_path("tools", "paper_timestep");
    fs::remove_all(d);
    const fs::path data = d / "data";
    const std::vector<std::string> levels = {"0.45", "0.3", "0.25", "0.2", "0.1"};
    auto W = [](int i, std::size_t k) {
        const double s = std::stod(std::vector<std::string>{"0.45", "0.3", "0.25", "0.2", "0.1"}[k]);
        return 1500 + 300 * s * s + 40 * (i - 3) + 0.25 * ((3 * i + 7 * static_cast<int>(k)) % 5 - 2);
    };
    auto run = [&](const fs::path& c, int cycles, double w) {
        fs::create_directories(c);
        std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
        for (int n = 1; n <= cycles; ++n) csv += std::to_string(n) + ",1," + std::to_string(n == 1 ? w + 700 : w) + ",100,0\n";
        write_file(c / "cycles.csv", csv);
        write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": 1090}\n");
    };
    auto level = [&](std::size_t k, int first, int last) {
        for (int i = first; i <= last; ++i) {
            if (k == 0)  // 0.45: the radius study's 25.5 mm, 0.06 MPa run of the seed, 5 cycles (the assembly takes 2)
                run(data / "radius_underpressure" /
                        ("damper.radius=0.0255_process.underpressure=60000_simulation.seed=" + std::to_string(i)),
                    5, W(i, k));
            else
                run(data / "timestep" / ("simulation.dt-safety=" + levels[k] + "_simulation.seed=" + std::to_string(i)),
                    2, W(i, k));
        }
    };
    const std::string env = "VPPDEM=" + kBinary + " DATA=" + data.string() + " DOCS=" + d.string() + " ";
    auto section = [&]() {
        const Outcome r = shell(env + "bash " + (kSource / "scripts/paper_report.sh").string());
        EXPECT_EQ(r.status, 0) << r.output;
        const std::string pg = slurp(d / "paper_comparison.md");
        const std::size_t at = pg.find("## Time step converged");
        const std::size_t c5 = pg.find("| C5 |");
        EXPECT_NE(at, std::string::npos) << pg;
        EXPECT_NE(c5, std::string::npos) << pg;
        if (at == std::string::npos || c5 == std::string::npos) return std::string();
        return pg.substr(c5, pg.find('\n', c5) - c5) + "\n" + pg.substr(at, pg.find("\n## ", at + 3) - at);
    };
    // 0.45 and 0.25 only (as published now): the other levels pending, nothing extrapolated, no crash.
    level(0, 1, 5);
    level(2, 1, 5);
    std::string v = section();
    EXPECT_NE(v.find("| seeds in | 5 of 5 | 0 of 5 | 5 of 5 | 0 of 5 | 0 of 5 |"), std::string::npos) << v;
    EXPECT_NE(v.find("- Pending: 0.3 (0 of 5 seeds), 0.2 (0 of 5 seeds), 0.1 (0 of 5 seeds)."), std::string::npos) << v;
    EXPECT_NE(v.find("Converged W, order, biases and the default: pending"), std::string::npos) << v;
    EXPECT_NE(v.find("converged W: pending"), std::string::npos) << v;  // C5's row
    EXPECT_EQ(v.find("Default rule"), std::string::npos) << v;
    EXPECT_TRUE(fs::exists(d / "paper_timestep.png"));  // the runs in, without a fit
    // 0.3 and 0.2 at every seed, 0.1 at seeds 1-3: extrapolated over those 3, provisionally.
    level(1, 1, 5);
    level(3, 1, 5);
    level(4, 1, 3);
    v = section();
    EXPECT_NE(v.find("- Pending: 0.1 (3 of 5 seeds)."), std::string::npos) << v;
    EXPECT_NE(v.find("over the 3 seeds with every level (1, 2, 3; 15 points) (provisional: 3 of 5 planned seeds)"),
              std::string::npos) << v;
    EXPECT_NE(v.find("**0.3** (its 95% interval lies within +-2%). The default (0.3, src/vpp/settings/settings.cpp) is that level"),
              std::string::npos) << v;
    // Every level: W0 per seed 1420, 1460, 1500, 1540, 1580 (sd 63.2, t_{0.975,4} 2.776: +- 79), mean 1500; p 2.
    level(4, 4, 5);
    v = section();
    EXPECT_EQ(v.find("- Pending"), std::string::npos) << v;
    EXPECT_NE(v.find("over the 5 seeds with every level (1, 2, 3, 4, 5; 25 points)."), std::string::npos) << v;
    EXPECT_NE(v.find("Converged W (s -> 0), per seed: 1: 1420, 2: 1460, 3: 1500, 4: 1540, 5: 1580; mean **1500 +- 79 J/m2**"),
              std::string::npos) << v;
    const std::size_t at = v.find("Order: p = ");
    ASSERT_NE(at, std::string::npos) << v;
    EXPECT_NEAR(std::stod(v.substr(at + 11, 4)), 2.0, 0.05) << v;
    EXPECT_NE(v.find("0.45: +4.1% +- "), std::string::npos) << v;
    EXPECT_NE(v.find("The studies' time step (0.45) lies +4.1% +- "), std::string::npos) << v;
    EXPECT_NE(v.find("of the converged W: **0.3** (its 95% interval lies within +-2%). The default (0.3, "
                     "src/vpp/settings/settings.cpp) is that level, since this study; the studies ran at 0.45, the default of "
                     "their build"),
              std::string::npos) << v;
    EXPECT_NE(v.find("converged W (Richardson over 5 seeds, section 'Time step converged'): 1500 +- 79 J/m2; dt_safety "
                     "0.45 biased +4.1% +- "),
              std::string::npos) << v;  // C5's row
    EXPECT_NE(v.find("; default rule: 0.3 |"), std::string::npos) << v;
    EXPECT_TRUE(fs::exists(d / "paper_timestep.png"));
    fs::remove_all(d);
}

// The radius at equal packing (issue 44, item 3; vppdem.report.paper radius_packing_section, C26 / C28 /
// C29) on synthetic runs of known W, 5 flat cycles each (every run stationary: W_settled), 5 seeds with the
// offsets 10 (s - 3) J/m2 (sd 15.81; a radius's mean +- 2.776 * 15.81 / sqrt(5) = 20; two radii by Welch:
// se 10, dof 8, +- 2.306 * 10 = 23). At equal packing (radius_packing): at 0.02 MPa W = 800 at every radius
// (differences +0 +- 23: no shape resolved); at 0.06 MPa 1440 / 1600 / 1280 for 20.5 / 25.5 / 30.5 mm
// (-160 +- 23 and -320 +- 23: a peak at 25.5 mm, resolved): W peaks at 1 of 2 dp, and C28 (W falls with the
// radius) is not reproduced there (20.5 mm below 25.5 mm, resolved), while C26 (the loop energy W pi r_p^2
// grows with the radius) is. The radius study's (unadjusted) samples at the same dp: 730 / 850 / 350 and
// 1330 / 1590 / 700; at 0.06 MPa its 20.5 mm effect -260 becomes -160, a change +100 +- 2.120 * sqrt(4 * 50)
// = 30 (Welch-Satterthwaite over the four groups: 16 dof), the packing's part 100 / 260 = 38%. The samples'
// packing: 0.620 within half a grain (0.5 * 0.62 / grains) but for one 30.5 mm sample at 0.621 (half a
// grain 0.00020 there). Missing: pending, no crash; seeds 1-3: provisional, C26 / C28 'pending (18 of 30)'.
TEST(Tools, PaperReportDecidesTheRadiusAtEqualPacking) {
    const fs::path d = scratch_path("tools", "paper_radius_packing");
    fs::remove_all(d);
    const fs::path data = d / "data";
    const std::map<std::string, int> grains = {{"0.0205", 680}, {"0.0255", 1090}, {"0.0305", 1580}};
    auto run = [&](const std::string& study, const std::string& r, int dp, int s, double W, double pack) {
        const fs::path c = data / study /
                           ("damper.radius=" + r + "_process.underpressure=" + std::to_string(dp) + "_simulation.seed=" +
                            std::to_string(s));
        fs::create_directories(c);
        const double E = W * std::numbers::pi * std::stod(r) * std::stod(r);
        std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
        for (int k = 1; k <= 5; ++k) csv += std::to_string(k) + "," + std::to_string(E) + "," + std::to_string(W) + ",100,0\n";
        write_file(c / "cycles.csv", csv);
        write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": " + std::to_string(grains.at(r)) +
                                           ", \"preparation\": {\"packing_fraction\": " + std::to_string(pack) + "}}\n");
    };
    const std::map<std::string, std::pair<double, double>> unadjusted = {
        {"0.0205", {730, 1330}}, {"0.0255", {850, 1590}}, {"0.0305", {350, 700}}};
    const std::map<std::string, double> unadjusted_pack = {{"0.0205", 0.613}, {"0.0255", 0.624}, {"0.0305", 0.615}};
    const std::map<std::string, std::pair<double, double>> equal = {
        {"0.0205", {800, 1440}}, {"0.0255", {800, 1600}}, {"0.0305", {800, 1280}}};
    for (const auto& [r, w] : unadjusted)
        for (int s = 1; s <= 5; ++s) {
            run("radius_underpressure", r, 20000, s, w.first + 10 * (s - 3), unadjusted_pack.at(r));
            run("radius_underpressure", r, 60000, s, w.second + 10 * (s - 3), unadjusted_pack.at(r));
        }
    auto packing_runs = [&](int first, int last) {
        for (const auto& [r, w] : equal)
            for (int s = first; s <= last; ++s) {
                const double pack = r == "0.0305" && s == 5 ? 0.621 : 0.62;
                run("radius_packing", r, 20000, s, w.first + 10 * (s - 3), pack);
                run("radius_packing", r, 60000, s, w.second + 10 * (s - 3), pack);
            }
    };
    struct Page {
        std::string section, c26, c28, c29, all;
    };
    auto page = [&]() {
        const Outcome r = shell("VPPDEM=" + kBinary + " DATA=" + data.string() + " DOCS=" + d.string() + " bash " +
                                (kSource / "scripts/paper_report.sh").string());
        EXPECT_EQ(r.status, 0) << r.output;
        Page p;
        p.all = slurp(d / "paper_comparison.md");
        auto row = [&](const std::string& id) {
            const std::size_t at = p.all.find("| " + id + " |");
            return at == std::string::npos ? std::string() : p.all.substr(at, p.all.find('\n', at) - at);
        };
        p.c26 = row("C26"), p.c28 = row("C28"), p.c29 = row("C29");
        const std::size_t at = p.all.find("## Radius at equal packing (C26, C28)");
        EXPECT_NE(at, std::string::npos) << p.all;
        if (at != std::string::npos) p.section = p.all.substr(at, p.all.find("\n## ", at + 3) - at);
        return p;
    };
    // No radius_packing folder: pending everywhere, no crash.
    Page p = page();
    EXPECT_NE(p.all.find(", radius_packing 0 of 30."), std::string::npos) << p.all;  // 'Runs finished'
    EXPECT_NE(p.section.find("- Runs finished: 0 of 30 (pending)."), std::string::npos) << p.section;
    EXPECT_NE(p.section.find("the differences and the answer: pending (no run finished)."), std::string::npos) << p.section;
    EXPECT_NE(p.c28.find("; at equal packing (section 'Radius at equal packing'): pending (0 of 30) |"), std::string::npos)
        << p.c28;
    EXPECT_NE(p.c26.find("; at equal packing (section 'Radius at equal packing'): pending (0 of 30) |"), std::string::npos)
        << p.c26;
    // Seeds 1-3 of every case: shown, provisional; the claims still pending.
    packing_runs(1, 3);
    p = page();
    EXPECT_NE(p.section.find("- Runs finished: 18 of 30 (the rest pending"), std::string::npos) << p.section;
    EXPECT_NE(p.section.find("- 0.06 MPa (provisional: 3 of 5 seeds): W_settled [J/m2] by r_p 20.5 / 25.5 / 30.5 mm: "
                             "1430 +- 25 (n 3 of 5) / 1590 +- 25 (n 3 of 5) / 1270 +- 25 (n 3 of 5)"),
              std::string::npos) << p.section;
    EXPECT_NE(p.section.find("- Provisional (18 of 30 runs): Does W still peak at 25.5 mm at equal packing? In part: at 1 "
                             "of 2 dp"),
              std::string::npos) << p.section;
    EXPECT_NE(p.c28.find("pending (18 of 30) |"), std::string::npos) << p.c28;
    EXPECT_NE(p.c26.find("pending (18 of 30) |"), std::string::npos) << p.c26;
    // All 30: decided.
    packing_runs(4, 5);
    p = page();
    const std::string& s = p.section;
    EXPECT_NE(s.find("- Runs finished: 30 of 30."), std::string::npos) << s;
    EXPECT_EQ(s.find("rovisional"), std::string::npos) << s;
    EXPECT_NE(s.find("20.5 mm 0.620 +- 0.000, 5 of 5 samples within half a grain of 0.62 (half a grain 0.00046)"),
              std::string::npos) << s;
    EXPECT_NE(s.find("30.5 mm 0.620 +- 0.001, 4 of 5 samples within half a grain of 0.62 (half a grain 0.00020)"),
              std::string::npos) << s;
    EXPECT_NE(s.find("The radius study's samples: 0.613 +- 0.000 / 0.624 +- 0.000 / 0.615 +- 0.000"), std::string::npos) << s;
    EXPECT_NE(s.find("- 0.02 MPa: W_settled [J/m2] by r_p 20.5 / 25.5 / 30.5 mm: 800 +- 20 / 800 +- 20 / 800 +- 20; "
                     "Welch: 20.5 - 25.5 mm +0 +- 23 (+0%); 30.5 - 25.5 mm +0 +- 23 (+0%): no shape resolved"),
              std::string::npos) << s;
    EXPECT_NE(s.find("- 0.06 MPa: W_settled [J/m2] by r_p 20.5 / 25.5 / 30.5 mm: 1440 +- 20 / 1600 +- 20 / 1280 +- 20; "
                     "Welch: 20.5 - 25.5 mm -160 +- 23 (-10%); 30.5 - 25.5 mm -320 +- 23 (-20%): W peaks at 25.5 mm"),
              std::string::npos) << s;
    EXPECT_NE(s.find("Against the radius study's samples at 0.06 MPa (W_settled, Welch, all seeds of both; equal packing "
                     "minus unadjusted): 20.5 mm +110 +- 23 (+8%); 25.5 mm +10 +- 23 (+1%); 30.5 mm +580 +- 23 (+83%). "
                     "Radius effects: 20.5 - 25.5 mm -260 +- 23 (-16%) unadjusted, -160 +- 23 (-10%) at equal packing, "
                     "change +100 +- 30 (the packing's part: 38% of the unadjusted effect)"),
              std::string::npos) << s;
    EXPECT_NE(s.find("Does W still peak at 25.5 mm at equal packing? In part: at 1 of 2 dp both neighbours lie below "
                     "25.5 mm, resolved at 95% by Welch (0.02 MPa: unresolved, 0.06 MPa: peak). By the rules (direction "
                     "at every dp, Welch): C28 at equal packing not reproduced, C26 (the loop energy) reproduced."),
              std::string::npos) << s;
    // Every run flat, so its stationary W is its W: the same answer on the stationary W.
    EXPECT_NE(s.find("On each run's stationary W (W_settled, or W_inf at the pooled q "), std::string::npos) << s;
    EXPECT_NE(s.find("W peaks at 25.5 mm, resolved, at 1 of 2 dp (0.02 MPa: unresolved, 0.06 MPa: peak; 0.02 MPa 20.5 mm "
                     "+0 +- 23 (+0%) [unresolved]; "),
              std::string::npos) << s;
    EXPECT_NE(s.find("(-20%) [yes]); C28 at equal packing not reproduced."), std::string::npos) << s;
    EXPECT_NE(p.c28.find("| not reproduced at equal packing (damper.packing_target 0.62, 5 planned seeds; section 'Radius "
                         "at equal packing'): 0.02 MPa 20.5 mm +0 +- 23 (+0%) [unresolved]; 0.02 MPa 30.5 mm +0 +- 23 "
                         "(+0%) [unresolved]; 0.06 MPa 20.5 mm -160 +- 23 (-10%) [against]; 0.06 MPa 30.5 mm -320 +- 23 "
                         "(-20%) [yes]; W peaks at 25.5 mm, resolved, at 1 of 2 dp. On the radius study's samples"),
              std::string::npos) << p.c28;
    EXPECT_NE(p.c26.find("| reproduced at equal packing (damper.packing_target 0.62, 5 planned seeds; section 'Radius at "
                         "equal packing'): 0.02 MPa 20.5 mm -0.58 +- 0.04 (-35%) [yes]"),
              std::string::npos) << p.c26;
    EXPECT_NE(p.c29.find("| not reproduced (as C28, at equal packing) |"), std::string::npos) << p.c29;
    // The 20.5 mm runs at 0.06 MPa drift: cycles 2-4 at 1600 + 150 (s - 3), cycle 5 at 1440 + 10 (s - 3) as
    // before, so none of them is stationary and the study decides on the last cycle (the same -160 +- 23:
    // C28 at equal packing not reproduced). The pooled decay ratio of the flat five-cycle runs is the
    // grid's lowest, 0.05, so each run's stationary W is about the mean of its cycles 3-5, 1547 + 103 (s - 3):
    // against 25.5 mm -53, its interval about +-200: unresolved, and at 0.02 MPa nothing is resolved, so
    // on the stationary W C28 at equal packing is only consistent: the claim's row says so.
    for (int s = 1; s <= 5; ++s) {
        const fs::path c = data / "radius_packing" /
                           ("damper.radius=0.0205_process.underpressure=60000_simulation.seed=" + std::to_string(s));
        const double area = std::numbers::pi * 0.0205 * 0.0205;
        std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
        for (int k = 1; k <= 5; ++k) {
            const double W = k == 5 ? 1440 + 10 * (s - 3) : 1600 + 150 * (s - 3);
            csv += std::to_string(k) + "," + std::to_string(W * area) + "," + std::to_string(W) + ",100,0\n";
        }
        write_file(c / "cycles.csv", csv);
    }
    p = page();
    EXPECT_NE(p.section.find("20.5 - 25.5 mm -160 +- 23 (-10%)"), std::string::npos) << p.section;
    EXPECT_NE(p.c28.find("| not reproduced at equal packing"), std::string::npos) << p.c28;
    EXPECT_NE(p.c28.find(" [on each run's stationary W (C28 at equal packing, pooled q 0.05): consistent, not established; "
                         "section 'Stationary W'] |"),
              std::string::npos) << p.c28;
    EXPECT_NE(p.section.find("W peaks at 25.5 mm, resolved, at 0 of 2 dp (0.02 MPa: unresolved, 0.06 MPa: unresolved; "),
              std::string::npos) << p.section;
    EXPECT_EQ(p.c26.find("on each run's stationary W"), std::string::npos) << p.c26;  // the loop energy: no W_stat
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

// vppdem.report.grain_shapes by hand: spheres W = 100, 110, 120 and dimers 210, 220, 230 J/m^2
// (3 seeds, sd 10 each): the dimers' difference is +110 (+100% of 110) with Welch's interval
// t_{0.975,4} sqrt(100/3 + 100/3) = 2.7764 * 8.165 = 22.67 (20.6% of 110), printed "+100 +- 21";
// the pressure study's W doubles from 0.02 to 0.08 MPa for every seed: 2.00 +- 0.00. Against a
// plan of spheres and dimers the page is final; against the repository's study (pellets too) it
// says 6 of 9 runs and names the pending ones.
TEST(Tools, GrainShapesReportByHand) {
    const fs::path d = scratch_path("tools", "shapes");
    fs::remove_all(d);
    const auto summary = [](double W, double peak, double dp) {
        std::ostringstream s;
        s << "{\"inputs\": {\"process.velocity\": 0.02, \"process.underpressure\": " << dp
          << ", \"damper.radius\": 0.0255}, \"grains\": 1100, \"dt\": 1.8e-06, \"run_seconds\": 3600, "
          << "\"cycles\": [{\"cycle\": 1, \"W\": " << W + 50 << ", \"peak_force\": " << peak
          << ", \"friction_dissipation\": 3, \"damping_dissipation\": 1, \"viscous_dissipation\": 0}, "
          << "{\"cycle\": 2, \"W\": " << W << ", \"peak_force\": " << peak
          << ", \"friction_dissipation\": 3, \"damping_dissipation\": 1, \"viscous_dissipation\": 0}], "
          << "\"W_settled\": " << W << ", \"first_settled_cycle\": 2, \"start_of_cycling\": {\"packing_fraction\": 0.6}}";
        return s.str();
    };
    for (int s = 1; s <= 3; ++s) {
        write_file(d / "data" / ("grains.shape=sphere_simulation.seed=" + std::to_string(s)) / "summary.json",
                   summary(90.0 + 10.0 * s, 500, 60000));
        write_file(d / "data" / ("grains.shape=dimer_simulation.seed=" + std::to_string(s)) / "summary.json",
                   summary(200.0 + 10.0 * s, 900, 60000));
        for (const double dp : {20000.0, 80000.0})
            write_file(d / "pressure" /
                           ("damper.radius=0.0255_process.underpressure=" + std::to_string(int(dp)) + "_simulation.seed=" +
                            std::to_string(s)) / "summary.json",
                       summary((dp > 50000 ? 2.0 : 1.0) * (100.0 + s), 500, dp));
    }
    fs::create_directories(d / "docs");
    write_file(d / "plan.toml", "seeds = 3\n[grid]\n\"grains.shape\" = [\"sphere\", \"dimer\"]\n");
    const auto report = [&](const std::string& args) {
        return shell(kReport + "grain_shapes " + (d / "data").string() + " " +
                     (d / "docs").string() + args);
    };
    const std::string with_plan = " --pressure " + (d / "pressure").string() + " --study " + (d / "plan.toml").string();
    const Outcome r = report(with_plan);
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string md = slurp(d / "docs" / "grains.md");
    EXPECT_EQ(md.find("Provisional"), std::string::npos) << md;
    EXPECT_NE(md.find("| sphere | 3 of 3 |"), std::string::npos) << md;
    EXPECT_NE(md.find("| 110 +- 25 |"), std::string::npos) << md;  // t_{0.975,2} 10 / sqrt(3) = 24.8
    // Dimers 210, 220, 230 against spheres 100, 110, 120: R = 2, var(ln R) = 100 / (3 110^2) + 100 /
    // (3 220^2) = 0.0034435 (se 0.058682), Welch dof 2.9412, t = 3.2188: R t se = 0.378, +100 +- 38%.
    EXPECT_NE(md.find("| +100 +- 38 |"), std::string::npos) << md;
    EXPECT_NE(md.find("W 2.00 +- 0.38 times the spheres'"), std::string::npos) << md;
    EXPECT_NE(md.find("W at 0.08 MPa is 2.00 +- 0.00 times W at 0.02 MPa"), std::string::npos) << md;
    // Both effects ln 2; the pressure's without scatter: the difference's half width is the
    // dimers' t se = 0.189 at 2.94 dof, and 0 lies inside it.
    EXPECT_NE(md.find("undecided: the pressure's and a shape's effects on W are equal"), std::string::npos) << md;
    EXPECT_NE(md.find("+- 0.19)"), std::string::npos) << md;
    // Peak forces 900 against 500 N in every run: 1.80 times, without scatter, resolved.
    EXPECT_NE(md.find("peak force over the stroke 1.80 +- 0.00 times (resolved)"), std::string::npos) << md;
    EXPECT_NE(md.find("changes with the shape for dimer (resolved)."), std::string::npos) << md;
    EXPECT_NE(md.find("friction share"), std::string::npos);
    EXPECT_TRUE(fs::exists(d / "docs" / "grains_shapes.png"));
    // The pressure runs' stationarity by the paper report's re-analysis beside them: seed 1 at
    // 0.08 MPa not stationary there, so its W is the mean of its last two cycles, 202 + 25 = 227,
    // and its ratio 227 / 101 = 2.2475; with 2 and 2 the mean ratio is 2.08.
    write_file(d / "report" / "pressure" / "summary.csv",
               "case,W_settled\ndamper.radius=0.0255_process.underpressure=80000_simulation.seed=1,\n");
    const Outcome re = report(with_plan);
    ASSERT_EQ(re.status, 0) << re.output;
    const std::string rmd = slurp(d / "docs" / "grains.md");
    EXPECT_NE(rmd.find("W at 0.08 MPa is 2.08 +- "), std::string::npos) << rmd;
    EXPECT_NE(rmd.find("1 of these 6 runs not stationary"), std::string::npos) << rmd;
    // The repository's plan: pellets too, none run.
    const Outcome part = report("");
    ASSERT_EQ(part.status, 0) << part.output;
    const std::string pmd = slurp(d / "docs" / "grains.md");
    EXPECT_NE(pmd.find("Provisional: 6 of the study's 9 runs"), std::string::npos) << pmd;
    EXPECT_NE(pmd.find("pellet seed 1, pellet seed 2, pellet seed 3"), std::string::npos) << pmd;
    EXPECT_NE(pmd.find("| pellet | 0 of 3 | pending"), std::string::npos) << pmd;
    // A folder without runs is refused naming it.
    fs::create_directories(d / "empty");
    const Outcome bad = shell(kReport + "grain_shapes " + (d / "empty").string() +
                              " " + (d / "docs").string());
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.output.find("no finished runs"), std::string::npos) << bad.output;
    fs::remove_all(d);
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

// C17 and C18 move to the friction study's second leg (friction_8: the runs at mu 0.1 ... 1.0
// taken to 8 cycles) once all of its 18 runs are there, and stay on the 5-cycle study until then.
// Hand-made records, every cycle of a run at one W but for mu 1.0's cycles 6-8: W = B(mu) + 10 s
// with B = 500, 800, 1000, 1300, 1500, 1550, 1600 for mu 0 ... 1; in the leg mu 1.0 falls to 1300
// + 10 s + 4 (s - 1) from cycle 6. 5 cycles: mu 0.6 -> 1.0 is +100 in every seed (+100 +- 0, 7% of
// mu 0.6's 1520: within 10%). The leg: -200, -196, -192, mean -196, sd 4, 95% half width 4.303 *
// 4 / sqrt(3) = 9.9 (-13% of 1520: beyond 10%, resolved); slope ratio (W(1) - W(0.6)) / 0.4 over
// (W(0.6) - W(0.1)) / 0.5 per seed -0.357, -0.350, -0.343. The leg's runs at mu 0.4, 0.6, 1.0
// continued a checkpoint (their summary.json's warning), the other 9 ran from their samples, one
// of which (mu 0.2, seed 3) differs in cycle 3 from the first leg: 8 of 9 repeat it. C18 plans 5
// seeds (the leg's added seeds 4-5, friction_8_seeds): over the leg's 3 it is provisional; with
// seeds 4-5 (the same pattern) it is -200 ... -184, mean -192, sd sqrt(40), half width 2.776 *
// sqrt(40) / sqrt(5) = 7.9, of mu 0.6's 1530: -13%, beyond 10% and final.
TEST(Tools, PaperReportTakesTheFrictionClaimsFromTheCompleteSecondLeg) {
    const fs::path d = scratch_path("tools", "paper_report_leg");
    fs::remove_all(d);
    const fs::path data = d / "data";
    const std::map<std::string, double> B = {{"0", 500},    {"0.1", 800},  {"0.2", 1000}, {"0.4", 1300},
                                             {"0.6", 1500}, {"0.8", 1550}, {"1", 1600}};
    auto runs = [&](const std::string& study, int cycles, int first_seed = 1, int last_seed = 3) {
        for (const auto& [mu, b] : B)
            for (int s = first_seed; s <= last_seed; ++s) {
                if (cycles == 8 && mu == "0") continue;  // the leg leaves mu 0 out
                if (first_seed > 1 && mu != "0.6" && mu != "1") continue;  // the added seeds: C18's two
                const fs::path c = data / study / ("grains.friction=" + mu + "_simulation.seed=" + std::to_string(s));
                fs::create_directories(c);
                std::string csv = "cycle,dissipated_energy,W,peak_force,min_force\n";
                for (int k = 1; k <= cycles; ++k) {
                    double W = mu == "1" && k > 5 ? 1300 + 10 * s + 4 * (s - 1) : b + 10 * s;
                    if (cycles == 8 && mu == "0.2" && s == 3 && k == 3) W += 1e-6;
                    csv += std::to_string(k) + ",1," + std::to_string(W) + ",100,0\n";
                }
                write_file(c / "cycles.csv", csv);
                const bool continued = cycles == 8 && first_seed == 1 && (mu == "0.4" || mu == "0.6" || mu == "1");
                write_file(c / "summary.json",
                           std::string("{\"run_seconds\": 1, \"grains\": 1090, \"warnings\": [") +
                               (continued ? "\"process.cycles raised on a checkpoint of an older vppdem: ...\"" : "") +
                               "]}\n");
            }
        write_file(data / study / "COMMAND",
                   "vppdem sweep (pinned build " + (first_seed > 1 ? std::string("friction_8") : study) + "-build)\n");
    };
    runs("friction", 5);
    runs("friction_8", 8);
    const fs::path held = d / "held";
    fs::rename(data / "friction_8" / "grains.friction=0.4_simulation.seed=2", held);  // 17 of 18
    const std::string report = "VPPDEM=" + kBinary + " DATA=" + data.string() + " DOCS=" + d.string() + " bash " +
                               (kSource / "scripts/paper_report.sh").string();
    auto row = [&](const std::string& page, const std::string& id) {
        const std::size_t at = page.find("| " + id + " |");
        return at == std::string::npos ? std::string() : page.substr(at, page.find('\n', at) - at);
    };
    Outcome r = shell(report);
    ASSERT_EQ(r.status, 0) << r.output;
    std::string page = slurp(d / "paper_comparison.md");
    std::string c18 = row(page, "C18");
    EXPECT_NE(c18.find("W_settled +100 +- 0 (+7%) J/m2, dissipated energy (cycle 5)"), std::string::npos) << c18;
    EXPECT_NE(c18.find("second leg (8 cycles): 17 of 18 runs finished"), std::string::npos) << c18;
    EXPECT_NE(c18.find("| reproduced: mu 1.0 against 0.6 +100 +- 0 (+7%) (+7% to +7%) |"), std::string::npos) << c18;
    EXPECT_NE(page.find("one pinned build for every run (friction-build;"), std::string::npos) << page;
    EXPECT_NE(page.find("by a later build (friction_8-build;"), std::string::npos) << page;
    EXPECT_NE(page.find("17 of 18 runs: `VPPDEM_LEG"), std::string::npos) << page;
    EXPECT_NE(page.find("friction_8 17 of 18, friction_8_seeds 0 of 4, radius_packing 0 of 30."), std::string::npos) << page;
    fs::rename(held, data / "friction_8" / "grains.friction=0.4_simulation.seed=2");
    r = shell(report);
    ASSERT_EQ(r.status, 0) << r.output;
    page = slurp(d / "paper_comparison.md");
    c18 = row(page, "C18");
    EXPECT_NE(c18.find("W_settled -196 +- 10 (-13%) (n 3 of 5) J/m2, dissipated energy (cycle 8)"), std::string::npos)
        << c18;
    EXPECT_NE(c18.find("(8 cycles: the friction study's runs taken on, second leg)"), std::string::npos) << c18;
    // Decided over the leg's 3 planned seeds (beyond the +-10% margin); the added seeds not in yet.
    EXPECT_NE(c18.find("| not reproduced: mu 1.0 against 0.6 -196 +- 10 (-13%) (-14% to -12%) |"), std::string::npos) << c18;
    EXPECT_NE(row(page, "C17").find("-0.35 +- 0.02 (3 seeds) (8 cycles"), std::string::npos) << row(page, "C17");
    EXPECT_NE(page.find("9 continued from their cycle-5 checkpoint"), std::string::npos) << page;
    EXPECT_NE(page.find("9 ran again from their samples (their checkpoints were gone), and 8 of those 9 repeat"),
              std::string::npos) << page;
    // C16 and C2 stay on the 5-cycle runs: 21 runs (the leg's are the same runs longer).
    EXPECT_NE(row(page, "C16").find("1: 1620 +- 25"), std::string::npos) << row(page, "C16");
    EXPECT_NE(page.find("21 of 21 finished 5-cycle runs are stationary"), std::string::npos) << page;
    // C18's added seeds: over 5 seeds, final; C17 stays on the leg's 3 seeds, C2 on the 5-cycle runs.
    runs("friction_8_seeds", 8, 4, 5);
    r = shell(report);
    ASSERT_EQ(r.status, 0) << r.output;
    page = slurp(d / "paper_comparison.md");
    c18 = row(page, "C18");
    EXPECT_NE(c18.find("W_settled -192 +- 8 (-13%) J/m2, dissipated energy (cycle 8)"), std::string::npos) << c18;
    EXPECT_NE(c18.find("| not reproduced: mu 1.0 against 0.6 -196 +- 10 (-13%) (-14% to -12%) [seeds 4-5 added after a "
                       "look, all 5 seeds: not reproduced: mu 1.0 against 0.6 -192 +- 8 (-13%) (-13% to -12%)] |"),
              std::string::npos) << c18;
    EXPECT_NE(row(page, "C17").find("-0.35 +- 0.02 (3 seeds) (8 cycles"), std::string::npos) << row(page, "C17");
    EXPECT_NE(page.find("21 of 21 finished 5-cycle runs are stationary"), std::string::npos) << page;
    EXPECT_NE(page.find("got seeds 4 and 5 (over three seeds not resolved), all 8 cycles from their seeds' samples by "
                        "the same build, 4 of 4 runs"),
              std::string::npos) << page;
    EXPECT_NE(page.find("by a later build (friction_8-build;"), std::string::npos) << page;
    fs::remove_all(d);
}

// C30 (how friction and the local damping share the dissipation) and C19 on hand-made records of
// the damping study (lambda 0.1 / 0.4) beside the friction study's lambda 0.2, at mu 0 / 0.6 / 1,
// 3 seeds, 5 flat cycles. W = base(mu) + 10 s + offset(lambda, mu, s): mu 0's offsets 30, -30, 0
// (lambda 0.1: W 540, 490, 530, 520 +- 4.303 * 26.5 / sqrt(3) = 65.7) and 20, -20, 0 (lambda 0.4)
// leave 0 +- 4.303 * 30 / sqrt(3) = 74.5 (and 49.7): not resolved; at mu 0.6 lambda 0.4 is
// -200 - 10 s lower (W 1400 in every seed; -220 +- 24.8: resolved). Friction
// shares (friction / (friction + damping) in the last cycle): 0.95 / 0.9 / 0.8 at mu 0.6 and
// 0.75 / 0.7 / 0.6 at mu 1 for lambda 0.1 / 0.2 / 0.4. Open while a run is missing; the mu-0
// sentence goes when its difference is resolved.
TEST(Tools, PaperReportSharesTheDissipationByTheLocalDamping) {
    const fs::path d = scratch_path("tools", "paper_report_damping");
    fs::remove_all(d);
    const fs::path data = d / "data";
    const std::map<std::string, double> base = {{"0", 500}, {"0.6", 1600}, {"1", 1650}};
    const std::map<std::string, std::map<std::string, double>> share = {
        {"0", {{"0.1", 0}, {"0.2", 0}, {"0.4", 0}}},
        {"0.6", {{"0.1", 0.95}, {"0.2", 0.9}, {"0.4", 0.8}}},
        {"1", {{"0.1", 0.75}, {"0.2", 0.7}, {"0.4", 0.6}}}};
    auto run = [&](const std::string& lam, const std::string& mu, int s, double mu0_lam01) {
        const bool ref = lam == "0.2";
        const fs::path c = data / (ref ? "friction" : "damping") /
                           ((ref ? std::string() : "simulation.local-damping=" + lam + "_") + "grains.friction=" + mu +
                            "_simulation.seed=" + std::to_string(s));
        const double pm = (s == 1) - (s == 2);  // +1, -1, 0 over the seeds
        double W = base.at(mu) + 10 * s;
        if (mu == "0") W += lam == "0.1" ? mu0_lam01 * pm : lam == "0.4" ? 20 * pm : 0;
        if (mu == "0.6" && lam == "0.4") W -= 200 + 10 * s;
        const double f = share.at(mu).at(lam);
        fs::create_directories(c);
        std::string csv = "cycle,dissipated_energy,W,peak_force,min_force,friction_dissipation,damping_dissipation,"
                          "viscous_dissipation,settled\n";
        for (int k = 1; k <= 5; ++k)
            csv += std::to_string(k) + ",1," + std::to_string(W) + ",100,0," + std::to_string(f) + "," +
                   std::to_string(1 - f) + ",0,0\n";
        write_file(c / "cycles.csv", csv);
        write_file(c / "summary.json", "{\"run_seconds\": 1, \"grains\": 1090}\n");
    };
    auto all = [&](double mu0_lam01) {
        for (const char* lam : {"0.1", "0.2", "0.4"})
            for (const char* mu : {"0", "0.6", "1"})
                for (int s = 1; s <= 3; ++s) run(lam, mu, s, mu0_lam01);
    };
    auto rows = [&]() {
        const Outcome r = shell("VPPDEM=" + kBinary + " DATA=" + data.string() + " DOCS=" + d.string() + " bash " +
                                (kSource / "scripts/paper_report.sh").string());
        EXPECT_EQ(r.status, 0) << r.output;
        const std::string page = slurp(d / "paper_comparison.md");
        auto row = [&](const std::string& id) {
            const std::size_t at = page.find("| " + id + " |");
            return at == std::string::npos ? std::string() : page.substr(at, page.find('\n', at) - at);
        };
        return std::make_pair(row("C19"), row("C30"));
    };
    all(30);
    fs::remove_all(data / "damping" / "simulation.local-damping=0.4_grains.friction=1_simulation.seed=3");
    auto [c19, c30] = rows();
    EXPECT_NE(c30.find("| open (runs pending) |"), std::string::npos) << c30;
    EXPECT_NE(c30.find("W_settled [J/m2] and the friction share of the dissipation (energy ledger, cycle 5): mu 0: W 520 +- 66 / "
                       "520 +- 25 / 520 +- 43"), std::string::npos) << c30;
    all(30);
    std::tie(c19, c30) = rows();
    EXPECT_NE(c30.find("mu 0.6: W 1620 +- 25 / 1620 +- 25 / 1400 +- 0, friction share 0.95 +- 0.00 / "
                       "0.90 +- 0.00 / 0.80 +- 0.00, W against lambda 0.2: lambda 0.1 +0 +- 23 (+0%) (Welch), lambda "
                       "0.4 -220 +- 25 (-14%) (Welch)"),
              std::string::npos) << c30;
    // Not resolved at mu 0, but Welch's intervals (lambda 0.1: 57 / 520 = 11%; 0.4: 35 / 520 = 7%) reach
    // past 10%: nothing shown either way.
    const std::string answered =
        "| - (an open question; answered in the model: with friction (mu 0.6-1.0) friction takes 0.60-0.95 of the dissipation for lambda "
        "0.1-0.4, the local damping the rest; W moves beyond the seed scatter at mu 0.6, lambda 0.4, not at the other 5; ";
    EXPECT_NE(c30.find(answered + "at mu 0 (the damping takes all of it) W is not resolved from lambda 0.2's, lambda 0.1 "
                                  "-11% to +11%, lambda 0.4 -7% to +7%: whether it follows the coefficient is not shown); "
                                  "the paper's own answer is C33 |"),
              std::string::npos) << c30;
    EXPECT_NE(c19.find("and W at mu 0 is not resolved from lambda 0.2's at lambda 0.1 or 0.4 (C30) |"), std::string::npos)
        << c19;
    // mu 0, lambda 0.1's offsets 3, -3, 0: Welch 0 +- 22, and lambda 0.4's 0 +- 35, both within 10% of 520.
    all(3);
    std::tie(c19, c30) = rows();
    EXPECT_NE(c30.find(answered + "at mu 0 the damping takes all of it, yet W stays within 10% of lambda 0.2's when "
                                  "lambda is halved or doubled"),
              std::string::npos) << c30;
    // mu 0, lambda 0.1 moved: 412, 424, 436 against 510, 520, 530 (-96 +- 5, resolved).
    for (int s = 1; s <= 3; ++s) {
        const fs::path c = data / "damping" / ("simulation.local-damping=0.1_grains.friction=0_simulation.seed=" +
                                               std::to_string(s));
        std::string csv = "cycle,dissipated_energy,W,peak_force,min_force,friction_dissipation,damping_dissipation,"
                          "viscous_dissipation,settled\n";
        for (int k = 1; k <= 5; ++k) csv += std::to_string(k) + ",1," + std::to_string(400 + 12 * s) + ",100,0,0,1,0,0\n";
        write_file(c / "cycles.csv", csv);
    }
    std::tie(c19, c30) = rows();
    EXPECT_NE(c30.find("W moves beyond the seed scatter at mu 0, lambda 0.1, mu 0.6, lambda 0.4, not at the other 4); "),
              std::string::npos) << c30;
    EXPECT_NE(c19.find("changes with the damping coefficient (C30) |"), std::string::npos) << c19;
    fs::remove_all(d);
}
