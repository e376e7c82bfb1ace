// An indexed triangle mesh of a surface (vertices shared by index, not repeated per triangle)
// and the integrals over it that the membrane and its checks need.
//
// Triangles wind counter-clockwise seen from outside: the area vector
// (b - a) x (c - a) / 2 points out of the enclosed volume. Loose triangle soups (facets,
// STL) become indexed meshes by welding (dem/mesh/mesh_read.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"

namespace dem {

struct SurfaceMesh {
    std::vector<Vec3> vertices;                      // [m]
    std::vector<std::array<uint32_t, 3>> triangles;  // vertex indices, outward winding
};

// Area vector of triangle t [m^2]: (b - a) x (c - a) / 2, pointing out for outward winding.
inline Vec3 area_vector(const SurfaceMesh& m, std::size_t t) {
    const auto& [a, b, c] = m.triangles[t];
    return 0.5 * cross(m.vertices[b] - m.vertices[a], m.vertices[c] - m.vertices[a]);
}

// Total area [m^2].
double surface_area(const SurfaceMesh& m);

// Volume enclosed by a closed, consistently wound mesh [m^3], by the divergence theorem:
// sum over triangles of a . (b x c) / 6. Positive when the normals point out. Meaningless for
// an open mesh (it then depends on the origin).
double enclosed_volume(const SurfaceMesh& m);

// Winding number of a closed, consistently wound mesh about the point p [-]: the triangles' solid
// angles summed (van Oosterom and Strackee) over 4 pi; 1 inside an outward mesh, 0 outside, for
// any shape (a test of "inside" is > 1/2). O(triangles).
double winding_number(const SurfaceMesh& m, const Vec3& p);

// Undirected edges as (lo, hi) vertex pairs, sorted and unique.
std::vector<std::array<uint32_t, 2>> unique_edges(const SurfaceMesh& m);

}  // namespace dem
