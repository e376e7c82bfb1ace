#include "dem/mesh/surface_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dem {

double surface_area(const SurfaceMesh& m) {
    double a = 0.0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) a += norm(area_vector(m, t));
    return a;
}

double enclosed_volume(const SurfaceMesh& m) {
    double six_v = 0.0;
    for (const auto& [a, b, c] : m.triangles) six_v += dot(m.vertices[a], cross(m.vertices[b], m.vertices[c]));
    return six_v / 6.0;
}

double winding_number(const SurfaceMesh& m, const Vec3& p) {
    double omega = 0.0;
    for (const auto& t : m.triangles) {
        const Vec3 a = m.vertices[t[0]] - p, b = m.vertices[t[1]] - p, c = m.vertices[t[2]] - p;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double num = dot(a, cross(b, c));
        const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        omega += 2.0 * std::atan2(num, den);
    }
    return omega / (4.0 * std::numbers::pi);
}

std::vector<std::array<uint32_t, 2>> unique_edges(const SurfaceMesh& m) {
    std::vector<std::array<uint32_t, 2>> e;
    e.reserve(3 * m.triangles.size());
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a != b) e.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    return e;
}

}  // namespace dem
