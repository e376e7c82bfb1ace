// Mass properties of clumps (dem/clumps/clump_shape.h) against closed forms: the union of two
// overlapping spheres integrated by disks, a lone sphere, the regular tetrahedron's isotropy, the
// scaling laws, and the Jacobi eigen-solver on a rotated diagonal matrix.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "dem/clumps/clump_shape.h"

using namespace dem;

namespace {

constexpr double kPi = std::numbers::pi;

// Two spheres of radius r at x = +-a (a < r), by disks along x: the union's cross-section at x
// is the larger disk, radius^2 = r^2 - (|x| - a)^2. With u = |x| - a from -a to r:
//   V      = 2 pi int (r^2 - u^2) du
//   I_axis = 2 (pi / 2) int (r^2 - u^2)^2 du          (disks' polar moments)
//   S_xx   = 2 pi int (u + a)^2 (r^2 - u^2) du        (int x^2 dV)
//   I_perp = S_xx + I_axis / 2
struct DimerClosedForm {
    double v, i_axis, i_perp;
};
DimerClosedForm dimer_closed_form(double r, double a) {
    const auto F = [&](auto f) { return f(r) - f(-a); };
    const double r2 = r * r;
    const double v = 2.0 * kPi * F([&](double u) { return r2 * u - u * u * u / 3.0; });
    const double i_axis = kPi * F([&](double u) { return r2 * r2 * u - 2.0 * r2 * u * u * u / 3.0 + std::pow(u, 5) / 5.0; });
    // (u + a)^2 (r^2 - u^2) = -u^4 - 2a u^3 + (r^2 - a^2) u^2 + 2 a r^2 u + a^2 r^2
    const double sxx = 2.0 * kPi * F([&](double u) {
        return -std::pow(u, 5) / 5.0 - a * std::pow(u, 4) / 2.0 + (r2 - a * a) * u * u * u / 3.0 + a * r2 * u * u +
               a * a * r2 * u;
    });
    return {v, i_axis, sxx + 0.5 * i_axis};
}

}  // namespace

// Two members overlap pairwise only: the lens is in closed form, so the union's integrals are
// exact to round-off (measured: 7e-16), checked at 1e-12; a lens counted once, or not at all, is
// off by 19%.
TEST(ClumpShape, DimerMatchesTheClosedFormOfTheUnion) {
    for (const double a : {0.5, 0.8}) {
        const DimerClosedForm e = dimer_closed_form(1.0, a);
        const ClumpShape s = make_clump_shape({{{-a, 0, 0}, 1.0}, {{a, 0, 0}, 1.0}});
        // The lens formula as a second closed form of the volume.
        const double d = 2.0 * a, lens = kPi * (4.0 + d) * (2.0 - d) * (2.0 - d) / 12.0;
        EXPECT_NEAR(e.v, 2.0 * 4.0 / 3.0 * kPi - lens, 1e-12);
        EXPECT_NEAR(s.volume / e.v - 1.0, 0.0, 1e-12) << "a = " << a;
        EXPECT_NEAR(s.inertia_per_density.x / e.i_axis - 1.0, 0.0, 1e-12) << "a = " << a;
        EXPECT_NEAR(s.inertia_per_density.y / e.i_perp - 1.0, 0.0, 1e-12) << "a = " << a;
        EXPECT_NEAR(s.inertia_per_density.z / e.i_perp - 1.0, 0.0, 1e-12) << "a = " << a;
        // Principal frame: the axis first (smallest moment), members at -+a on it.
        ASSERT_EQ(s.members.size(), 2u);
        EXPECT_NEAR(std::abs(s.members[0].center.x), a, 1e-9);
        EXPECT_NEAR(s.members[0].center.y, 0.0, 1e-9);
        EXPECT_NEAR(s.members[0].center.z, 0.0, 1e-9);
        EXPECT_NEAR(s.members[0].center.x + s.members[1].center.x, 0.0, 1e-9);
        EXPECT_NEAR(s.bounding_radius, a + 1.0, 1e-9);
        std::cout << "[measure] dimer a=" << a << ": volume rel err " << s.volume / e.v - 1.0 << ", I_axis "
                  << s.inertia_per_density.x / e.i_axis - 1.0 << ", I_perp " << s.inertia_per_density.y / e.i_perp - 1.0
                  << "\n";
    }
}

TEST(ClumpShape, UnequalPairHasTheLensVolumeAndItsCentreOnTheAxis) {
    // Radii R = 1 and r = 0.5 at distance d = 1.2: lens V = pi (R + r - d)^2 (d^2 + 2dr - 3r^2 +
    // 2dR + 6rR - 3R^2) / (12 d).
    const double R = 1.0, r = 0.5, d = 1.2;
    const double lens = kPi * (R + r - d) * (R + r - d) * (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d);
    const double v = 4.0 / 3.0 * kPi * (R * R * R + r * r * r) - lens;
    // A template off the origin and turned: the result does not depend on the frame.
    const Vec3 axis = normalized(Vec3{1, 2, 2});
    const Vec3 o{0.3, -1.0, 2.0};
    const ClumpShape s = make_clump_shape({{o, R}, {o + axis * d, r}});
    EXPECT_NEAR(s.volume / v - 1.0, 0.0, 1e-12);
    // The centre lies on the line through the two centres.
    const Vec3 c = s.template_center - o;
    EXPECT_NEAR(norm(cross(c, axis)), 0.0, 1e-9);
    // Members' centres in the principal frame: on axis 0 (the smallest moment), d apart.
    EXPECT_NEAR(norm(s.members[1].center - s.members[0].center), d, 1e-9);
    EXPECT_NEAR(std::abs(s.members[1].center.x - s.members[0].center.x), d, 1e-9);
    // The principal frame maps the template's axis onto x.
    const Vec3 e = rotate(s.template_to_principal, axis);
    EXPECT_NEAR(std::abs(e.x), 1.0, 1e-9);
}

TEST(ClumpShape, OneSphereIsExact) {
    const ClumpShape s = make_clump_shape({{{1, 2, 3}, 0.7}});
    const double v = 4.0 / 3.0 * kPi * 0.343;
    EXPECT_DOUBLE_EQ(s.volume, v);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.inertia_per_density[k], 0.4 * v * 0.49, 1e-15);
    EXPECT_NEAR(norm(s.members[0].center), 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(s.bounding_radius, 0.7);
}

TEST(ClumpShape, RegularTetrahedronIsIsotropicAndBuiltInShapesHaveTheSphereVolume) {
    const double r = 1.5e-3;
    for (const std::string& name : builtin_clump_shapes()) {
        const ClumpShape s = builtin_clump_shape(name, r);
        EXPECT_NEAR(s.volume / (4.0 / 3.0 * kPi * r * r * r) - 1.0, 0.0, 1e-13) << name;
        EXPECT_LE(s.inertia_per_density.x, s.inertia_per_density.y) << name;
        EXPECT_LE(s.inertia_per_density.y, s.inertia_per_density.z) << name;
        EXPECT_GE(s.bounding_radius, r * (1.0 - 1e-12)) << name;
    }
    const ClumpShape t = builtin_clump_shape("tetrahedron", r);
    // Its triple overlaps by the midpoint rule: isotropic and centred to the rule's error.
    EXPECT_NEAR(t.inertia_per_density.x / t.inertia_per_density.z, 1.0, 1e-5);
    Vec3 com;
    for (const ClumpMember& m : t.members) com += m.center;
    EXPECT_NEAR(norm(com) / r, 0.0, 1e-5);
    // The dimer's aspect ratio: length / width = (2 + 1) / 2 radii.
    const ClumpShape d = builtin_clump_shape("dimer", r);
    EXPECT_NEAR(d.bounding_radius * 2.0 / (2.0 * d.members[0].radius), 1.5, 1e-9);
    try {
        builtin_clump_shape("cube", r);
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'cube'"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("pellet"), std::string::npos);
    }
}

// Members overlapping three at a time (the tetrahedron, the pellet): the triple regions by the
// midpoint rule, whose error on a region bounded by spheres falls irregularly with the cell.
// Against a grid 4 times finer the default changes volume and moments by less than 1e-4
// (measured: tetrahedron 1e-5, pellet 6.4e-5; 320 cells per radius: 1e-5 and 5e-5).
TEST(ClumpShape, TripleOverlapsConvergeWithTheGrid) {
    for (const char* name : {"tetrahedron", "pellet"}) {
        const ClumpShape unit = builtin_clump_shape(name, 1.0);
        std::vector<ClumpMember> t = unit.members;
        const ClumpShape a = make_clump_shape(t, 40), b = make_clump_shape(t, 160);
        double worst = std::abs(a.volume / b.volume - 1.0);
        for (int k = 0; k < 3; ++k)
            worst = std::max(worst, std::abs(a.inertia_per_density[k] / b.inertia_per_density[k] - 1.0));
        std::cout << "[measure] " << name << ": 40 against 160 cells per radius, largest relative change " << worst << "\n";
        EXPECT_LT(worst, 1e-4) << name;
    }
}

TEST(ClumpShape, ScalingFollowsTheDimensions) {
    const ClumpShape a = builtin_clump_shape("pellet", 1.0);
    const ClumpShape b = scaled(a, 2.0);
    EXPECT_DOUBLE_EQ(b.volume, 8.0 * a.volume);
    EXPECT_DOUBLE_EQ(b.inertia_per_density.z, 32.0 * a.inertia_per_density.z);
    EXPECT_DOUBLE_EQ(b.members[3].radius, 2.0 * a.members[3].radius);
}

TEST(ClumpShape, BadTemplatesAreRefusedWithTheReason) {
    const auto message = [](const std::vector<ClumpMember>& m) {
        try {
            make_clump_shape(m);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message({}).find("no members"), std::string::npos);
    EXPECT_NE(message({{{0, 0, 0}, 1.0}, {{3, 0, 0}, 1.0}}).find("do not all touch"), std::string::npos);
    EXPECT_NE(message({{{0, 0, 0}, 1.0}, {{1, 0, 0}, -1.0}}).find("member 2 has radius"), std::string::npos);
    EXPECT_NE(message({{{0, 0, NAN}, 1.0}}).find("non-finite"), std::string::npos);
}

TEST(ClumpShape, JacobiRecoversARotatedDiagonal) {
    // R diag(1, 2, 3) R^T with R a rotation about (1, 1, 1) by 0.7 rad.
    const Vec3 u = normalized(Vec3{1, 1, 1});
    const double h = 0.35;
    const Quat q{std::cos(h), u.x * std::sin(h), u.y * std::sin(h), u.z * std::sin(h)};
    std::array<std::array<double, 3>, 3> a{};
    const double lam[3] = {1.0, 2.0, 3.0};
    for (int k = 0; k < 3; ++k) {
        const Vec3 e = body_axis(q, k);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) a[i][j] += lam[k] * e[i] * e[j];
    }
    const SymmetricEigen3 e = symmetric_eigen(a);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(e.values[k], lam[k], 1e-13);
        EXPECT_NEAR(std::abs(dot(e.vectors[k], body_axis(q, k))), 1.0, 1e-12);
    }
    EXPECT_NEAR(dot(cross(e.vectors[0], e.vectors[1]), e.vectors[2]), 1.0, 1e-12);
}
