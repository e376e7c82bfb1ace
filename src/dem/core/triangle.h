// The closest point of a triangle to a point: the one geometric kernel that the contact geometry
// (dem/detect/geometry.h: spheres against facets) and the mesh tools (dem/mesh/remesh.cpp: the
// projection back onto the input surface) share, so it lives below both, in the core.
#pragma once

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem {

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5).
// Returns the point; `region` tells face (0), edge (1) or vertex (2), which the tests use.
VPPDEM_HD inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                      int* region = nullptr) {
    auto set = [&](int r) { if (region) *region = r; };
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) { set(2); return a; }
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { set(2); return b; }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) { set(1); return a + ab * (d1 / (d1 - d3)); }
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) { set(2); return c; }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) { set(1); return a + ac * (d2 / (d2 - d6)); }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        set(1);
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    const double denom = 1.0 / (va + vb + vc);
    set(0);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace dem
