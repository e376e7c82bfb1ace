// Narrow-phase geometry: sphere-sphere, sphere-plane, sphere-facet (face, edge, vertex,
// one-sided) against hand-computed normals and overlaps. Exact inputs (dyadic numbers where
// possible), so tolerances are a few ulps (1e-12 relative).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "dem/detect/geometry.h"

using namespace dem;

namespace {

constexpr double kTol = 1e-12;

void expect_vec_near(const Vec3& a, const Vec3& b, double tol = kTol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// Facet in z = 0: v0 = (-1,0,0), v1 = (1,0,0), v2 = (0,1,0); normal (v1-v0)x(v2-v0) = +z.
const std::array<Vec3, 3> kTri{Vec3{-1, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}};

}  // namespace

TEST(UnitGeometry, SphereSphereNormalOverlapArms) {
    ContactGeom g;
    // Centres 3 apart along (0.6, 0, 0.8), radii 1 and 2.5: overlap 0.5.
    const Vec3 x1{1, 2, 3}, d{1.8, 0, 2.4};
    ASSERT_TRUE(sphere_sphere(x1, 1.0, x1 + d, 2.5, g));
    expect_vec_near(g.normal, {0.6, 0, 0.8});
    EXPECT_NEAR(g.overlap, 0.5, kTol);
    EXPECT_NEAR(g.arm1, 1.0 - 0.25, kTol);
    EXPECT_NEAR(g.arm2, 2.5 - 0.25, kTol);
    // Exactly touching or apart: no contact.
    EXPECT_FALSE(sphere_sphere(x1, 1.0, x1 + Vec3{3.5, 0, 0}, 2.5, g));
    EXPECT_FALSE(sphere_sphere(x1, 1.0, x1 + Vec3{4, 0, 0}, 2.5, g));
}

TEST(UnitGeometry, SpherePlaneTwoSidedAndOneSided) {
    ContactGeom g;
    const Vec3 pt{0, 0, 1}, n{0, 0, 1};
    // Above: overlap r - s, normal +n.
    ASSERT_TRUE(sphere_plane({5, 5, 1.25}, 0.5, pt, n, false, g));
    expect_vec_near(g.normal, n);
    EXPECT_NEAR(g.overlap, 0.25, kTol);
    EXPECT_NEAR(g.arm2, 0.5 - 0.125, kTol);
    // Below a two-sided plane: pushed down.
    ASSERT_TRUE(sphere_plane({5, 5, 0.75}, 0.5, pt, n, false, g));
    expect_vec_near(g.normal, {0, 0, -1});
    EXPECT_NEAR(g.overlap, 0.25, kTol);
    // Below a one-sided plane: still pushed back to +n, overlap r - s > r.
    ASSERT_TRUE(sphere_plane({5, 5, 0.75}, 0.5, pt, n, true, g));
    expect_vec_near(g.normal, n);
    EXPECT_NEAR(g.overlap, 0.75, kTol);
    // Out of reach.
    EXPECT_FALSE(sphere_plane({5, 5, 1.5}, 0.5, pt, n, false, g));
    EXPECT_FALSE(sphere_plane({5, 5, 0.5}, 0.5, pt, n, false, g));
}

TEST(UnitGeometry, ClosestPointRegions) {
    int region = -1;
    // Face interior.
    expect_vec_near(closest_point_on_triangle({0.25, 0.25, 3}, kTri[0], kTri[1], kTri[2], &region),
                    {0.25, 0.25, 0});
    EXPECT_EQ(region, 0);
    // Edge v0-v1 (below y = 0).
    expect_vec_near(closest_point_on_triangle({0.5, -2, 1}, kTri[0], kTri[1], kTri[2], &region),
                    {0.5, 0, 0});
    EXPECT_EQ(region, 1);
    // Edge v1-v2: outward normal (1,1)/sqrt2; point (1,1,0) projects to (0.5, 0.5, 0).
    expect_vec_near(closest_point_on_triangle({1, 1, -1}, kTri[0], kTri[1], kTri[2], &region),
                    {0.5, 0.5, 0});
    EXPECT_EQ(region, 1);
    // Edge v2-v0: point (-1,1,0) projects to (-0.5, 0.5, 0).
    expect_vec_near(closest_point_on_triangle({-1, 1, 0.5}, kTri[0], kTri[1], kTri[2], &region),
                    {-0.5, 0.5, 0});
    EXPECT_EQ(region, 1);
    // Vertices.
    expect_vec_near(closest_point_on_triangle({-3, -1, 1}, kTri[0], kTri[1], kTri[2], &region), kTri[0]);
    EXPECT_EQ(region, 2);
    expect_vec_near(closest_point_on_triangle({3, -1, 1}, kTri[0], kTri[1], kTri[2], &region), kTri[1]);
    EXPECT_EQ(region, 2);
    expect_vec_near(closest_point_on_triangle({0, 4, -1}, kTri[0], kTri[1], kTri[2], &region), kTri[2]);
    EXPECT_EQ(region, 2);
}

TEST(UnitGeometry, SphereFacetFaceContact) {
    ContactGeom g;
    ASSERT_TRUE(sphere_facet({0.25, 0.25, 0.375}, 0.5, kTri, false, g));
    expect_vec_near(g.normal, {0, 0, 1});
    EXPECT_NEAR(g.overlap, 0.125, kTol);
    EXPECT_EQ(g.arm1, 0.0);
    EXPECT_NEAR(g.arm2, 0.5 - 0.0625, kTol);
    // Below a two-sided facet: normal points down.
    ASSERT_TRUE(sphere_facet({0.25, 0.25, -0.375}, 0.5, kTri, false, g));
    expect_vec_near(g.normal, {0, 0, -1});
    EXPECT_NEAR(g.overlap, 0.125, kTol);
    // Out of reach.
    EXPECT_FALSE(sphere_facet({0.25, 0.25, 0.5}, 0.5, kTri, false, g));
}

TEST(UnitGeometry, SphereFacetEdgeContactNormalFromClosestPoint) {
    ContactGeom g;
    // Centre (0.5, -0.3, 0.4): closest point (0.5, 0, 0) on edge v0-v1, distance 0.5.
    ASSERT_TRUE(sphere_facet({0.5, -0.3, 0.4}, 0.75, kTri, false, g));
    expect_vec_near(g.normal, {0, -0.6, 0.8});
    EXPECT_NEAR(g.overlap, 0.25, kTol);
    // Beyond the edge but within reach of it, below the plane: normal points down and out.
    ASSERT_TRUE(sphere_facet({0.5, -0.3, -0.4}, 0.75, kTri, false, g));
    expect_vec_near(g.normal, {0, -0.6, -0.8});
    // Beyond reach of the edge although within r of the facet's plane.
    EXPECT_FALSE(sphere_facet({0.5, -0.7, 0.1}, 0.6, kTri, false, g));
}

TEST(UnitGeometry, SphereFacetVertexContactNormalFromClosestPoint) {
    ContactGeom g;
    // Centre v1 + (0.4, -0.4, 0.2): |off| = 0.6, normal (2/3, -2/3, 1/3).
    const Vec3 off{0.4, -0.4, 0.2};
    const double dist = 0.6;
    int region = -1;
    closest_point_on_triangle(kTri[1] + off, kTri[0], kTri[1], kTri[2], &region);
    ASSERT_EQ(region, 2);
    ASSERT_TRUE(sphere_facet(kTri[1] + off, 1.0, kTri, false, g));
    expect_vec_near(g.normal, {2.0 / 3.0, -2.0 / 3.0, 1.0 / 3.0});
    EXPECT_NEAR(g.overlap, 1.0 - dist, kTol);
    EXPECT_FALSE(sphere_facet(kTri[1] + off, 0.99 * dist, kTri, false, g));
}

TEST(UnitGeometry, OneSidedFacetIgnoresSpheresBehind) {
    ContactGeom g;
    // In front (+z): touches like a two-sided one.
    ASSERT_TRUE(sphere_facet({0.25, 0.25, 0.375}, 0.5, kTri, true, g));
    expect_vec_near(g.normal, {0, 0, 1});
    // Behind the face, behind an edge, behind a vertex: no contact.
    EXPECT_FALSE(sphere_facet({0.25, 0.25, -0.375}, 0.5, kTri, true, g));
    EXPECT_FALSE(sphere_facet({0.5, -0.3, -0.4}, 0.75, kTri, true, g));
    EXPECT_FALSE(sphere_facet(kTri[1] + Vec3{0.3, -0.2, -0.1}, 0.5, kTri, true, g));
    // The two-sided facet does touch all three.
    EXPECT_TRUE(sphere_facet({0.25, 0.25, -0.375}, 0.5, kTri, false, g));
    EXPECT_TRUE(sphere_facet({0.5, -0.3, -0.4}, 0.75, kTri, false, g));
    EXPECT_TRUE(sphere_facet(kTri[1] + Vec3{0.3, -0.2, -0.1}, 0.5, kTri, false, g));
    // Flipping the vertex order flips the side.
    const std::array<Vec3, 3> flipped{kTri[0], kTri[2], kTri[1]};
    EXPECT_TRUE(sphere_facet({0.25, 0.25, -0.375}, 0.5, flipped, true, g));
    expect_vec_near(g.normal, {0, 0, -1});
    EXPECT_FALSE(sphere_facet({0.25, 0.25, 0.375}, 0.5, flipped, true, g));
}

TEST(UnitGeometry, SphereCentreOnFacetUsesFaceNormal) {
    ContactGeom g;
    ASSERT_TRUE(sphere_facet({0.25, 0.25, 0.0}, 0.5, kTri, false, g));
    expect_vec_near(g.normal, {0, 0, 1});
    EXPECT_NEAR(g.overlap, 0.5, kTol);
}

TEST(UnitGeometry, DistanceToTriangle) {
    EXPECT_NEAR(distance2_to_triangle({0.25, 0.25, 3}, kTri), 9.0, kTol);
    EXPECT_NEAR(distance2_to_triangle({0.5, -2, 1}, kTri), 5.0, kTol);
    EXPECT_NEAR(distance2_to_triangle({3, -1, 1}, kTri), 4.0 + 1.0 + 1.0, kTol);
}
