// Studies without running them (src/vpp/study/study.h): ensembles of seeds in the grid, which cases
// share a preparation, and the per-case table summary_cases.csv against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "scene/config.h"
#include "vpp/study/study.h"

using namespace vpp;

namespace {

std::string write_study(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + "vppdem_ensembles_" + name + ".toml";
    std::ofstream(path) << text;
    return path;
}

// Number of distinct preparations of a study.
int preparations(const std::vector<StudyCase>& cases) {
    int n = 0;
    for (const StudyCase& c : cases) n = std::max(n, c.group + 1);
    return n;
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
    if (!line.empty() && line.back() == ',') out.push_back("");
    return out;
}

}  // namespace

TEST(StudyEnsembles, SeedsAddTheLastGridKeyWithOnePreparationPerSeed) {
    const Study s = load_study(write_study("seeds", "seeds = 3\n[grid]\n\"grains.friction\" = [0.3, 0.6]\n"));
    ASSERT_EQ(s.grid.size(), 2u);
    EXPECT_EQ(s.grid[1].key, "simulation.seed");
    EXPECT_EQ(s.grid[1].labels, (std::vector<std::string>{"1", "2", "3"}));
    EXPECT_EQ(seed_axis(s), 1);
    const auto cases = expand_study(s);
    ASSERT_EQ(cases.size(), 6u);
    EXPECT_EQ(preparations(cases), 3);  // each seed its own packing; friction shares it
    EXPECT_EQ(cases[0].name, "grains.friction=0.3_simulation.seed=1");
    EXPECT_EQ(cases[3].preparer, 0u);  // friction 0.6, seed 1 branches from friction 0.3, seed 1
    EXPECT_EQ(cases[5].preparer, 2u);
    EXPECT_EQ(cases[4].config.simulation.seed, 2u);
    // The ensemble rows: the two frictions, three runs each.
    const auto groups = ensemble_groups(s, cases);
    ASSERT_EQ(groups.size(), 2u);
    EXPECT_EQ(groups[1], (std::vector<std::size_t>{3, 4, 5}));
    // --seeds replaces the count, and a [grid] list of seeds.
    EXPECT_EQ(load_study(s.path, {}, 5).grid[1].labels.size(), 5u);
    const Study listed = load_study(write_study("list", "[grid]\n\"simulation.seed\" = [4, 9]\n\"process.velocity\" = [0.1, 0.05]\n"));
    EXPECT_EQ(seed_axis(listed), 0);  // a list is an ensemble too, wherever it stands
    EXPECT_EQ(preparations(expand_study(listed)), 2);
    const Study replaced = load_study(listed.path, {}, 2);
    EXPECT_EQ(seed_axis(replaced), 1);
    EXPECT_EQ(replaced.grid[1].labels, (std::vector<std::string>{"1", "2"}));
}

TEST(StudyEnsembles, BadSeedCountsAreRefusedNamingTheKey) {
    for (const std::string& text :
         {std::string("seeds = 0\n"), std::string("seeds = 2.5\n"), std::string("seeds = \"3\"\n"),
          std::string("seeds = 2\n[grid]\n\"simulation.seed\" = [1, 2]\n"),
          std::string("seeds = 2\n[set]\n\"simulation.seed\" = 4\n"), std::string("[set]\nseeds = 2\n")}) {
        try {
            load_study(write_study("bad", text));
            FAIL() << text;
        } catch (const cfg::ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("seeds"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(load_study(write_study("ok", "[grid]\n\"grains.friction\" = [0.3]\n"), {}, -1), cfg::ConfigError);
}

TEST(StudyEnsembles, OnlyKeysThatDoNotActBeforeThePreparationShareIt) {
    // Acting during the fill or the cap's compression: a preparation per value.
    for (const char* key : {"grains.young", "grains.stiffness_ratio", "foil.young", "foil.thickness", "foil.friction",
                            "foil.stiffness_ratio", "simulation.local_damping", "simulation.dt_safety",
                            "grains.volume_fraction", "damper.refill"}) {
        std::string values = "[0.3, 0.4]";
        if (std::string(key) == "grains.young" || std::string(key) == "foil.young") values = "[23e6, 2.3e9]";
        if (std::string(key) == "foil.thickness") values = "[0.1e-3, 0.15e-3]";
        if (std::string(key) == "damper.refill") values = "[true, false]";
        const Study s = load_study(write_study("acts", std::string("[grid]\n\"") + key + "\" = " + values + "\n"));
        EXPECT_EQ(preparations(expand_study(s)), 2) << key;
    }
    // Acting after prepared.ckpt only: one preparation.
    for (const char* key : {"grains.friction", "damper.cap_friction", "process.velocity", "process.underpressure",
                            "process.cycles", "output.energy", "analysis.settle_tolerance", "simulation.threads"}) {
        std::string values = "[0.3, 0.4]";
        if (std::string(key) == "process.velocity") values = "[0.1, 0.05]";
        if (std::string(key) == "process.underpressure") values = "[0.02e6, 0.06e6]";
        if (std::string(key) == "process.cycles" || std::string(key) == "simulation.threads") values = "[1, 2]";
        if (std::string(key) == "output.energy") values = "[true, false]";
        const Study s = load_study(write_study("shares", std::string("[grid]\n\"") + key + "\" = " + values + "\n"));
        EXPECT_EQ(preparations(expand_study(s)), 1) << key;
    }
}

TEST(StudyEnsembles, CasesTableHoldsTheMeanAndTheStudentInterval) {
    const Study s = load_study(write_study("table", "seeds = 3\n[grid]\n\"grains.friction\" = [0.3, 0.6]\n"));
    const auto cases = expand_study(s);
    std::vector<CaseOutcome> out(cases.size());
    const double W[6] = {10, 12, 14, 20, 21, 0};
    for (std::size_t i = 0; i < 6; ++i) {
        out[i].ok = i != 5;  // the third seed of friction 0.6 failed
        out[i].W = W[i];
        out[i].peak_force = 100 + double(i);
        out[i].W_settled = i == 1 ? NAN : W[i];  // seed 2 of friction 0.3 never settled
        out[i].friction_share = 0.5;
    }
    out[5].message = "boom";
    const std::string csv = cases_csv(s, cases, out);
    std::istringstream in(csv);
    std::string header, row1, row2;
    std::getline(in, header);
    std::getline(in, row1);
    std::getline(in, row2);
    const auto h = split(header), a = split(row1), b = split(row2);
    ASSERT_EQ(h.size(), a.size()) << csv;
    auto at = [&](const std::vector<std::string>& r, const std::string& col) {
        for (std::size_t k = 0; k < h.size(); ++k)
            if (h[k] == col) return r[k];
        ADD_FAILURE() << "no column " << col;
        return std::string();
    };
    EXPECT_EQ(h[0], "grains.friction");
    EXPECT_EQ(h[1], "seeds");
    EXPECT_EQ(h.back(), "cases");
    EXPECT_EQ(at(a, "grains.friction"), "0.3");
    EXPECT_EQ(at(a, "seeds"), "3");
    EXPECT_EQ(at(a, "ok"), "3");
    // 10, 12, 14: mean 12, sd 2, half width t_{0.975,2} * 2 / sqrt(3), t_{0.975,2} = 0.95 /
    // sqrt(2 * 0.975 * 0.025); t_{0.975,1} = tan(0.475 pi) below.
    EXPECT_EQ(at(a, "W_n"), "3");
    EXPECT_EQ(std::stod(at(a, "W_mean")), 12.0);
    EXPECT_EQ(std::stod(at(a, "W_sd")), 2.0);
    const double t2 = 0.95 / std::sqrt(2 * 0.975 * 0.025), t1 = std::tan(0.475 * M_PI);
    EXPECT_NEAR(std::stod(at(a, "W_ci95")), t2 * 2.0 / std::sqrt(3.0), 1e-12);
    // W_settled over the seeds that settled: 10 and 14, mean 12, sd 2.828..., t_{0.975,1} = 12.706.
    EXPECT_EQ(at(a, "W_settled_n"), "2");
    EXPECT_NEAR(std::stod(at(a, "W_settled_ci95")), t1 * std::sqrt(8.0) / std::sqrt(2.0), 1e-12);
    EXPECT_EQ(at(a, "friction_share_sd"), "0");
    EXPECT_EQ(at(a, "damping_share_n"), "0");  // no value: empty mean
    EXPECT_EQ(at(a, "damping_share_mean"), "");
    EXPECT_EQ(at(a, "cases"), "grains.friction=0.3_simulation.seed=1;grains.friction=0.3_simulation.seed=2;"
                              "grains.friction=0.3_simulation.seed=3");
    // The failed run is counted in seeds, not in ok nor in the statistics.
    EXPECT_EQ(at(b, "seeds"), "3");
    EXPECT_EQ(at(b, "ok"), "2");
    EXPECT_EQ(std::stod(at(b, "W_mean")), 20.5);
    EXPECT_NEAR(std::stod(at(b, "W_ci95")), t1 * std::sqrt(0.5) / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(std::stod(at(b, "peak_force_mean")), 103.5, 1e-12);

    // summary.csv keeps the contract columns first, then the new ones.
    const std::string sum = summary_csv(s, cases, out);
    EXPECT_EQ(sum.substr(0, sum.find('\n')),
              "grains.friction,simulation.seed,W,dissipated_energy,peak_force,run_seconds,status,case,"
              "W_settled,settled_cycles,first_settled_cycle,friction_share,damping_share,grains,packing_fraction,warnings");
}

// Issue 48: a key written twice in [set], quoted and as a dotted key, is one config key: the
// later silently won. Refused, naming the key.
TEST(StudyEnsembles, AKeyGivenTwiceInSetIsRefused) {
    try {
        load_study(write_study("twice", "[set]\n\"grains.friction\" = 0.3\ngrains.friction = 0.5\n"));
        FAIL() << "accepted";
    } catch (const cfg::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("[set] key 'grains.friction' is given twice"), std::string::npos) << e.what();
    }
}

// Issue 48: 0 and -0.0 made two cases of one run (labels "0" and "-0"). -0.0 is the value 0: in
// a list it repeats 0 (refused as any repeat), alone it is labelled 0.
TEST(StudyEnsembles, MinusZeroIsZero) {
    EXPECT_THROW(load_study(write_study("mz", "[grid]\n\"grains.friction\" = [0.0, -0.0]\n")), cfg::ConfigError);
    const Study s = load_study(write_study("mz1", "[grid]\n\"grains.friction\" = [-0.0, 0.5]\n"));
    EXPECT_EQ(s.grid[0].labels, (std::vector<std::string>{"0", "0.5"}));
    EXPECT_EQ(expand_study(s)[0].name, "grains.friction=0");
}
