// A damper filled with clumps (grains.shape, docs/damper.md "Grain shapes"): the fill places
// rigid dimers in random orientations, the preparation and the cycling run with them, the
// ledger closes, the bits do not depend on the thread count; bad combinations of the keys are
// refused naming them. The clumps' mechanics against closed forms: tests/physics/test_clumps.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"

using namespace cli_test;
namespace fs = std::filesystem;

namespace {

// The points of a legacy VTK frame.
std::vector<std::array<double, 3>> vtk_points(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::vector<std::array<double, 3>> pts;
    while (std::getline(in, line))
        if (line.rfind("POINTS ", 0) == 0) {
            const std::size_t n = std::stoul(line.substr(7));
            for (std::size_t k = 0; k < n; ++k) {
                std::array<double, 3> x;
                in >> x[0] >> x[1] >> x[2];
                pts.push_back(x);
            }
            break;
        }
    return pts;
}

}  // namespace

// The small damper of the tests with dimers of the spheres' volume: the pour has the spheres'
// grain count (the same grain volume), every grain is a clump of two members after the 494 foil
// particles, the axes at the pour point every way (uniform directions: E|cos| = 1/2 per axis,
// sd 0.29; 56 grains, checked within 4 standard errors), and one cycle runs with the ledger's
// residual below 0.1% of the work (measured 0.02%).
TEST(GrainShapes, ADimerDamperFillsInRandomOrientationsAndCycles) {
    const fs::path d = scratch_path("grain_shapes", "dimer");
    fs::remove_all(d);
    const Outcome r = run("damper --out " + d.string() + " " + kSmallDamper +
                          " --set grains.shape=dimer --set process.cycles=1");
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string js = slurp(d / "summary.json");
    const double poured = std::round(0.45 * 0.012 * 0.012 * 0.03 / (4.0 / 3.0 * 2.965e-3 * 2.965e-3 * 2.965e-3));
    EXPECT_EQ(json_number(js, "grains_poured", "preparation"), poured) << js;
    const double packing = json_number(js, "packing_fraction", "preparation");
    EXPECT_GT(packing, 0.4);
    EXPECT_LT(packing, 0.74);
    // The pour's frame: the foil, then two members per grain.
    const auto pts = vtk_points(d / "vtk" / "damper_0000_fill.vtk");
    ASSERT_EQ(pts.size(), 494u + 2u * std::size_t(poured));
    double ax[3] = {0, 0, 0};
    for (std::size_t k = 0; k < std::size_t(poured); ++k) {
        const auto& a = pts[494 + 2 * k];
        const auto& b = pts[494 + 2 * k + 1];
        const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2], n = std::sqrt(dx * dx + dy * dy + dz * dz);
        ax[0] += std::abs(dx) / n / poured;
        ax[1] += std::abs(dy) / n / poured;
        ax[2] += std::abs(dz) / n / poured;
    }
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ax[k], 0.5, 4.0 * 0.2887 / std::sqrt(poured)) << "axis " << k;
    const auto c = read_columns(d / "cycles.csv");
    ASSERT_EQ(c.at("W").size(), 1u);
    EXPECT_GT(c.at("W")[0], 0.0);
    EXPECT_LT(std::abs(c.at("energy_residual")[0]), 1e-3 * c.at("boundary_work")[0]);

    // Two threads: the same bits.
    const fs::path d2 = scratch_path("grain_shapes", "dimer2");
    fs::remove_all(d2);
    const Outcome r2 = run("damper --out " + d2.string() + " " + kSmallDamper +
                           " --set grains.shape=dimer --set process.cycles=1 --set simulation.threads=2");
    ASSERT_EQ(r2.status, 0) << r2.output;
    EXPECT_EQ(slurp(d / "forces.csv"), slurp(d2 / "forces.csv"));
    EXPECT_EQ(slurp(d / "cycles.csv"), slurp(d2 / "cycles.csv"));
    fs::remove_all(d.parent_path());
}

TEST(GrainShapes, BadCombinationsAreRefusedNamingTheKey) {
    const fs::path d = scratch_path("grain_shapes", "bad");
    const auto refused = [](const std::string& sets, const std::string& what) {
        const Outcome r = run("damper --out /nonexistent_vppdem_dir " + sets + " --quiet --no-plot");
        EXPECT_NE(r.status, 0) << sets;
        EXPECT_NE(r.output.find(what), std::string::npos) << sets << "\n" << r.output;
    };
    refused("--set grains.shape=cube", "grains.shape");
    refused("--set grains.shape=template", "grains.clump_template");
    write_file(d / "pair.csv", "x,y,z,r\n0,0,0,0.001\n0.001,0,0,0.0008\n");
    refused("--set grains.clump_template=" + (d / "pair.csv").string(), "must be \"template\" when grains.clump_template");
    write_file(d / "apart.csv", "x,y,z,r\n0,0,0,0.001\n0.01,0,0,0.001\n");
    refused("--set grains.shape=template --set grains.clump_template=" + (d / "apart.csv").string(), "do not all touch");
    refused("--set grains.shape=template --set grains.clump_template=/nonexistent.csv", "grains.clump_template");
    fs::remove_all(d.parent_path());
}
