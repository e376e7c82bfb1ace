#include "dem/mesh/mesh_shapes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

namespace dem {

SurfaceMesh make_icosphere(double radius, int s, const Vec3& center) {
    if (!(radius > 0) || s < 1) throw std::invalid_argument("icosphere: radius > 0 and subdivisions >= 1");
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    const Vec3 ico[12] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                          {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    SurfaceMesh m;
    // Points of a face's grid are keyed by their exact barycentric integers on the shared
    // icosahedron vertices, so neighbouring faces reuse the same vertex without welding.
    std::map<std::array<int, 6>, uint32_t> index;
    auto vertex = [&](int a, int b, int c, int i, int j, int k) {
        // Canonical key: (corner, weight) pairs sorted by corner, zero weights dropped.
        std::array<std::pair<int, int>, 3> w{{{a, i}, {b, j}, {c, k}}};
        std::sort(w.begin(), w.end());
        std::array<int, 6> key{};
        int n = 0;
        for (auto [v, x] : w)
            if (x != 0) key[n++] = v, key[n++] = x;
        for (; n < 6; ++n) key[n] = -1;
        auto [it, fresh] = index.try_emplace(key, uint32_t(m.vertices.size()));
        if (fresh) {
            const Vec3 p = (double(i) * ico[a] + double(j) * ico[b] + double(k) * ico[c]) / double(s);
            m.vertices.push_back(center + radius * normalized(p));
        }
        return it->second;
    };
    for (const auto& f : faces) {
        const int a = f[0], b = f[1], c = f[2];
        for (int j = 0; j < s; ++j)
            for (int k = 0; j + k < s; ++k) {
                const int i = s - j - k;
                m.triangles.push_back({vertex(a, b, c, i, j, k), vertex(a, b, c, i - 1, j + 1, k), vertex(a, b, c, i - 1, j, k + 1)});
                if (j + k + 1 < s)
                    m.triangles.push_back({vertex(a, b, c, i - 1, j + 1, k), vertex(a, b, c, i - 2, j + 1, k + 1),
                                           vertex(a, b, c, i - 1, j, k + 1)});
            }
    }
    return m;
}

SurfaceMesh make_box_mesh(const Vec3& lo, const Vec3& hi, int n) {
    if (n < 1 || !(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw std::invalid_argument("box mesh: hi > lo and n >= 1");
    SurfaceMesh m;
    std::map<std::array<int, 3>, uint32_t> index;  // integer lattice coordinates 0..n
    auto vertex = [&](int x, int y, int z) {
        auto [it, fresh] = index.try_emplace({x, y, z}, uint32_t(m.vertices.size()));
        if (fresh)
            m.vertices.push_back({lo.x + (hi.x - lo.x) * x / n, lo.y + (hi.y - lo.y) * y / n, lo.z + (hi.z - lo.z) * z / n});
        return it->second;
    };
    // Each face: axis `ax` fixed at 0 or n; (u, v) the other two axes in right-handed order so
    // that u x v points along +ax; the face at 0 is wound the other way.
    for (int ax = 0; ax < 3; ++ax)
        for (int side : {0, n}) {
            const int u = (ax + 1) % 3, v = (ax + 2) % 3;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    auto P = [&](int a, int b) {
                        std::array<int, 3> c{};
                        c[ax] = side, c[u] = a, c[v] = b;
                        return vertex(c[0], c[1], c[2]);
                    };
                    const uint32_t p00 = P(i, j), p10 = P(i + 1, j), p11 = P(i + 1, j + 1), p01 = P(i, j + 1);
                    if (side == n) {
                        m.triangles.push_back({p00, p10, p11});
                        m.triangles.push_back({p00, p11, p01});
                    } else {
                        m.triangles.push_back({p00, p11, p10});
                        m.triangles.push_back({p00, p01, p11});
                    }
                }
        }
    return m;
}

SurfaceMesh make_cylinder_mesh(double radius, double height, int segments, int rings, double z0) {
    if (!(radius > 0 && height > 0) || segments < 3 || rings < 1)
        throw std::invalid_argument("cylinder mesh: radius, height > 0, segments >= 3, rings >= 1");
    SurfaceMesh m;
    for (int k = 0; k <= rings; ++k)
        for (int c = 0; c < segments; ++c) {
            const double a = 2.0 * std::numbers::pi * c / segments;
            m.vertices.push_back({radius * std::cos(a), radius * std::sin(a), z0 + height * k / rings});
        }
    auto at = [&](int k, int c) { return uint32_t(k * segments + (c % segments)); };
    for (int k = 0; k < rings; ++k)
        for (int c = 0; c < segments; ++c) {
            m.triangles.push_back({at(k, c), at(k, c + 1), at(k + 1, c + 1)});
            m.triangles.push_back({at(k, c), at(k + 1, c + 1), at(k + 1, c)});
        }
    const uint32_t bottom = uint32_t(m.vertices.size()), top = bottom + 1;
    m.vertices.push_back({0, 0, z0});
    m.vertices.push_back({0, 0, z0 + height});
    for (int c = 0; c < segments; ++c) {
        m.triangles.push_back({bottom, at(0, c + 1), at(0, c)});
        m.triangles.push_back({top, at(rings, c), at(rings, c + 1)});
    }
    return m;
}

SurfaceMesh make_torus(double major, double minor, int n_major, int n_minor) {
    if (!(major > minor && minor > 0) || n_major < 3 || n_minor < 3)
        throw std::invalid_argument("torus mesh: major > minor > 0, at least 3 segments each way");
    SurfaceMesh m;
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j) {
            const double u = 2.0 * std::numbers::pi * i / n_major, v = 2.0 * std::numbers::pi * j / n_minor;
            const double r = major + minor * std::cos(v);
            m.vertices.push_back({r * std::cos(u), r * std::sin(u), minor * std::sin(v)});
        }
    auto at = [&](int i, int j) { return uint32_t((i % n_major) * n_minor + (j % n_minor)); };
    // d/du x d/dv points out of the tube.
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

}  // namespace dem
