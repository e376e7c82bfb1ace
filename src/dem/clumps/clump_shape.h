// A clump's shape: overlapping spheres rigidly joined, and the mass properties of their union
// (volume, centre, principal moments and axes), so that a grain of any shape is a rigid body
// whose members carry the contacts.
//
// The union's integrals (volume, first and second moments) are the spheres' closed forms minus
// what the overlaps count twice, integral of (n(x) - 1)+ over the points covered n(x) >= 2 times:
// each overlapping pair's lens in closed form (two spherical caps), less the points covered
// three or more times, counted too often by the pairs, integrated by the midpoint rule on a grid
// of `cells_per_radius` cells per smallest radius in the boxes of the overlapping triples. So
// members that overlap at most pairwise (spheres, dimers, trimers) are exact to round-off; the
// others carry the midpoint rule's error on the triple regions only (the built-in tetrahedron
// and pellet at the default 40 cells: within 1e-5 and 5e-5 of the volume and moments of a grid
// 8 times finer; tests/unit/test_clump_shape.cpp checks 1e-4 against a grid 4 times finer).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "dem/clumps/quaternion.h"
#include "dem/core/vec3.h"

namespace dem {

struct ClumpMember {
    Vec3 center;    // [m] in the clump's frame
    double radius;  // [m]
};

struct ClumpShape {
    // Members in the principal frame: the centre of mass at the origin, the axes along the
    // principal axes of inertia (moments in ascending order, a right-handed frame).
    std::vector<ClumpMember> members;
    double volume = 0.0;            // [m^3] of the union
    Vec3 inertia_per_density;       // [m^5] principal moments divided by the density
    double bounding_radius = 0.0;   // [m] farthest member surface from the centre of mass
    double min_radius = 0.0;        // [m] smallest member
    Quat template_to_principal;     // the template frame's orientation in the principal frame
    Vec3 template_center;           // [m] the centre of mass in the template's frame
};

// Mass properties of the union of `members` (the template, in any frame). Throws
// std::invalid_argument naming the member for a radius <= 0 or a non-finite number, and for an
// empty template or one whose members do not all touch one another (a clump is one body).
ClumpShape make_clump_shape(const std::vector<ClumpMember>& members, int cells_per_radius = 40);

// The same shape scaled by s > 0 (lengths s, volume s^3, moments s^5).
ClumpShape scaled(const ClumpShape& shape, double s);
// The same shape scaled to the volume of a sphere of radius r > 0 [m] (r becomes its
// volume-equivalent radius).
ClumpShape scaled_to_radius(const ClumpShape& shape, double r);

// The built-in shapes, made of unit spheres and then scaled to the volume of a sphere of radius
// r_equivalent [m]:
//   "sphere"       one sphere
//   "dimer"        two spheres, centres one radius apart (aspect ratio 1.5)
//   "trimer"       three spheres in a line, centres one radius apart (aspect 2: a rice grain)
//   "tetrahedron"  four spheres at the corners of a regular tetrahedron of edge 1.5 radii
//   "pellet"       a short cylinder: a centre sphere and a ring of six, one radius from it
//                  (a disc about twice as wide as it is thick)
// Throws std::invalid_argument naming the shape and the choices for an unknown name.
ClumpShape builtin_clump_shape(const std::string& name, double r_equivalent);
// The names above, in that order.
const std::vector<std::string>& builtin_clump_shapes();

// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations: eigenvalues in
// ascending order and the eigenvectors as the columns of a right-handed rotation. (Written here
// rather than taken from a library: one 3x3 case, and the project has no linear-algebra
// dependency.)
struct SymmetricEigen3 {
    std::array<double, 3> values;
    std::array<Vec3, 3> vectors;  // vectors[k]: the unit eigenvector of values[k]
};
SymmetricEigen3 symmetric_eigen(const std::array<std::array<double, 3>, 3>& a);

}  // namespace dem
