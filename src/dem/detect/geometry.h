// Narrow phase: contact geometry of sphere-sphere, sphere-plane and sphere-facet pairs.
// Geometry is kept apart from physics (Yade's Ig2 -> Ip2 -> Law2 split): these functions
// only produce a ContactGeom; the contact laws never look at shapes.
#pragma once

#include <array>
#include <cmath>

#include "dem/core/hd.h"
#include "dem/core/triangle.h"
#include "dem/core/vec3.h"

namespace dem {

// Convention (as Yade's ScGeom): body 1 -> body 2. For wall contacts the wall is body 1.
struct ContactGeom {
    Vec3 normal;          // unit vector from body 1 towards body 2
    double overlap = 0;   // [m] penetration depth, > 0 when touching
    double arm1 = 0;      // [m] centre of body 1 to contact point along +normal (0 for walls)
    double arm2 = 0;      // [m] centre of body 2 to contact point along -normal
};

// Sphere-sphere. Returns false when the spheres do not overlap.
VPPDEM_HD inline bool sphere_sphere(const Vec3& x1, double r1, const Vec3& x2, double r2, ContactGeom& g) {
    const Vec3 d = x2 - x1;
    const double d2 = norm2(d);
    const double rs = r1 + r2;
    if (d2 >= rs * rs) return false;
    const double dist = std::sqrt(d2);
    // One division and three products instead of three divisions (the hot path).
    g.normal = dist > 0.0 ? d * (1.0 / dist) : Vec3{0, 0, 1};
    g.overlap = rs - dist;
    g.arm1 = r1 - 0.5 * g.overlap;
    g.arm2 = r2 - 0.5 * g.overlap;
    return true;
}

// Sphere against an infinite plane through `point` with unit `normal`.
// Two-sided: the sphere is pushed away from whichever side its centre is on.
// One-sided: the plane bounds the half-space on its +normal side, so a sphere whose centre
// has crossed it is still pushed back out (a floor never lets grains tunnel through).
VPPDEM_HD inline bool sphere_plane(const Vec3& x, double r, const Vec3& point, const Vec3& normal,
                         bool one_sided, ContactGeom& g) {
    const double s = dot(x - point, normal);
    double dist = s;
    Vec3 n = normal;
    if (!one_sided && s < 0.0) {
        dist = -s;
        n = -normal;
    }
    if (dist >= r) return false;
    g.normal = n;
    g.overlap = r - dist;
    g.arm1 = 0.0;
    g.arm2 = r - 0.5 * g.overlap;
    return true;
}

// Sphere against a triangular facet: face, edge and vertex contacts all follow from the
// closest point; the normal runs from that point to the sphere centre.
// One-sided facets only touch spheres whose centre is on the +normal side.
VPPDEM_HD inline bool sphere_facet(const Vec3& x, double r, const std::array<Vec3, 3>& v, bool one_sided,
                         ContactGeom& g) {
    const Vec3 q = closest_point_on_triangle(x, v[0], v[1], v[2]);
    const Vec3 d = x - q;
    const double d2 = norm2(d);
    if (d2 >= r * r) return false;
    const Vec3 fn = cross(v[1] - v[0], v[2] - v[0]);
    const double side = dot(x - v[0], fn);
    if (one_sided && side <= 0.0) return false;
    const double dist = std::sqrt(d2);
    // A centre exactly on the facet has no direction to the closest point: use the face normal.
    g.normal = dist > 1e-14 * r ? d / dist : normalized(side >= 0.0 ? fn : -fn);
    g.overlap = r - dist;
    g.arm1 = 0.0;
    g.arm2 = r - 0.5 * g.overlap;
    return true;
}

// Squared distance from p to the triangle (broad phase).
inline double distance2_to_triangle(const Vec3& p, const std::array<Vec3, 3>& v) {
    return norm2(p - closest_point_on_triangle(p, v[0], v[1], v[2]));
}

}  // namespace dem
