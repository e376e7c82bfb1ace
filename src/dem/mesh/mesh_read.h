// Reading a closed surface from a file into an indexed triangle mesh: STL (binary or ASCII)
// and Wavefront OBJ ('v' and 'f' lines; polygons are fan-triangulated, everything else is
// ignored). Corners closer than a tolerance are welded into one vertex, so an STL's triangle
// soup gets the connectivity the checks (dem/mesh/mesh_checks.h) and the membrane need.
//
// Unlike dem::read_stl (walls), nothing is skipped here: a zero-area triangle is kept so that
// the checks can refuse the mesh and name the defect instead of silently repairing it.
#pragma once

#include <string>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/mesh/surface_mesh.h"

namespace dem {

struct MeshReadOptions {
    double scale = 1.0;        // [-] factor on the file's coordinates (1e-3 for a file in mm)
    // [-] corners closer than weld * (bounding-box diagonal) become one vertex; relative so a
    // file in mm and one in m weld alike. STL stores floats (7 digits), hence 1e-6 and not less.
    double weld = 1e-6;
};

// Reads `path` by its extension (.stl, .obj; case-insensitive). Throws std::runtime_error naming
// the file when it is missing, unreadable, malformed or holds no triangle.
SurfaceMesh read_surface_mesh(const std::string& path, const MeshReadOptions& opt = {});

// Corners of a triangle soup (3 per triangle) welded within `tolerance` [m] into an indexed
// mesh; triangle order and winding are kept. A triangle whose corners weld together stays (with
// repeated indices) for the checks to report.
SurfaceMesh weld_triangles(const std::vector<Vec3>& corners, double tolerance);

// Writes an ASCII STL (17 significant digits) or, for a path ending in .obj, an OBJ; for tests
// and for exporting a membrane's triangulation. Throws std::runtime_error naming the file.
void write_surface_mesh(const std::string& path, const SurfaceMesh& m);

}  // namespace dem
