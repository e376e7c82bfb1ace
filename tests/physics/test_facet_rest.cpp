// A sphere at rest on a horizontal facet under gravity, on the face, on an edge and on a
// vertex. In every case the contact normal runs from the closest point of the triangle to the
// centre (vertical here), so at equilibrium the facet carries m g and the overlap is
// m g / kn with kn = E r (same material on both sides).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dem/detect/geometry.h"
#include "helpers.h"

using namespace dem;
using namespace dem::testing;

namespace facet_rest_test {

constexpr double kR = 0.01;
constexpr double kFacetYoung = 1e6;
constexpr double kG = 9.81;
constexpr double kA = 0.05;  // facet size [m]

struct RestResult {
    double force_z = 0;   // [N] z component of the force the sphere puts on the facet
    double overlap = 0;   // [m] r - distance(centre, closest point)
    double drift = 0;     // [m] horizontal drift of the centre
    int region = -1;      // closest_point_on_triangle region of the start position
};

// Facet v0 = (-a,0,0), v1 = (a,0,0), v2 = (0,a,0): normal (v1-v0)x(v2-v0) = +z.
// The sphere starts just touching (zero overlap) at rest at horizontal position xy, so it
// drops by m g / kn and rings; local damping 0.4 removes the ringing.
RestResult rest_on_facet(Vec3 xy, bool one_sided) {
    World w;
    w.add_material(make_material(kFacetYoung, 0.4));
    w.params.gravity = {0, 0, -kG};
    w.params.local_damping = 0.4;
    const double m = sphere_mass(2800.0, kR), kn = kFacetYoung * kR;
    w.params.dt = 2.0 * kPi * std::sqrt(m / kn) / 50.0;  // 50 steps per normal period
    Facet f;
    f.vertices = {Vec3{-kA, 0, 0}, Vec3{kA, 0, 0}, Vec3{0, kA, 0}};
    f.one_sided = one_sided;
    w.add_facet(f);
    SphereDef s;
    s.radius = kR;
    s.position = {xy.x, xy.y, kR};
    w.add_sphere(s);
    RestResult r;
    closest_point_on_triangle(s.position, f.vertices[0], f.vertices[1], f.vertices[2], &r.region);
    for (int k = 0; k < 3000; ++k) w.step();  // 60 periods
    w.compute_forces();
    const Vec3 x = w.particles.pos[0];
    const Vec3 q = closest_point_on_triangle(x, f.vertices[0], f.vertices[1], f.vertices[2]);
    r.force_z = w.wall_force(w.planes.size() + 0).z;
    r.overlap = kR - norm(x - q);
    r.drift = std::hypot(x.x - xy.x, x.y - xy.y);
    return r;
}

void check_rest(const std::string& name, Vec3 xy, int expected_region, bool one_sided = false) {
    const RestResult r = rest_on_facet(xy, one_sided);
    const double m = sphere_mass(2800.0, kR), kn = kFacetYoung * kR;
    EXPECT_EQ(r.region, expected_region);
    // Facet reaction: the sphere pushes down with m g. Tolerance 0.5%: after 60 periods with
    // local damping 0.4 (amplitude x ~0.43 per period) the ringing is gone to machine level.
    EXPECT_LT(report_rel(name + "_facet_force", -r.force_z, m * kG, 0.005), 0.005);
    // Overlap m g / kn within 1%.
    EXPECT_LT(report_rel(name + "_overlap", r.overlap, m * kG / kn, 0.01), 0.01);
    // The vertical normal leaves no horizontal force: the centre stays put.
    EXPECT_LT(r.drift, 1e-12);
}


TEST(PhysicsFacetRest, OnFace) { check_rest("facet_face", {0.0, 0.3 * kA, 0}, 0); }

// Centre above the middle of edge v0-v1 (y = 0): the closest point is on the edge (region 1).
TEST(PhysicsFacetRest, OnEdge) { check_rest("facet_edge", {0.0, 0.0, 0}, 1); }

// Centre above vertex v1 = (a, 0, 0): region 2.
TEST(PhysicsFacetRest, OnVertex) { check_rest("facet_vertex", {kA, 0.0, 0}, 2); }

// The same on a one-sided facet (the sphere is on its +normal side).
TEST(PhysicsFacetRest, OnEdgeOneSided) { check_rest("facet_edge_one_sided", {0.0, 0.0, 0}, 1, true); }

}  // namespace facet_rest_test
