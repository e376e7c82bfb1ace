// The broad phase (dem/detect/broad_phase.h) against its definition, checked pair by pair: a
// candidate is every pair (i < j) closer than the sum of its radii plus the skin, of shared mask,
// one of them moving; a wall candidate every (moving or prescribed particle, plane or facet of
// shared mask) closer than the radius plus the skin; each row ascending, each gap the surface gap
// rounded down to float. On packings
// that stress the cell grid: spheres on the cells' edges with their neighbours exactly at the
// reach (ties), two spheres at one point, fixed spheres (no pairs among them), a sphere thrown far
// off (the grid's cells grow), facets as large as the box; for 1, 2 and 3 threads (the same lists).
// The reference for issue 58's broad phase written once for World and the device (item 4).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "dem/bonds/bond_tables.h"
#include "dem/core/particles.h"
#include "dem/core/thread_team.h"
#include "dem/detect/broad_phase.h"
#include "dem/detect/geometry.h"
#include "dem/walls/wall.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_broad_phase {

using dem::Vec3;

namespace {

void add(dem::Particles& p, const Vec3& x, double r, bool fixed = false, uint32_t mask = 1) {
    p.pos.push_back(x);
    p.vel.emplace_back();
    p.angvel.emplace_back();
    p.force.emplace_back();
    p.torque.emplace_back();
    p.radius.push_back(r);
    p.mass.push_back(1e-3);
    p.inv_mass.push_back(fixed ? 0.0 : 1e3);
    p.inv_inertia.push_back(fixed ? 0.0 : 1e9);
    p.material.push_back(0);
    p.mask.push_back(mask);
    p.flags.push_back(fixed ? dem::kFixed : 0u);
    p.motion.push_back(-1);
    p.ref_pos.push_back(x);
}

// A gap [m] as float, rounded down (as the broad phase stores it).
float down(double g) {
    float f = float(g);
    if (double(f) > g) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

struct Rows {
    std::vector<std::vector<std::pair<uint32_t, float>>> pp, pw;
};

// The definition, every pair looked at.
Rows brute_force(const dem::Particles& p, const std::vector<dem::Plane>& planes, const std::vector<dem::Facet>& facets,
                 double skin) {
    const std::size_t n = p.size();
    Rows r;
    r.pp.resize(n);
    r.pw.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            const double reach = p.radius[i] + p.radius[j] + skin;
            const double d2 = dem::norm2(p.pos[j] - p.pos[i]);
            if (!(d2 < reach * reach) || !(p.mask[i] & p.mask[j])) continue;
            if (!dem::moves(p, i) && !dem::moves(p, j)) continue;
            r.pp[i].emplace_back(uint32_t(j), down(std::sqrt(d2) - (p.radius[i] + p.radius[j])));
        }
        if (!dem::moves(p, i) && !(p.flags[i] & dem::kPrescribed)) continue;  // a fixed sphere: no wall contacts
        for (std::size_t w = 0; w < planes.size(); ++w) {
            if (!(planes[w].mask & p.mask[i])) continue;
            const double sd = dem::dot(p.pos[i] - planes[w].point, planes[w].normal);
            const double dist = planes[w].one_sided ? sd : std::abs(sd);
            if (dist < p.radius[i] + skin) r.pw[i].emplace_back(uint32_t(w), down(dist - p.radius[i]));
        }
        for (std::size_t f = 0; f < facets.size(); ++f) {
            if (!(facets[f].mask & p.mask[i])) continue;
            const double reach = p.radius[i] + skin;
            const double d2 = dem::distance2_to_triangle(p.pos[i], facets[f].vertices);
            if (d2 < reach * reach)
                r.pw[i].emplace_back(uint32_t(planes.size() + f), down(std::sqrt(d2) - p.radius[i]));
        }
    }
    return r;
}

void expect_rows(const dem::CandidateList& cl, const std::vector<std::vector<std::pair<uint32_t, float>>>& rows,
                 const std::string& what) {
    ASSERT_EQ(cl.start.size(), rows.size() + 1) << what;
    std::size_t total = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        ASSERT_EQ(cl.start[i + 1] - cl.start[i], rows[i].size()) << what << ", particle " << i;
        for (std::size_t k = 0; k < rows[i].size(); ++k) {
            const uint32_t e = cl.start[i] + uint32_t(k);
            ASSERT_EQ(cl.other[e], rows[i][k].first) << what << ", particle " << i << ", entry " << k;
            ASSERT_EQ(cl.gap[e], rows[i][k].second) << what << ", particle " << i << ", entry " << k;
            ASSERT_EQ(cl.slot[e], dem::kNoSlot) << what;
        }
        total += rows[i].size();
    }
    EXPECT_EQ(cl.other.size(), total) << what;
}

// The broad phase's lists for `threads` threads, against the definition's.
void check(const dem::Particles& p, const std::vector<dem::Plane>& planes, const std::vector<dem::Facet>& facets,
           double skin, const std::string& what, std::size_t min_pairs) {
    const Rows ref = brute_force(p, planes, facets, skin);
    std::size_t pairs = 0;
    for (const auto& row : ref.pp) pairs += row.size();
    EXPECT_GE(pairs, min_pairs) << what << ": the packing has the pairs it is made for";
    std::vector<Vec3> plane_point;
    for (const dem::Plane& w : planes) plane_point.push_back(w.point);
    std::vector<std::array<Vec3, 3>> facet_now;
    for (const dem::Facet& f : facets) facet_now.push_back(f.vertices);
    dem::BondTables bonds;
    bonds.build(p.size(), dem::BondList{});
    for (const int threads : {1, 2, 3}) {
        dem::ThreadTeam team;
        dem::BroadPhase::Scene s;
        s.p = &p;
        s.planes = &planes;
        s.facets = &facets;
        s.plane_point = &plane_point;
        s.facet_now = &facet_now;
        s.bonds = &bonds;
        s.skin = skin;
        s.threads = threads;
        s.team = &team;
        dem::BroadPhase bp;
        dem::CandidateList pp, pw;
        bp.rebuild(s, pp, pw);
        const std::string w = what + ", " + std::to_string(threads) + " thread(s)";
        expect_rows(pp, ref.pp, w + ", particle pairs");
        expect_rows(pw, ref.pw, w + ", wall pairs");
    }
}

}  // namespace

// Spheres of radius r on a cubic lattice of spacing a = 2r + skin / 2: each sees its 6 neighbours
// at a gap of skin / 2 (inside the reach) and its 12 diagonal ones beyond it; the cells (2 rmax +
// skin = a + skin / 2) put many of them near a cell's face. With the lattice's origin at 0 the
// positions are exact multiples, so many distances tie.
TEST(BroadPhase, LatticeOnTheCellsEdgesGivesTheDefinitionsLists) {
    const double r = 0.001, skin = 0.0004, a = 2 * r + skin / 2;
    dem::Particles p;
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 6; ++x) add(p, {a * x, a * y, a * z}, r);
    check(p, {}, {}, skin, "lattice", 3 * 5 * 36);
}

// A random packing with the hard cases mixed in: two spheres at one point, spheres exactly at
// the reach of another (not candidates: the test is strict), fixed spheres touching each other
// (no pair among them, but pairs with the free ones), a second mask, a sphere thrown 100 m off
// (the grid's cells grow to keep their count bounded), walls: planes two- and one-sided, facets
// as large as the box.
TEST(BroadPhase, HardCasesGiveTheDefinitionsLists) {
    dem::Particles p;
    uint64_t s = 12345;
    const auto uniform = [&](double lo, double hi) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * double(s >> 11) * 0x1.0p-53;
    };
    for (int k = 0; k < 400; ++k) add(p, {uniform(0, 0.02), uniform(0, 0.02), uniform(0, 0.02)}, uniform(0.0005, 0.0012));
    add(p, {0.01, 0.01, 0.01}, 0.001);
    add(p, {0.01, 0.01, 0.01}, 0.001);                 // the same point
    add(p, {0.01 + 0.0024, 0.01, 0.01}, 0.001);        // gap 0.0004: at the reach (skin 0.0004), not a candidate
    for (int k = 0; k < 20; ++k) add(p, {0.001 * k, 0.0, -0.002}, 0.0006, true);  // a fixed row, touching
    for (int k = 0; k < 30; ++k) add(p, {uniform(0, 0.02), uniform(0, 0.02), uniform(0, 0.02)}, 0.001, false, 2);
    const double skin = 0.0004;
    std::vector<dem::Plane> planes(2);
    planes[0].point = {0, 0, 0};
    planes[0].normal = {0, 0, 1};
    planes[1].point = {0.02, 0, 0};
    planes[1].normal = {-1, 0, 0};
    planes[1].one_sided = true;
    std::vector<dem::Facet> facets(2);
    facets[0].vertices = {Vec3{-0.001, -0.001, 0.021}, Vec3{0.021, -0.001, 0.021}, Vec3{-0.001, 0.021, 0.021}};
    facets[1].vertices = {Vec3{0.0, 0.021, -0.001}, Vec3{0.021, 0.021, -0.001}, Vec3{0.0, 0.021, 0.021}};
    check(p, planes, facets, skin, "hard cases", 300);
    add(p, {100.0, 0.0, 0.0}, 0.001);  // thrown far off: the cells grow
    check(p, planes, facets, skin, "hard cases and a far sphere", 300);
}

}  // namespace test_broad_phase
