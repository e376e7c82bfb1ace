// Ensemble statistics (src/vpp/analysis/stats.h) and stationary loops (src/vpp/analysis/settle.h) against values
// computed by hand or by an independent implementation (SciPy's stats.t.ppf, quoted below), and
// the analysis.settle_tolerance key's range check.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/config.h"
#include "vpp/analysis/analysis.h"
#include "vpp/analysis/records.h"
#include "vpp/settings/config.h"
#include "vpp/analysis/settle.h"
#include "vpp/analysis/stats.h"

using namespace vpp;

TEST(EnsembleStats, StudentQuantilesMatchTheTables) {
    // Closed forms (dof 1: tan(pi (p - 1/2)); dof 2: (2p - 1) / sqrt(2 p (1 - p)); dof 4:
    // 2 sqrt(cos(acos(sqrt(q)) / 3) / sqrt(q) - 1), q = 4 p (1 - p)) to round-off.
    const double p = 0.975, q = 4 * p * (1 - p);
    EXPECT_NEAR(student_t_quantile(p, 1), std::tan(M_PI * (p - 0.5)), 1e-13);
    EXPECT_NEAR(student_t_quantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-13);
    EXPECT_NEAR(student_t_quantile(p, 4), 2 * std::sqrt(std::cos(std::acos(std::sqrt(q)) / 3) / std::sqrt(q) - 1), 1e-13);
    // scipy.stats.t.ppf(0.975, dof) (itself accurate to about 1e-10 only: its 12.706204736432095
    // for dof 1 is 2.6e-10 above tan(0.475 pi)).
    const std::vector<std::pair<double, double>> t975 = {
        {1, 12.706204736432095}, {2, 4.302652729911275},   {3, 3.182446305284263},   {4, 2.7764451051977987},
        {9, 2.2621571627409915}, {29, 2.045229642132703},  {1000, 1.9623390808264074}};
    for (const auto& [dof, t] : t975) EXPECT_NEAR(student_t_quantile(0.975, dof), t, 1e-9 * t) << dof;
    EXPECT_NEAR(student_t_quantile(0.9, 5), 1.4758840487820273, 1e-9);
    EXPECT_NEAR(student_t_quantile(0.995, 7), 3.4994832973505026, 1e-9);
    EXPECT_NEAR(student_t_quantile(0.025, 3), -3.1824463052842638, 1e-9);  // symmetric
    EXPECT_EQ(student_t_quantile(0.5, 4), 0.0);
    // dof = 1 is Cauchy: t = tan(pi (p - 1/2)).
    EXPECT_NEAR(student_t_quantile(0.8, 1), std::tan(M_PI * 0.3), 1e-9);
    EXPECT_THROW(student_t_quantile(1.0, 3), std::invalid_argument);
    EXPECT_THROW(student_t_quantile(0.975, 0.5), std::invalid_argument);
}

TEST(EnsembleStats, MeanAndIntervalByHand) {
    // 10, 12, 14: mean 12, s = sqrt((4 + 0 + 4) / 2) = 2, half width t_{0.975,2} 2 / sqrt(3),
    // t_{0.975,2} = 0.95 / sqrt(2 * 0.975 * 0.025) = 4.302652729749462.
    const Interval a = mean_interval({10, 12, 14});
    EXPECT_EQ(a.n, 3u);
    EXPECT_DOUBLE_EQ(a.mean, 12.0);
    EXPECT_DOUBLE_EQ(a.sd, 2.0);
    EXPECT_NEAR(a.half, 4.302652729749462 * 2.0 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(a.low(), 12.0 - 4.968275423500657, 1e-9);
    // NaN (a run without the quantity) is left out; one value has no spread.
    const Interval b = mean_interval({0.2, NAN, 0.35, 0.31, 0.28});
    EXPECT_EQ(b.n, 4u);
    EXPECT_NEAR(b.mean, 0.285, 1e-15);
    EXPECT_NEAR(b.sd, 0.06350852961085882, 1e-14);
    EXPECT_NEAR(b.half, 0.10105624270705692, 1e-9 * 0.101);  // t_{0.975,3} from the table
    const Interval one = mean_interval({5.0});
    EXPECT_EQ(one.n, 1u);
    EXPECT_EQ(one.mean, 5.0);
    EXPECT_TRUE(std::isnan(one.sd));
    EXPECT_TRUE(std::isnan(one.half));
    EXPECT_TRUE(std::isnan(mean_interval({}).mean));
    // Overlap: [12 +- 4.97] and [17.5 +- 1] meet; [20 +- 1] does not; single values by their mean.
    Interval c;
    c.n = 3, c.mean = 17.5, c.half = 1;
    EXPECT_TRUE(overlaps(a, c));
    c.mean = 20;
    EXPECT_FALSE(overlaps(a, c));
    EXPECT_TRUE(overlaps(a, one) == false);  // 5 lies below 12 - 4.97
    EXPECT_TRUE(overlaps(one, one));
}

namespace {
std::vector<CycleResult> cycles_of(const std::vector<double>& W) {
    std::vector<CycleResult> c;
    for (std::size_t k = 0; k < W.size(); ++k) {
        CycleResult r;
        r.cycle = int(k) + 1;
        r.W = W[k];
        c.push_back(r);
    }
    return c;
}
}  // namespace

TEST(StationaryLoops, TheMainJobsCyclesSettleAfterTheCompaction) {
    // The main job's damper for 8 cycles (docs/data/settle_cycles.csv, W rounded to J/m^2).
    const std::vector<double> W = {2608, 2164, 1649, 1502, 1565, 1598, 1503, 1522};
    Settling s = settle_cycles(cycles_of(W), 0.03);
    // Grown back from cycle 8, cycle 3 is the first to fail: |1649 - 1538| = 111 J/m^2 against
    // the level bound 1.96 * 0.03 * 1538 * sqrt(1 + 1/5) = 99.1 J/m^2.
    EXPECT_EQ(s.settled, (std::vector<bool>{false, false, false, true, true, true, true, true}));
    EXPECT_EQ(s.first, 4);
    EXPECT_EQ(s.count, 5u);
    EXPECT_DOUBLE_EQ(s.W_mean, 1538.0);
    // Slope over cycles 4-8 by hand: S_xx = 10, S_xy = -2*1502 - 1565 + 1503 + 2*1522 = -22.
    EXPECT_NEAR(s.slope, -2.2, 1e-9);
    EXPECT_NEAR(s.slope_limit, 1.959963984540054 * 0.03 * 1538.0 / std::sqrt(10.0), 1e-9);
    // The first 6 cycles (the main job's default): cycle 3 passes against the mean of 4-6
    // (|1649 - 1555| = 94 <= 1.96 * 0.03 * 1555 * sqrt(4/3) = 105.6) and the slope of 3-6 is
    // -9 J/m^2 per cycle (bound 41.5): stationary over cycles 3-6, mean 1578.5.
    s = settle_cycles(cycles_of({W.begin(), W.begin() + 6}), 0.03);
    EXPECT_EQ(s.first, 3);
    EXPECT_EQ(s.count, 4u);
    EXPECT_DOUBLE_EQ(s.W_mean, 1578.5);
    EXPECT_NEAR(s.slope, -9.0, 1e-9);
    // The first 5: cycle 3 fails against 4-5 (115.5 > 110.4): a tail of two is not stationary.
    s = settle_cycles(cycles_of({W.begin(), W.begin() + 5}), 0.03);
    EXPECT_EQ(s.count, 0u);
    EXPECT_EQ(s.first, 0);
    EXPECT_TRUE(std::isnan(s.W_mean));
    EXPECT_EQ(s.tail_first, 4);
    EXPECT_EQ(s.tail_last, 5);
    EXPECT_EQ(s.settled, std::vector<bool>(5, false));
}

TEST(StationaryLoops, ATrendBeyondTheScatterIsNotStationary) {
    // A steady decline of 5% of W_1 per cycle, no noise: the level test stops the tail at two
    // (the third-last lies 1.5 steps = 75 J/m^2 above the mean of the last two, bound 58).
    std::vector<double> decline;
    for (int k = 0; k < 6; ++k) decline.push_back(1000.0 - 50.0 * k);
    EXPECT_EQ(settle_cycles(cycles_of(decline), 0.03).count, 0u);
    // At a scatter of 10% the same decline hides in the noise of cycles 2-6, but not of all six:
    // the trend over 1-6 (S_xx = 17.5) is bounded by 1.96 * 0.1 * 875 / sqrt(17.5) = 41 < 50.
    EXPECT_EQ(settle_cycles(cycles_of(decline), 0.10).first, 2);
    // A jump in the middle of a flat run: the tail starts after it.
    Settling s = settle_cycles(cycles_of({100, 100, 100, 120, 120, 120, 120}), 0.03);
    EXPECT_EQ(s.first, 4);
    EXPECT_DOUBLE_EQ(s.W_mean, 120.0);
    EXPECT_EQ(s.slope, 0.0);
    // A constant W settles from cycle 1.
    EXPECT_EQ(settle_cycles(cycles_of({7, 7, 7}), 0.03).count, 3u);
}

// The criterion's error rates on synthetic runs of 5 cycles: W_k = 1000 (1 + 0.03 e_k) with
// e_k standard normal (the scatter the tolerance states), with and without a drift. The level
// and trend tests are each at 95%; up to three of them are applied per run, so a stationary run
// is called stationary about 85-90% of the time; a drift of 10% per cycle (2.4 times the
// smallest the 3-cycle trend resolves) almost never.
TEST(StationaryLoops, ErrorRatesOnSyntheticNoise) {
    std::mt19937_64 rng(12345);
    std::normal_distribution<double> e(0.0, 1.0);
    auto rate = [&](double drift) {
        int stationary = 0;
        const int runs = 4000;
        for (int r = 0; r < runs; ++r) {
            std::vector<double> W;
            for (int k = 0; k < 5; ++k) W.push_back(1000.0 * (1.0 + 0.03 * e(rng)) * (1.0 - drift * k));
            stationary += settle_cycles(cycles_of(W), 0.03).count >= 3;
        }
        return double(stationary) / runs;
    };
    const double flat = rate(0.0), drifting = rate(0.10);
    EXPECT_GT(flat, 0.80) << flat;
    EXPECT_LT(drifting, 0.05) << drifting;
}

TEST(StationaryLoops, TheTailEndsAtTheLastCompleteCycleAndNeedsConsecutiveNumbers) {
    auto c = cycles_of({100, 100, 100, 100, 55});
    c[4].complete = false;  // a cut-off last cycle is not a loop
    Settling s = settle_cycles(c, 0.03);
    EXPECT_EQ(s.settled, (std::vector<bool>{true, true, true, true, false}));
    EXPECT_EQ(s.tail_last, 4);
    auto gap = cycles_of({100, 100, 100, 100});
    gap[2].cycle = 4, gap[3].cycle = 5;  // cycles 1, 2, 4, 5: the tail is 4-5 only
    s = settle_cycles(gap, 0.03);
    EXPECT_EQ(s.count, 0u);
    EXPECT_EQ(s.tail_first, 4);
    EXPECT_EQ(settle_cycles({}, 0.03).tail_first, 0);
    EXPECT_THROW(settle_cycles(gap, 0.0), std::invalid_argument);
    EXPECT_THROW(settle_cycles(gap, 1.0), std::invalid_argument);
}

TEST(StationaryLoops, TheFlagGoesIntoCyclesCsv) {
    auto c = cycles_of({1275, 1066, 1076, 1088});
    mark_settled(c, 0.03);  // stationary over cycles 2-4
    const std::string path = ::testing::TempDir() + "settled_cycles.csv";
    write_cycles_csv(path, c);
    std::string text;
    {
        FILE* f = std::fopen(path.c_str(), "r");
        char buf[512];
        while (f && std::fgets(buf, sizeof buf, f)) text += buf;
        if (f) std::fclose(f);
    }
    EXPECT_EQ(text,
              "cycle,dissipated_energy,W,peak_force,min_force,settled\n1,0,1275,0,0,0\n2,0,1066,0,0,1\n"
              "3,0,1076,0,0,1\n4,0,1088,0,0,1\n");
    std::remove(path.c_str());
}

TEST(StationaryLoops, TheToleranceKeyIsRangeChecked) {
    EXPECT_EQ(load_config("", {}).analysis.settle_tolerance, 0.03);
    EXPECT_EQ(load_config("", {"analysis.settle_tolerance=0.05"}).analysis.settle_tolerance, 0.05);
    EXPECT_THROW(load_config("", {"analysis.settle_tolerance=\"x\""}), cfg::ConfigError);
    for (const char* bad : {"0", "1", "1.5", "-0.1"}) {
        try {
            load_config("", {std::string("analysis.settle_tolerance=") + bad});
            FAIL() << bad;
        } catch (const cfg::ConfigError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("analysis.settle_tolerance"), std::string::npos) << m;
            EXPECT_NE(m.find("(0, 1)"), std::string::npos) << m;
        }
    }
}
