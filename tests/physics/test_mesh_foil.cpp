// The damper's foil built by the membrane builder (foil.builder = "mesh", issue 47): the tube's
// pressure and volume against closed forms, its end rings held by base and cap, a small damper
// that runs, resumes bit for bit on another thread count, and bad values refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "dem/world/world.h"
#include "vpp/settings/config.h"
#include "vpp/damper/damper.h"
#include "vpp/membrane/foil.h"
#include "vpp/membrane/membrane.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_mesh_foil {

namespace fs = std::filesystem;

namespace {

using dem::Vec3;
constexpr double kPi = std::numbers::pi;

// The damper's mesh foil definition (DamperScene::membrane_def): the paper's foil, MatchFoil x
// 2.05, 25% vacancies seeded.
vpp::MembraneDef damper_membrane(uint64_t seed) {
    vpp::MembraneDef d;
    d.foil = vpp::Config().foil;
    d.stiffness_factor = 2.05;
    d.vacancies = true;
    d.seed = seed;
    return d;
}

Vec3 tri_area(const std::vector<Vec3>& p, const std::array<uint32_t, 3>& t) {
    return 0.5 * cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

// The tests' small damper (cli_helpers.h kSmallDamper) as a Config, with the mesh foil.
vpp::Config small_mesh_damper(int threads) {
    return vpp::load_config("", {"damper.radius=0.012", "damper.height=0.03", "grains.volume_fraction=0.45",
                                 "process.velocity=0.1", "process.amplitude=0.002", "process.cycles=2",
                                 "process.samples_per_cycle=80", "simulation.threads=" + std::to_string(threads),
                                 "foil.builder=mesh",
                                 // mass-scaled at the feature tests' step (cli_helpers.h, kSmallDamper)
                                 "simulation.dt_safety=0.45", "grains.density=268963.9", "foil.density=15177"});
}

}  // namespace

// The tube of the small damper (the lattice's ring radius and height for damper.radius 12 mm,
// damper.height 30 mm), with and without vacancies. The closed form: under a uniform dp the
// closed surface foil + caps takes no net force. The fans load the particles off the end rings;
// the rest of each rim triangle's area (a third per corner on a ring) is the rings', which the
// base and cap hold, and the caps close the rims with flat polygons: fans + ring remainder + caps
// must sum to zero at round-off. As the built-in's test (Foil.TributaryAreasSumToLateralArea...),
// the half x > 0 of the lateral surface projects onto 2 R H; each cap onto pi R^2.
TEST(MeshFoil, PressureOnFoilPlusCapsBalancesAndProjectsAsTheClosedFormSays) {
    const vpp::FoilDef f = vpp::Config().foil;
    dem::World wl;
    const vpp::FoilLattice L = vpp::build_cylinder(wl, f, 0.012, 0.03);
    const double R = L.radius, H = (L.rows - 1) * L.spacing, h = L.spacing;
    for (bool vac : {false, true}) {
        vpp::MembraneDef d = damper_membrane(3);
        d.vacancies = vac;
        dem::World w;
        vpp::Membrane m = vpp::membrane_tube_sites(d, R, H, 0.0);
        vpp::place_membrane(w, d, m);
        ASSERT_TRUE(m.open());
        ASSERT_EQ(m.boundary.size(), 2u);
        const auto& pos = w.particles.pos;
        // The rings: full loops on the rims (z = 0 and H, radius R within the 256-gon's sag).
        std::vector<uint8_t> on_ring(pos.size(), 0);
        for (int e = 0; e < 2; ++e)
            for (uint32_t i : m.boundary[e]) {
                on_ring[i] = 1;
                ASSERT_NEAR(pos[i].z, e == 0 ? 0.0 : H, 1e-12);
                ASSERT_NEAR(std::hypot(pos[i].x, pos[i].y), R, 1e-4 * R);
            }
        w.pressure.fans = vpp::membrane_pressure_fans(m);
        ASSERT_EQ(w.broken_invariant(), nullptr);
        ASSERT_EQ(w.pressure.fans.node.size(), m.particles.size() - m.boundary[0].size() - m.boundary[1].size());
        Vec3 fans, rings, caps;
        double abs_sum = 0, half = 0;
        for (std::size_t k = 0; k < w.pressure.fans.node.size(); ++k) {
            const Vec3 a = dem::fan_area(pos, w.pressure.fans, k);
            fans += a;
            abs_sum += norm(a);
            if (pos[w.pressure.fans.node[k]].x > 0) half += a.x;
        }
        double half_rings = 0;
        for (const auto& t : m.triangles) {
            int n = 0;
            for (uint32_t v : t) n += on_ring[v];
            rings += tri_area(pos, t) * (n / 3.0);
            for (uint32_t v : t)
                if (on_ring[v] && pos[v].x > 0) half_rings += tri_area(pos, t).x / 3.0;
        }
        double cap_area[2] = {0, 0};
        for (int e = 0; e < 2; ++e) {
            const auto& loop = m.boundary[e];
            Vec3 c;
            for (uint32_t i : loop) c += pos[i];
            c /= double(loop.size());
            Vec3 a;
            for (std::size_t k = 0; k < loop.size(); ++k) a += 0.5 * cross(pos[loop[(k + 1) % loop.size()]] - c, pos[loop[k]] - c);
            caps += a;
            cap_area[e] = a.z;
        }
        const Vec3 total = fans + rings + caps;
        // The loaded band's height: the x > 0 half of the fans over 2 R.
        const double loaded = half / (2 * R);
        std::printf("tube%s: %zu particles (%zu vacancies, rings %zu + %zu), %zu bonds; |fans + rings + caps| / "
                    "sum|A| = %.3g; |fans| / sum|A| = %.3g; caps %.6f and %.6f of -+pi R^2; lateral half "
                    "projection (fans + rings) %.6f of 2 R H; loaded height %.4f H (built-in %.4f H)\n",
                    vac ? " with vacancies" : "", m.particles.size(), m.vacancies, m.boundary[0].size(),
                    m.boundary[1].size(), m.bonds.size(), norm(total) / abs_sum, norm(fans) / abs_sum,
                    -cap_area[0] / (kPi * R * R), cap_area[1] / (kPi * R * R), (half + half_rings) / (2 * R * H),
                    loaded / H, (H - 2 * h) / H);
        EXPECT_LT(norm(total), 1e-13 * abs_sum);
        // The caps: inscribed polygons of the rim sites (~38 sides), pi R^2 within their
        // chord deficit (1 - sin(2 pi / n) n / (2 pi) = 0.5% at n = 38).
        EXPECT_NEAR(-cap_area[0] / (kPi * R * R), 1.0, 0.01);
        EXPECT_NEAR(cap_area[1] / (kPi * R * R), 1.0, 0.01);
        EXPECT_NEAR((half + half_rings) / (2 * R * H), 1.0, 0.01);
        // The rings keep about half of the rim triangles (a strip sqrt(3)/2 L high, corners on the
        // ring counting a third each, two kinds of triangle equally often): the loaded height is
        // H - sqrt(3)/2 L, to within a quarter of L; the lattice's is H - 2 h.
        EXPECT_NEAR(loaded, H - std::sqrt(3.0) / 2 * m.mean_edge, 0.25 * m.mean_edge);
        // The fans alone: their net is the rings' remainder and the caps' difference, small.
        EXPECT_LT(norm(fans), 0.01 * abs_sum);
    }
}

// The undeformed mesh foil's enclosed volume (lateral triangulation closed by the cap fans)
// against pi R^2 H: a polyhedron inscribed in the cylinder, short by its facets' sag. The
// built-in's ring polygon of n = 2 pi R / L sides holds sin(x) / x of the circle, x = L / R,
// 1 - (L/R)^2 / 6 (0.99545 here, which its test reproduces exactly); the triangulation's edges are
// 0.46-1.29 L long and run in every direction, and its deficit comes out 1.4-1.5 times that
// (seeds 1-2): between 1 and 2 times (L/R)^2 / 6 with L the mean edge.
TEST(MeshFoil, EnclosedVolumeOfTheUndeformedTubeIsPiR2H) {
    const vpp::FoilDef f = vpp::Config().foil;
    dem::World wl;
    const vpp::FoilLattice L = vpp::build_cylinder(wl, f, 0.012, 0.03);
    const double R = L.radius, H = (L.rows - 1) * L.spacing;
    const double exact = kPi * R * R * H;
    const double built_in = vpp::enclosed_volume(L, wl.particles.pos) / exact;
    const double x = L.spacing / R;
    EXPECT_NEAR(built_in, std::sin(x) / x, 1e-3 * x * x);
    for (uint64_t seed : {1, 2}) {
        const vpp::MembraneDef d = damper_membrane(seed);
        dem::World w;
        vpp::Membrane m = vpp::membrane_tube_sites(d, R, H, 0.0);
        vpp::place_membrane(w, d, m);
        const double v = vpp::enclosed_volume(m, w.particles.pos) / exact;
        const double sag = std::pow(m.mean_edge / R, 2) / 6.0;
        std::printf("seed %llu: mesh foil volume %.6f of pi R^2 H, deficit %.3f times (L/R)^2/6 = %.6f; built-in "
                    "%.6f (sin x / x %.6f)\n", (unsigned long long)seed, v, (1.0 - v) / sag, sag, built_in,
                    std::sin(x) / x);
        EXPECT_GT(1.0 - v, 1.0 * sag);
        EXPECT_LT(1.0 - v, 2.0 * sag);
    }
}

// A small damper with the mesh foil (the tests' small damper: 12 x 30 mm, 2 cycles of 2 mm at
// 0.1 m/s, one thread): its end rings held (bottom fixed where it was built, top moved with the
// cap), finite positive W in every cycle; and a checkpoint saved after its first cycle, resumed,
// records the samples of the uninterrupted run bit for bit (the pressure fans are not in the
// checkpoint: the resumed run rebuilds them from the foil, which the config rebuilds). The fans'
// thread independence is Membrane.FanPressureWorkBalancesTheLedgerAndIsThreadIndependent's.
TEST(MeshFoil, SmallDamperRunsHoldsItsRingsAndResumesBitwise) {
    const fs::path dir = cli_test::scratch_path("mesh_foil_test", "resume");
    fs::remove_all(dir);
    fs::create_directories(dir);
    vpp::DamperOptions opt;
    opt.quiet = true;
    vpp::Damper a(small_mesh_damper(1), opt);
    // The rings as built: foil particles on the base (z = 0) and at the top ring's height.
    const dem::World& w0 = a.world();
    std::vector<uint32_t> bottom, top;
    double z_top = 0;
    for (std::size_t i = 0; i < w0.particles.size(); ++i)
        if (w0.particles.flags[i] & vpp::kFoil) z_top = std::max(z_top, w0.particles.pos[i].z);
    for (std::size_t i = 0; i < w0.particles.size(); ++i) {
        if (!(w0.particles.flags[i] & vpp::kFoil)) continue;
        if (w0.particles.pos[i].z == 0.0) bottom.push_back(uint32_t(i));
        if (w0.particles.pos[i].z == z_top) top.push_back(uint32_t(i));
    }
    ASSERT_GT(bottom.size(), 20u);
    ASSERT_GT(top.size(), 20u);
    std::vector<Vec3> bottom0;
    for (uint32_t i : bottom) bottom0.push_back(w0.particles.pos[i]);
    a.cycle(1);
    const std::string ckpt = (dir / "one_cycle.ckpt").string();
    a.save(ckpt);  // with the fans on: saved without them
    ASSERT_FALSE(a.world().pressure.fans.empty());
    a.cycle(-1);
    const dem::World& w = a.world();
    for (std::size_t k = 0; k < bottom.size(); ++k) {
        EXPECT_EQ(w.particles.inv_mass[bottom[k]], 0.0);
        EXPECT_EQ(w.particles.pos[bottom[k]].x, bottom0[k].x);
        EXPECT_EQ(w.particles.pos[bottom[k]].z, 0.0);
    }
    // The top ring moves with the cap (one prescribed motion, the cap's history): all of it at
    // one height, back at the damper height at the end of the cycles (to the cap's travel within
    // the last step, 0.1 m/s x dt).
    const int32_t motion = w.particles.motion[top[0]];
    EXPECT_GE(motion, 0);
    for (uint32_t i : top) {
        EXPECT_EQ(w.particles.inv_mass[i], 0.0);
        EXPECT_EQ(w.particles.motion[i], motion);
        EXPECT_EQ(w.particles.pos[i].z, w.particles.pos[top[0]].z);
    }
    EXPECT_NEAR(w.particles.pos[top[0]].z, z_top, 0.1 * 10 * w.params.dt);
    const vpp::DamperResult r = a.result();
    ASSERT_EQ(r.cycles.size(), 2u);
    for (const auto& c : r.cycles) {
        std::printf("mesh foil, small damper: cycle %d W = %.5g J/m^2\n", c.cycle, c.W);
        EXPECT_TRUE(std::isfinite(c.W));
        EXPECT_GT(c.W, 0.0);
    }
    EXPECT_GT(r.foil_vacancies, 0u);
    EXPECT_EQ(r.foil_columns, 0);

    // Resumed from the checkpoint of the first cycle: the same samples, bit for bit.
    vpp::DamperOptions from = opt;
    from.from = ckpt;
    vpp::Damper c(small_mesh_damper(1), from);
    ASSERT_FALSE(c.world().pressure.fans.empty());
    c.cycle(-1);
    const auto& sa = a.samples();
    const auto& sc = c.samples();
    ASSERT_EQ(sa.size(), sc.size());
    for (std::size_t k = 0; k < sa.size(); ++k) {
        ASSERT_EQ(sa[k].time, sc[k].time) << k;
        ASSERT_EQ(sa[k].displacement, sc[k].displacement) << k;
        ASSERT_EQ(sa[k].grains, sc[k].grains) << k;
        ASSERT_EQ(sa[k].foil, sc[k].foil) << k;
    }
    fs::remove_all(dir);
}

// Bad values: a builder that is none, the mesh foil for the lattice's own checks (tension,
// envelope), a lattice sample cycled as a mesh foil: exit 2, naming the key, the value and what
// is allowed; nothing runs.
TEST(MeshFoil, BadBuilderValuesAreRefusedNamingTheKey) {
    using cli_test::run;
    const fs::path dir = cli_test::scratch_path("mesh_foil_test", "bad");
    fs::remove_all(dir);
    const auto none = run("damper --out " + (dir / "none").string() + " --set foil.builder=net --quiet");
    EXPECT_EQ(WEXITSTATUS(none.status), 2) << none.output;
    EXPECT_NE(none.output.find("foil.builder"), std::string::npos) << none.output;
    EXPECT_NE(none.output.find("net"), std::string::npos) << none.output;
    EXPECT_NE(none.output.find("\"lattice\" or \"mesh\""), std::string::npos) << none.output;
    EXPECT_FALSE(fs::exists(dir / "none" / "run.ckpt"));
    for (const char* cmd : {"envelope", "tension"}) {
        const auto r = run(std::string(cmd) + " --out " + (dir / cmd).string() + " --set foil.builder=mesh");
        EXPECT_EQ(WEXITSTATUS(r.status), 2) << cmd << ": " << r.output;
        EXPECT_NE(r.output.find("foil.builder"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("tension and envelope"), std::string::npos) << r.output;
    }
    fs::remove_all(dir);
}

}  // namespace test_mesh_foil
