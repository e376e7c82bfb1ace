// The fill's geometry (device/fill_geometry.h).
#include "vpp/device/fill_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dem/mesh/surface_mesh.h"

namespace vpp::device_detail {

using dem::Vec3;

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return norm(p - a);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return norm(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + ab * (d1 / (d1 - d3))));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return norm(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return norm(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double den = 1.0 / (va + vb + vc);
    return norm(p - (a + ab * (vb * den) + ac * (vc * den)));
}

bool inside(const dem::SurfaceMesh& m, const Vec3& p) { return dem::winding_number(m, p) > 0.5; }

bool inside_membrane(const Membrane& m, const std::vector<Vec3>& pos, const Vec3& p) {
    double omega = 0.0;
    for (const auto& t : m.triangles) {
        const Vec3 a = pos[t[0]] - p, b = pos[t[1]] - p, c = pos[t[2]] - p;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double num = dot(a, cross(b, c));
        const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        omega += 2.0 * std::atan2(num, den);
    }
    return omega > 2.0 * std::numbers::pi;
}

double distance_to_surface(const dem::SurfaceMesh& m, const Vec3& p) {
    double d = 1e300;
    for (const auto& t : m.triangles)
        d = std::min(d, point_triangle_distance(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
    return d;
}

double uniform(uint64_t& s) {
    // splitmix64
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
}

}  // namespace vpp::device_detail
