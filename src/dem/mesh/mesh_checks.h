// Checks that a triangle mesh bounds a solid: what a membrane (or any closed-surface
// integral) needs, each defect found and named rather than repaired, since a silent repair
// (dropping a sliver, flipping a triangle) changes the body the user meant.
//
// In the order they are tested (the first found is reported):
//   degenerate triangles   zero area (repeated corners, or collinear within 1e-12 relative)
//   open                   an edge used by one triangle only (a hole)
//   not a manifold         an edge used by more than two triangles, or a vertex whose
//                          triangles form more than one fan (two surfaces touching at a point)
//   inconsistent winding   an edge traversed twice in the same direction (some triangles flipped)
//   several surfaces       more than one connected piece
//   inverted               negative enclosed volume: the normals point inward
//   self-intersecting      two triangles that share no vertex intersect (a uniform grid of
//                          their bounding boxes limits the pairs tested: fast for 1e4-1e5 triangles)
#pragma once

#include <string>

#include "dem/mesh/mesh_read.h"
#include "dem/mesh/surface_mesh.h"

namespace dem {

// The first defect of `m`, described with the triangle, edge or vertex involved; empty when the
// mesh is a closed, outward-wound, 2-manifold, connected surface without self-intersection.
std::string find_mesh_defect(const SurfaceMesh& m);

// Whether two triangles (corners a0..a2 and b0..b2 [m]) intersect, touching included. Exact in
// the orientation signs up to round-off; coplanar pairs are tested in their common plane.
bool triangles_intersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1,
                         const Vec3& b2);

// Throws std::runtime_error "mesh 'name': <defect>" when find_mesh_defect finds one.
void check_closed_surface(const SurfaceMesh& m, const std::string& name);

// read_surface_mesh then check_closed_surface, naming the file.
SurfaceMesh read_closed_surface(const std::string& path, const MeshReadOptions& opt = {});

}  // namespace dem
