// A damper filled from a size distribution (grains.radius_distribution): the fill draws the
// radii, the grain count follows from the distribution's mean volume, summary.json reports what
// was drawn, and the run cycles; bad combinations of the keys are refused naming them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "cli_helpers.h"

using namespace cli_test;
namespace fs = std::filesystem;

TEST(GrainSizes, AUniformFillDrawsItsRadiiAndCycles) {
    const fs::path d = scratch_path("grain_sizes", "uniform");
    fs::remove_all(d);
    const double rk = 2.965e-3, s = 0.2;
    const Outcome r = run("damper --out " + d.string() + " " + kSmallDamper +
                          " --set grains.radius_distribution=uniform --set grains.radius_spread=0.2 --set process.cycles=1");
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string js = slurp(d / "summary.json");
    // The pour: round(phi V / mean volume), the uniform law's E[r^3] = r^3 (1 + s^2).
    const double v = 4.0 / 3.0 * std::numbers::pi * rk * rk * rk * (1.0 + s * s);
    const double poured = std::round(0.45 * std::numbers::pi * 0.012 * 0.012 * 0.03 / v);
    EXPECT_EQ(json_number(js, "grains_poured", "preparation"), poured) << js;
    const double n = json_number(js, "grains", "preparation");
    EXPECT_GE(n, poured);
    EXPECT_GE(json_number(js, "radius_min", "preparation"), rk * (1.0 - s));
    EXPECT_LE(json_number(js, "radius_max", "preparation"), rk * (1.0 + s));
    EXPECT_GT(json_number(js, "radius_max", "preparation") - json_number(js, "radius_min", "preparation"), rk * s);
    // About 60 grains: their mean within 5 standard errors (sd r s / sqrt 3) of r.
    EXPECT_NEAR(json_number(js, "radius_mean", "preparation"), rk, 5.0 * rk * s / std::sqrt(3.0 * n)) << js;
    EXPECT_NEAR(json_number(js, "radius_sd", "preparation"), rk * s / std::sqrt(3.0), 0.5 * rk * s / std::sqrt(3.0));
    EXPECT_GT(json_number(js, "d90", "preparation"), json_number(js, "d10", "preparation"));
    const auto c = read_columns(d / "cycles.csv");
    ASSERT_EQ(c.at("W").size(), 1u);
    EXPECT_GT(c.at("W")[0], 0.0);
    fs::remove_all(d.parent_path());
}

TEST(GrainSizes, BadCombinationsAreRefusedNamingTheKey) {
    const auto refused = [](const std::string& sets, const std::string& what) {
        const Outcome r = run("damper --out /nonexistent_vppdem_dir " + sets + " --quiet --no-plot");
        EXPECT_NE(r.status, 0) << sets;
        EXPECT_NE(r.output.find(what), std::string::npos) << sets << "\n" << r.output;
    };
    refused("--set grains.radius_distribution=gaussian", "grains.radius_distribution");
    refused("--set grains.radius_distribution=uniform", "grains.radius_spread");
    refused("--set grains.radius_distribution=lognormal --set grains.radius_spread=0.7", "at most 0.5");
    refused("--set grains.radius_distribution=sieve", "grains.sieve_curve");
    refused("--set grains.radius_distribution=sieve --set grains.sieve_curve=/nonexistent.csv", "grains.sieve_curve");
    refused("--set grains.radius_spread=1.5", "grains.radius_spread");
    // The largest grain the law can draw must fit, as grains.radius must.
    const fs::path d = scratch_path("grain_sizes", "big");
    write_file(d / "big.csv", "size,passing\n0.006,0\n0.009,100\n");
    const Outcome r = run("damper --out " + (d / "out").string() + " " + kSmallDamper +
                          " --set grains.radius_distribution=sieve --set grains.sieve_curve=" + (d / "big.csv").string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("'grains.radius_distribution' = \"sieve\": its largest grain (radius 0.0045 m) is too large"),
              std::string::npos) << r.output;
    fs::remove_all(d);
}
