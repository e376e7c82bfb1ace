#include "dem/mesh/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace dem {

namespace {

double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return dot(b - a, cross(c - a, d - a)); }

std::string tri_name(const SurfaceMesh& m, std::size_t t) {
    const auto& v = m.triangles[t];
    return "triangle " + std::to_string(t) + " (vertices " + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " +
           std::to_string(v[2]) + ")";
}

std::string point_name(const Vec3& p) {
    char s[96];
    std::snprintf(s, sizeof s, "(%.6g, %.6g, %.6g)", p.x, p.y, p.z);
    return s;
}

// 2D helpers for coplanar pairs, in the plane dropping axis `drop`.
struct P2 {
    double x, y;
};
P2 project(const Vec3& p, int drop) {
    if (drop == 0) return {p.y, p.z};
    if (drop == 1) return {p.z, p.x};
    return {p.x, p.y};
}
double orient2(P2 a, P2 b, P2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }
bool on_segment(P2 a, P2 b, P2 p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}
bool segments_cross(P2 a, P2 b, P2 c, P2 d) {
    const double o1 = orient2(a, b, c), o2 = orient2(a, b, d), o3 = orient2(c, d, a), o4 = orient2(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
    return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
           (o4 == 0 && on_segment(c, d, b));
}
bool inside2(P2 a, P2 b, P2 c, P2 p) {
    const double d1 = orient2(a, b, p), d2 = orient2(b, c, p), d3 = orient2(c, a, p);
    const bool neg = d1 < 0 || d2 < 0 || d3 < 0, pos = d1 > 0 || d2 > 0 || d3 > 0;
    return !(neg && pos);
}

// The interval that triangle v[0..2] (signed distances d[0..2] to the other's plane, round-off
// snapped to 0) cuts from the planes' common line, as parameters along direction `dir`.
void plane_interval(const Vec3 v[3], const double d[3], const Vec3& dir, double& lo, double& hi) {
    lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if (d[i] == 0) {
            const double t = dot(v[i], dir);
            lo = std::min(lo, t), hi = std::max(hi, t);
        }
        if ((d[i] < 0 && d[j] > 0) || (d[i] > 0 && d[j] < 0)) {
            const double t = dot(v[i] + (d[i] / (d[i] - d[j])) * (v[j] - v[i]), dir);
            lo = std::min(lo, t), hi = std::max(hi, t);
        }
    }
}

}  // namespace

bool triangles_intersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1,
                         const Vec3& b2) {
    // Moeller's interval test: each triangle cuts a segment from the line where the two planes
    // meet; they intersect iff the segments overlap. Signed distances within round-off of a
    // plane count as on it (a triangle's edge lying in the other's plane is common in meshes
    // of prisms and cylinders).
    const Vec3 A[3] = {a0, a1, a2}, B[3] = {b0, b1, b2};
    const double scale = std::max({norm2(a1 - a0), norm2(a2 - a0), norm2(b1 - b0), norm2(b2 - b0)});
    const double tol = 1e-12 * scale * std::sqrt(scale);  // orient() is a volume
    auto snap = [tol](double x) { return std::abs(x) <= tol ? 0.0 : x; };
    double db[3], da[3];
    for (int i = 0; i < 3; ++i) db[i] = snap(orient(a0, a1, a2, B[i]));
    if ((db[0] > 0 && db[1] > 0 && db[2] > 0) || (db[0] < 0 && db[1] < 0 && db[2] < 0)) return false;
    const Vec3 n = cross(a1 - a0, a2 - a0);
    if (db[0] == 0 && db[1] == 0 && db[2] == 0) {
        // Coplanar: edges crossing, or one triangle inside the other.
        const int drop = std::abs(n.x) >= std::abs(n.y) && std::abs(n.x) >= std::abs(n.z) ? 0
                         : std::abs(n.y) >= std::abs(n.z)                                  ? 1
                                                                                           : 2;
        const P2 PA[3] = {project(a0, drop), project(a1, drop), project(a2, drop)};
        const P2 PB[3] = {project(b0, drop), project(b1, drop), project(b2, drop)};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (segments_cross(PA[i], PA[(i + 1) % 3], PB[j], PB[(j + 1) % 3])) return true;
        return inside2(PA[0], PA[1], PA[2], PB[0]) || inside2(PB[0], PB[1], PB[2], PA[0]);
    }
    for (int i = 0; i < 3; ++i) da[i] = snap(orient(b0, b1, b2, A[i]));
    if ((da[0] > 0 && da[1] > 0 && da[2] > 0) || (da[0] < 0 && da[1] < 0 && da[2] < 0)) return false;
    const Vec3 dir = cross(n, cross(b1 - b0, b2 - b0));
    double alo, ahi, blo, bhi;
    plane_interval(A, da, dir, alo, ahi);
    plane_interval(B, db, dir, blo, bhi);
    return alo <= bhi && blo <= ahi;
}

namespace {

// Non-manifold vertices: the triangles around a vertex must form a single fan, i.e. be connected
// through the edges that contain the vertex. The first such vertex, or "".
std::string non_manifold_vertex(const SurfaceMesh& m) {
    const std::size_t nt = m.triangles.size(), nv = m.vertices.size();
    std::vector<std::vector<uint32_t>> around(nv);
    for (std::size_t t = 0; t < nt; ++t)
        for (uint32_t k : m.triangles[t]) around[k].push_back(uint32_t(t));
    for (uint32_t v = 0; v < nv; ++v) {
        const auto& fan = around[v];
        if (fan.empty()) continue;
        // Walk from the first triangle across shared edges through v; a fan reaches them all.
        std::vector<char> seen(fan.size(), 0);
        std::vector<std::size_t> stack{0};
        seen[0] = 1;
        std::size_t reached = 1;
        while (!stack.empty()) {
            const auto& t = m.triangles[fan[stack.back()]];
            stack.pop_back();
            for (std::size_t q = 0; q < fan.size(); ++q) {
                if (seen[q]) continue;
                const auto& s = m.triangles[fan[q]];
                int shared = 0;
                for (uint32_t a : t)
                    for (uint32_t b : s) shared += (a == b);
                if (shared >= 2) {
                    seen[q] = 1;
                    ++reached;
                    stack.push_back(q);
                }
            }
        }
        if (reached != fan.size())
            return "not a manifold: vertex " + std::to_string(v) + " at " + point_name(m.vertices[v]) +
                   " joins surfaces that touch only there";
    }
    return "";
}

// Self-intersection between triangles that share no vertex, on a grid of cells about the size of
// the mean triangle's bounding box. The first intersecting pair, or "".
std::string self_intersection(const SurfaceMesh& m) {
    const std::size_t nt = m.triangles.size();
    std::vector<Vec3> lo(nt), hi(nt);
    Vec3 glo = m.vertices[0], ghi = m.vertices[0];
    double mean_extent = 0.0;
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& [a, b, c] = m.triangles[t];
        const Vec3 &A = m.vertices[a], &B = m.vertices[b], &C = m.vertices[c];
        lo[t] = {std::min({A.x, B.x, C.x}), std::min({A.y, B.y, C.y}), std::min({A.z, B.z, C.z})};
        hi[t] = {std::max({A.x, B.x, C.x}), std::max({A.y, B.y, C.y}), std::max({A.z, B.z, C.z})};
        glo = {std::min(glo.x, lo[t].x), std::min(glo.y, lo[t].y), std::min(glo.z, lo[t].z)};
        ghi = {std::max(ghi.x, hi[t].x), std::max(ghi.y, hi[t].y), std::max(ghi.z, hi[t].z)};
        mean_extent += std::max({hi[t].x - lo[t].x, hi[t].y - lo[t].y, hi[t].z - lo[t].z});
    }
    const Vec3 box = ghi - glo;
    double cell = std::max(mean_extent / double(nt), 1e-9 * norm(box));
    // At most ~8 cells per triangle on average: a few huge triangles must not blow up the grid.
    while ((box.x / cell + 1) * (box.y / cell + 1) * (box.z / cell + 1) > 8.0 * double(nt) + 64) cell *= 1.5;
    auto cidx = [&](double x, double o) { return int64_t(std::floor((x - o) / cell)); };
    const int64_t nx = cidx(ghi.x, glo.x) + 1, ny = cidx(ghi.y, glo.y) + 1;
    std::unordered_map<int64_t, std::vector<uint32_t>> grid;
    for (uint32_t t = 0; t < nt; ++t)
        for (int64_t z = cidx(lo[t].z, glo.z); z <= cidx(hi[t].z, glo.z); ++z)
            for (int64_t y = cidx(lo[t].y, glo.y); y <= cidx(hi[t].y, glo.y); ++y)
                for (int64_t x = cidx(lo[t].x, glo.x); x <= cidx(hi[t].x, glo.x); ++x)
                    grid[(z * ny + y) * nx + x].push_back(t);
    std::vector<uint32_t> stamp(nt, UINT32_MAX);
    for (uint32_t t = 0; t < nt; ++t) {
        const auto& T = m.triangles[t];
        for (int64_t z = cidx(lo[t].z, glo.z); z <= cidx(hi[t].z, glo.z); ++z)
            for (int64_t y = cidx(lo[t].y, glo.y); y <= cidx(hi[t].y, glo.y); ++y)
                for (int64_t x = cidx(lo[t].x, glo.x); x <= cidx(hi[t].x, glo.x); ++x)
                    for (uint32_t s : grid[(z * ny + y) * nx + x]) {
                        if (s <= t || stamp[s] == t) continue;
                        stamp[s] = t;
                        const auto& S = m.triangles[s];
                        bool adjacent = false;
                        for (uint32_t a : T)
                            for (uint32_t b : S) adjacent |= (a == b);
                        if (adjacent) continue;
                        if (hi[s].x < lo[t].x || hi[t].x < lo[s].x || hi[s].y < lo[t].y || hi[t].y < lo[s].y ||
                            hi[s].z < lo[t].z || hi[t].z < lo[s].z)
                            continue;
                        if (triangles_intersect(m.vertices[T[0]], m.vertices[T[1]], m.vertices[T[2]], m.vertices[S[0]],
                                                m.vertices[S[1]], m.vertices[S[2]]))
                            return "self-intersecting: " + tri_name(m, t) + " and " + tri_name(m, s) + " intersect near " +
                                   point_name(m.vertices[T[0]]);
                    }
    }
    return "";
}

}  // namespace

std::string find_mesh_defect(const SurfaceMesh& m) {
    const std::size_t nt = m.triangles.size(), nv = m.vertices.size();
    if (nt < 4) return "not closed: " + std::to_string(nt) + " triangles cannot enclose a volume";
    for (const auto& t : m.triangles)
        for (uint32_t k : t)
            if (k >= nv) return "a triangle names vertex " + std::to_string(k) + " of " + std::to_string(nv);
    // Beyond 1e100 products of coordinates (volumes, orientations) overflow.
    for (const Vec3& v : m.vertices)
        if (!(std::abs(v.x) < 1e100 && std::abs(v.y) < 1e100 && std::abs(v.z) < 1e100))
            return "a vertex at " + point_name(v) + " is not finite or beyond 1e100";

    // Degenerate triangles: area against the longest edge squared (scale-free).
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& [a, b, c] = m.triangles[t];
        const Vec3 &A = m.vertices[a], &B = m.vertices[b], &C = m.vertices[c];
        const double l2 = std::max({norm2(B - A), norm2(C - A), norm2(C - B)});
        if (a == b || b == c || a == c || !(norm(cross(B - A, C - A)) > 1e-12 * l2))
            return "degenerate triangle: " + tri_name(m, t) + " at " + point_name(A) + " has zero area";
    }

    // Directed half-edges sorted by their undirected edge.
    struct Half {
        uint32_t lo, hi;
        bool forward;  // lo -> hi in the triangle's winding
        uint32_t tri;
    };
    std::vector<Half> h;
    h.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
            h.push_back({std::min(a, b), std::max(a, b), a < b, uint32_t(t)});
        }
    std::sort(h.begin(), h.end(), [](const Half& x, const Half& y) {
        return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.tri < y.tri;
    });
    std::vector<uint32_t> parent(nt);
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::string inconsistent;
    for (std::size_t i = 0; i < h.size();) {
        std::size_t j = i;
        while (j < h.size() && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
        const std::string edge = "edge " + std::to_string(h[i].lo) + "-" + std::to_string(h[i].hi) + " at " +
                                 point_name(0.5 * (m.vertices[h[i].lo] + m.vertices[h[i].hi]));
        if (j - i == 1) return "open: " + edge + " belongs to one triangle only (" + tri_name(m, h[i].tri) + ")";
        if (j - i > 2)
            return "not a manifold: " + edge + " is shared by " + std::to_string(j - i) + " triangles";
        if (h[i].forward == h[i + 1].forward && inconsistent.empty())
            inconsistent = "inconsistent orientation: " + edge + " is traversed in the same direction by " +
                           tri_name(m, h[i].tri) + " and " + tri_name(m, h[i + 1].tri) + " (some triangles are flipped)";
        parent[root(h[i].tri)] = root(h[i + 1].tri);
        i = j;
    }

    if (std::string fan = non_manifold_vertex(m); !fan.empty()) return fan;
    if (!inconsistent.empty()) return inconsistent;
    std::size_t pieces = 0;
    for (uint32_t t = 0; t < nt; ++t) pieces += root(t) == t;
    if (pieces > 1) return "several surfaces: " + std::to_string(pieces) + " separate closed pieces (one is expected)";
    const double vol = enclosed_volume(m);
    if (!(vol > 0)) return "inverted: the enclosed volume is negative, the normals point inward (reverse the winding)";
    return self_intersection(m);
}

void check_closed_surface(const SurfaceMesh& m, const std::string& name) {
    const std::string d = find_mesh_defect(m);
    if (!d.empty()) throw std::runtime_error("mesh '" + name + "': " + d);
}

SurfaceMesh read_closed_surface(const std::string& path, const MeshReadOptions& opt) {
    SurfaceMesh m = read_surface_mesh(path, opt);
    check_closed_surface(m, path);
    return m;
}

}  // namespace dem
