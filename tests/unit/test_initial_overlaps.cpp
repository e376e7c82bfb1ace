// Initial overlaps of a scene (scene/initial_overlaps.h): the binned search against a brute-force
// one, the World's interaction rules (masks, fixed, prescribed, one-sided walls), and its cost
// on 100000 spheres.
#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "scene/initial_overlaps.h"
#include "dem/detect/geometry.h"
#include "dem/walls/facet_sets.h"

using dem::Vec3;

namespace {

dem::World random_spheres(std::size_t n, uint32_t seed) {
    dem::World w;
    w.add_material(dem::Material{});
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> x(0.0, 0.2), r(0.002, 0.006), u(0.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        dem::SphereDef d;
        d.position = {x(rng), x(rng), x(rng)};
        d.radius = r(rng);
        d.mask = u(rng) < 0.1 ? 2u : 1u | 2u;  // some spheres pass through the others' mask 1
        if (u(rng) < 0.05) d.flags |= dem::kFixed;
        w.add_sphere(d);
    }
    dem::SphereDef big;  // far larger than the cells: tested against everything
    big.position = {0.1, 0.1, 0.1};
    big.radius = 0.05;
    w.add_sphere(big);
    return w;
}

scene::OverlapReport brute_force(const dem::World& w, double tol) {
    scene::OverlapReport rep;
    const auto& p = w.particles;
    for (uint32_t i = 0; i < p.size(); ++i)
        for (uint32_t j = i + 1; j < p.size(); ++j) {
            if (!(p.mask[i] & p.mask[j]) || (p.inv_mass[i] == 0.0 && p.inv_mass[j] == 0.0)) continue;
            const double ov = p.radius[i] + p.radius[j] - norm(p.pos[j] - p.pos[i]);
            const double rmin = std::min(p.radius[i], p.radius[j]);
            if (ov <= tol * rmin) continue;
            ++rep.count;
            if (rep.count == 1 || ov / rmin > rep.worst.fraction) rep.worst = {i, j, false, ov, ov / rmin};
        }
    return rep;
}

}  // namespace

TEST(InitialOverlaps, BinnedSearchFindsWhatBruteForceFinds) {
    for (uint32_t seed : {1u, 2u, 3u}) {
        const dem::World w = random_spheres(1500, seed);
        for (double tol : {0.0, 0.01, 0.5}) {
            const auto a = scene::sphere_overlaps(w, tol), b = brute_force(w, tol);
            ASSERT_GT(b.count, 0u);
            EXPECT_EQ(a.count, b.count) << "seed " << seed << " tol " << tol;
            EXPECT_EQ(a.worst.a, b.worst.a);
            EXPECT_EQ(a.worst.b, b.worst.b);
            EXPECT_DOUBLE_EQ(a.worst.fraction, b.worst.fraction);
        }
    }
}

TEST(InitialOverlaps, BinnedFacetSearchFindsWhatBruteForceFinds) {
    // Random spheres in a cylinder of 72 segments through their box, and one large facet.
    dem::World w = random_spheres(1500, 4);
    for (dem::Facet f : dem::make_cylinder_facets({0.1, 0.1, -0.05}, 0.09, 0.3, 72, true)) w.add_facet(f);
    dem::Facet big;
    big.vertices = {Vec3{-5, -5, 0.1}, Vec3{5, -5, 0.1}, Vec3{0, 5, 0.1}};
    w.add_facet(big);
    std::size_t count = 0;
    for (uint32_t f = 0; f < w.facets.size(); ++f)
        for (uint32_t i = 0; i < w.particles.size(); ++i) {
            if (w.particles.flags[i] & dem::kFixed || !(w.facets[f].mask & w.particles.mask[i])) continue;
            dem::ContactGeom g;
            if (dem::sphere_facet(w.particles.pos[i], w.particles.radius[i], w.facets[f].vertices, false, g) &&
                g.overlap > 0.01 * w.particles.radius[i])
                ++count;
        }
    ASSERT_GT(count, 100u);
    EXPECT_EQ(scene::wall_overlaps(w, 0.01).count, count);
}

TEST(InitialOverlaps, FollowsTheWorldsInteractionRules) {
    dem::World w;
    w.add_material(dem::Material{});
    auto add = [&](Vec3 x, double r, uint32_t mask = 1, uint32_t flags = 0) {
        dem::SphereDef d;
        d.position = x;
        d.radius = r;
        d.mask = mask;
        d.flags = flags;
        return w.add_sphere(d);
    };
    add({0, 0, 1}, 0.01);
    add({0, 0, 1}, 0.01);                    // identical centres: 100% of the radius
    add({1, 0, 1}, 0.01, 2);
    add({1.005, 0, 1}, 0.01, 1);             // masks share no bit: no contact
    add({2, 0, 1}, 0.01, 1, dem::kFixed);
    add({2.005, 0, 1}, 0.01, 1, dem::kFixed);  // both fixed: no contact
    add({3, 0, 1}, 0.01);
    add({3.01995, 0, 1}, 0.01);              // 0.5%: within the default tolerance
    auto r = scene::sphere_overlaps(w, 0.01);
    EXPECT_EQ(r.count, 1u);
    EXPECT_EQ(r.worst.a, 0u);
    EXPECT_EQ(r.worst.b, 1u);
    EXPECT_NEAR(r.worst.fraction, 2.0, 1e-12);  // overlap 2 r of the radius r
    EXPECT_EQ(scene::sphere_overlaps(w, 0.004).count, 2u);

    // Walls: a floor z = 0 (two-sided), a one-sided wall x = 10 facing -x, a one-sided facet.
    dem::World v;
    v.add_material(dem::Material{});
    auto put = [&](Vec3 x, uint32_t flags = 0) {
        dem::SphereDef d;
        d.position = x;
        d.radius = 0.01;
        d.flags = flags;
        return v.add_sphere(d);
    };
    put({0, 0, 0.005});                 // 0: half in the floor
    put({0, 0, -0.005});                // 1: half in the floor from below (two-sided)
    put({5, 0, 0.5});                   // 2: clear of everything
    put({10.5, 0, 0.5});                // 3: behind the one-sided wall: pushed back, overlap r + 0.5
    put({0, 0, 0.002}, dem::kFixed);    // 4: fixed: no wall contacts
    put({5, 0, 1.005});                 // 5: on the facet's front side, 0.005 into it
    put({5, 0, 0.995});                 // 6: behind the one-sided facet: no contact
    dem::Plane floor;
    floor.normal = {0, 0, 1};
    v.add_plane(floor);
    dem::Plane side;
    side.point = {10, 0, 0};
    side.normal = {-1, 0, 0};
    side.one_sided = true;
    v.add_plane(side);
    dem::Facet f;
    f.vertices = {Vec3{4, -1, 1}, Vec3{6, -1, 1}, Vec3{5, 1, 1}};
    f.one_sided = true;
    v.add_facet(f);
    const auto wr = scene::wall_overlaps(v, 0.01);
    EXPECT_EQ(wr.count, 4u);  // spheres 0, 1 on the floor, 3 on the side, 5 on the facet
    EXPECT_EQ(wr.worst.a, 3u);
    EXPECT_EQ(wr.worst.b, 1u);
    EXPECT_NEAR(wr.worst.overlap, 0.51, 1e-12);
}

// A facet far outside the spheres' box (1e100 m away; fuzz/regressions/scene/
// wall_far_outside_the_spheres.toml, found by the fuzzer: its cell coordinate overflowed the
// integer conversion, undefined behaviour) touches nothing, and one whose box reaches far beyond
// the spheres' box on every side (its cells clamped to the box) is still tested against them.
TEST(InitialOverlaps, FacetsFarOutsideTheSpheresBoxAreHandled) {
    dem::World v;
    v.add_material(dem::Material{});
    dem::SphereDef d;
    d.radius = 0.01;
    d.position = {0, 0, 0.005};
    v.add_sphere(d);
    d.position = {1, 0, 0.5};
    v.add_sphere(d);
    dem::Facet far;
    far.vertices = {Vec3{1e100, 0, 0}, Vec3{2e100, 0, 0}, Vec3{1e100, 1e100, 0}};
    v.add_facet(far);
    EXPECT_EQ(scene::wall_overlaps(v, 0.01).count, 0u);
    dem::Facet wide;  // z = 0, 1 km across: under sphere 0, which sits 0.005 into it
    wide.vertices = {Vec3{-1e3, -1e3, 0}, Vec3{1e3, -1e3, 0}, Vec3{0, 1e3, 0}};
    v.add_facet(wide);
    const auto wr = scene::wall_overlaps(v, 0.01);
    EXPECT_EQ(wr.count, 1u);
    EXPECT_EQ(wr.worst.a, 0u);
    EXPECT_NEAR(wr.worst.overlap, 0.005, 1e-12);
}

TEST(InitialOverlaps, HundredThousandSpheresTakeWellUnderASecond) {
    // A cubic lattice of touching-but-clear spheres (gap 1% of the radius) plus one pair that
    // overlaps: 100000 spheres, so an O(N^2) search (5e9 pairs) would take minutes.
    dem::World w;
    w.add_material(dem::Material{});
    const double r = 0.001, pitch = 2.02 * r;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j)
            for (int k = 0; k < 10; ++k) {
                dem::SphereDef d;
                d.radius = r;
                d.position = {i * pitch, j * pitch, k * pitch};
                if (i == 50 && j == 50 && k == 5) d.position.x -= 0.5 * r;  // into its neighbour
                w.add_sphere(d);
            }
    const auto t0 = std::chrono::steady_clock::now();
    const auto rep = scene::sphere_overlaps(w, 0.01);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("100000 spheres: %.3f s\n", s);
    EXPECT_EQ(rep.count, 1u);
    EXPECT_LT(s, 5.0);  // about 0.1 s; generous for a busy machine
}
