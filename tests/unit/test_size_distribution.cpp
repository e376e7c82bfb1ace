// Grain size distributions (scene/size_distribution.h) against their closed forms: the drawn
// radii's mean, spread and volume moments for the uniform and the truncated lognormal law, the
// mass fractions of a sieve curve, the bounds of every kind, reproducible streams, and the
// refusals of a bad sieve file naming it. Tolerances: 5 standard errors of the sample statistic
// (N = 200,000 draws), so a correct law passes with certainty and a wrong moment fails.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/size_distribution.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_size_distribution {

using scene::SizeDistribution;
using K = SizeDistribution::Kind;
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kN = 200000;
constexpr double kV = 4.0 / 3.0 * std::numbers::pi;

struct Moments {
    double mean = 0, sd = 0, r3 = 0, r3_sd = 0, lnr_sd = 0, lo = 1e300, hi = 0;
};

Moments sample(const SizeDistribution& d, uint64_t seed = 7) {
    std::mt19937_64 rng(seed);
    std::vector<double> r(kN);
    for (double& x : r) x = d.draw(rng);
    Moments m;
    double s = 0, s2 = 0, c = 0, c2 = 0, l = 0, l2 = 0;
    for (double x : r) {
        s += x;
        s2 += x * x;
        c += x * x * x;
        c2 += x * x * x * x * x * x;
        l += std::log(x);
        l2 += std::log(x) * std::log(x);
        m.lo = std::min(m.lo, x);
        m.hi = std::max(m.hi, x);
    }
    const double n = double(kN);
    m.mean = s / n;
    m.sd = std::sqrt(s2 / n - m.mean * m.mean);
    m.r3 = c / n;
    m.r3_sd = std::sqrt(c2 / n - m.r3 * m.r3);
    m.lnr_sd = std::sqrt(l2 / n - (l / n) * (l / n));
    return m;
}

fs::path write_csv(const std::string& name, const std::string& text) {
    const fs::path p = fs::temp_directory_path() / ("vppdem_sizes_" + std::to_string(::getpid()) + "_" + name);
    std::ofstream(p) << text;
    return p;
}

std::string refusal(const std::string& text) {
    const fs::path p = write_csv("bad.csv", text);
    try {
        SizeDistribution::sieve_curve(p.string());
    } catch (const std::runtime_error& e) {
        fs::remove(p);
        return e.what();
    }
    fs::remove(p);
    return "";
}

}  // namespace

TEST(SizeDistribution, SingleIsTheRadiusAndDrawsNothing) {
    SizeDistribution d;
    d.radius = 2.965e-3;
    std::mt19937_64 a(1), b(1);
    EXPECT_EQ(d.draw(a), 2.965e-3);
    EXPECT_EQ(a(), b());  // the stream untouched
    EXPECT_EQ(d.mean_volume(), kV * 2.965e-3 * 2.965e-3 * 2.965e-3);
    EXPECT_EQ(d.min_radius(), d.max_radius());
}

TEST(SizeDistribution, UniformMatchesItsMoments) {
    SizeDistribution d;
    d.kind = K::Uniform;
    d.radius = 3e-3;
    d.spread = 0.2;
    const Moments m = sample(d);
    const double a = 2.4e-3, b = 3.6e-3;
    EXPECT_GE(m.lo, a);
    EXPECT_LE(m.hi, b);
    EXPECT_NEAR(m.mean, 3e-3, 5.0 * (b - a) / std::sqrt(12.0 * kN));
    EXPECT_NEAR(m.sd, (b - a) / std::sqrt(12.0), 0.01 * (b - a) / std::sqrt(12.0));
    const double r3 = (b * b * b * b - a * a * a * a) / (4.0 * (b - a));
    EXPECT_NEAR(d.mean_volume(), kV * r3, 1e-12 * kV * r3);
    EXPECT_NEAR(m.r3, r3, 5.0 * m.r3_sd / std::sqrt(double(kN)));
}

TEST(SizeDistribution, TruncatedLognormalHasTheMeanRadiusAndItsSpread) {
    SizeDistribution d;
    d.kind = K::Lognormal;
    d.radius = 3e-3;
    d.spread = 0.3;
    const Moments m = sample(d);
    // Cut at 3 sd of ln r: radii within exp(+-0.9) of the median.
    EXPECT_GE(m.lo, d.min_radius());
    EXPECT_LE(m.hi, d.max_radius());
    EXPECT_NEAR(d.max_radius() / d.min_radius(), std::exp(6.0 * 0.3), 1e-9);
    EXPECT_NEAR(m.mean, 3e-3, 5.0 * m.sd / std::sqrt(double(kN)));
    // sd of a normal cut at +-3 sd: s sqrt(1 - 2 * 3 phi(3) / (Phi(3) - Phi(-3))).
    const double phi3 = std::exp(-4.5) / std::sqrt(2.0 * std::numbers::pi);
    const double mass = std::erf(3.0 / std::numbers::sqrt2);
    const double sd = 0.3 * std::sqrt(1.0 - 6.0 * phi3 / mass);
    EXPECT_NEAR(m.lnr_sd, sd, 5.0 * sd / std::sqrt(2.0 * kN));
    EXPECT_NEAR(d.mean_volume() / kV, m.r3, 5.0 * m.r3_sd / std::sqrt(double(kN)));
}

TEST(SizeDistribution, SieveCurveDrawsTheCurvesMassFractions) {
    // Openings 2, 4, 6, 8 mm passing 0, 30, 80, 100 %.
    const fs::path p = write_csv("sieve.csv", "size,passing\n0.002,0\n0.004,30\n0.006,80\n0.008,100\n");
    const SizeDistribution d = SizeDistribution::sieve_curve(p.string());
    fs::remove(p);
    EXPECT_EQ(d.min_radius(), 1e-3);
    EXPECT_EQ(d.max_radius(), 4e-3);
    std::mt19937_64 rng(11);
    std::vector<double> r(kN);
    double total = 0, sum = 0;
    for (double& x : r) {
        x = d.draw(rng);
        total += x * x * x;
        sum += x;
    }
    for (const auto& [bound, passing] : std::vector<std::pair<double, double>>{{2e-3, 0.3}, {3e-3, 0.8}}) {
        double below = 0;
        for (double x : r)
            if (x < bound) below += x * x * x;
        EXPECT_NEAR(below / total, passing, 0.005) << "passing at radius " << bound;
    }
    EXPECT_NEAR(d.mean_volume() / kV, total / double(kN), 0.005 * total / double(kN));
    EXPECT_NEAR(d.mean_radius(), sum / double(kN), 0.005 * sum / double(kN));
    EXPECT_EQ(d.radius, d.mean_radius());
}

TEST(SizeDistribution, StreamsAreReproducible) {
    SizeDistribution d;
    d.kind = K::Lognormal;
    d.radius = 1e-3;
    d.spread = 0.2;
    std::mt19937_64 a(42), b(42);
    for (int k = 0; k < 1000; ++k) ASSERT_EQ(d.draw(a), d.draw(b));
    // The uniform law from the generator's top 53 bits, nothing else.
    SizeDistribution u;
    u.kind = K::Uniform;
    u.radius = 1.0;
    u.spread = 0.5;
    std::mt19937_64 g(3), h(3);
    EXPECT_EQ(u.draw(g), 1.0 + 0.5 * (2.0 * (double(h() >> 11) * 0x1p-53) - 1.0));
}

TEST(SizeDistribution, ABadSieveFileIsRefusedNamingIt) {
    EXPECT_NE(refusal("size,passing\n0.002,0\n").find("at least two sieves"), std::string::npos);
    EXPECT_NE(refusal("0.004,0\n0.002,1\n").find("row 2: sizes must ascend"), std::string::npos);
    EXPECT_NE(refusal("0.002,0.5\n0.004,0.2\n").find("row 2: passing must not decrease"), std::string::npos);
    EXPECT_NE(refusal("-0.002,0\n0.004,1\n").find("row 1: size -0.002 must be a sieve opening > 0 m"), std::string::npos);
    EXPECT_NE(refusal("0.002,0.5\n0.004,0.5\n").find("does not rise"), std::string::npos);
    EXPECT_NE(refusal("0.002,0\n0.004,x\n").find("vppdem_sizes_"), std::string::npos);  // the path
}

TEST(SizeDistribution, StatsOfTheDrawnRadii) {
    const scene::SizeStats s = scene::size_stats({1.0, 2.0});
    EXPECT_EQ(s.count, 2u);
    EXPECT_DOUBLE_EQ(s.mean, 1.5);
    EXPECT_DOUBLE_EQ(s.sd, std::sqrt(0.5));
    // Volumes 1 and 8: the first 10% of the volume is in the small grain, 50% and 90% reach the large.
    EXPECT_EQ(s.d10, 2.0);
    EXPECT_EQ(s.d50, 4.0);
    EXPECT_EQ(s.d90, 4.0);
}

// Issue 48: a sieve curve that does not span 0 to 100% was renormalised silently. The curve is
// still taken from its smallest sieve to its largest, and what was left out is said (the run
// repeats it as a warning); a curve from 0 to 100% has nothing to say.
TEST(SizeDistribution, ASieveCurveNotFromZeroToAHundredPercentSaysWhatItLeavesOut) {
    const fs::path p = write_csv("partial.csv", "size,passing\n0.002,10\n0.004,30\n0.006,80\n0.008,95\n");
    const SizeDistribution d = SizeDistribution::sieve_curve(p.string());
    EXPECT_NE(d.sieve_note.find("runs from 10% to 95% passing"), std::string::npos) << d.sieve_note;
    EXPECT_NE(d.sieve_note.find("the 10% below its smallest sieve and the 5% above its largest"), std::string::npos)
        << d.sieve_note;
    EXPECT_DOUBLE_EQ(d.sieve_passing.front(), 0.0);
    EXPECT_DOUBLE_EQ(d.sieve_passing.back(), 1.0);
    const fs::path full = write_csv("full.csv", "size,passing\n0.002,0\n0.004,30\n0.008,100\n");
    EXPECT_EQ(SizeDistribution::sieve_curve(full.string()).sieve_note, "");
}

}  // namespace test_size_distribution
