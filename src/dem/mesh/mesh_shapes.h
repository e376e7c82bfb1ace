// Closed triangle meshes of simple solids, outward wound: for tests, for the verification of
// the membrane against closed forms, and as ready-made membrane or tool shapes.
#pragma once

#include "dem/mesh/surface_mesh.h"

namespace dem {

// Sphere of `radius` [m] about `center`: an icosahedron whose triangles are split into
// `subdivisions`^2 (each edge into `subdivisions` parts, >= 1), vertices pushed onto the sphere.
// 20 s^2 triangles, 10 s^2 + 2 vertices.
SurfaceMesh make_icosphere(double radius, int subdivisions, const Vec3& center = {});

// Axis-aligned box from `lo` to `hi` [m], each face a grid of n x n squares (2 triangles each).
SurfaceMesh make_box_mesh(const Vec3& lo, const Vec3& hi, int n);

// Closed z-axis cylinder of `radius` and `height` [m] from z = z0: `segments` around, `rings`
// bands along z, flat caps as fans from their centres (the kind of cap an STL export writes).
SurfaceMesh make_cylinder_mesh(double radius, double height, int segments, int rings, double z0 = 0.0);

// Torus about the z axis: tube centre circle of radius `major`, tube radius `minor` [m]
// (major > minor > 0); `n_major` x `n_minor` quads of 2 triangles. Not convex, not star-shaped
// about any point, genus 1: the case that rules out projecting onto a hull or a sphere.
SurfaceMesh make_torus(double major, double minor, int n_major, int n_minor);

}  // namespace dem
