// Builders for common facet meshes (cylinders, funnels) and STL import/export.
// All builders return facets with only the vertices set; material, mask, one_sided and
// motion keep their defaults so the caller assigns them for the whole set at once.
#pragma once

#include <string>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/walls/wall.h"

namespace dem {

// Side surface of a vertical (z-axis) cylinder from base_center.z to base_center.z + height,
// approximated by `segments` flat quads of 2 triangles each (2*segments facets), vertices on
// the circle of `radius` (as Yade's geom.facetCylinder). Facet normals point toward the axis
// when inward_normals (particles inside, the usual container), away from it otherwise.
// base_center, radius, height in [m]; requires radius > 0, height > 0, segments >= 3
// (std::invalid_argument otherwise).
std::vector<Facet> make_cylinder_facets(const Vec3& base_center, double radius, double height,
                                        int segments, bool inward_normals = true);

// Side surface of a z-axis cone frustum: radius bottom_radius at bottom_center.z, top_radius
// at bottom_center.z + height, 2 triangles per segment (2*segments facets). Normals point
// into the funnel's interior when inward_normals. Lengths in [m]; requires both radii > 0
// (an open outlet; a closed apex would give degenerate triangles), height > 0, segments >= 3.
std::vector<Facet> make_funnel_facets(const Vec3& bottom_center, double bottom_radius,
                                      double top_radius, double height, int segments,
                                      bool inward_normals = true);

// Reads a binary or ASCII STL file; coordinates are multiplied by `scale` (e.g. 1e-3 for a
// file in [mm] to get [m]; must be finite and > 0). Vertex order is kept, so facet normals
// follow the file's winding (the stored STL normals are ignored: they are often wrong).
// Zero-area triangles are skipped. Throws std::runtime_error naming the path when the file
// is missing, truncated, malformed, has no triangles, or only degenerate ones.
std::vector<Facet> read_stl(const std::string& path, double scale = 1.0);

// Writes facets as an ASCII STL with round-trip precision (17 significant digits).
// Throws std::runtime_error naming the path if the file cannot be written.
void write_stl_ascii(const std::string& path, const std::vector<Facet>& facets);

}  // namespace dem
