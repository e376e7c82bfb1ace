// Isotropic remeshing of a closed triangle mesh to a target edge length (Botsch and Kobbelt,
// "A remeshing approach to multiresolution modeling", 2004): repeated passes of
//   split edges longer than 4/3 L at their midpoints,
//   collapse edges shorter than 4/5 L,
//   flip edges towards valence 6,
//   move vertices tangentially to their neighbours' centroid and project them back onto
//   the input surface.
// The result's vertices lie on the input surface and its edges are close to L (typically
// within +-20%), whatever the input's triangles were (long slivers of an STL export, fans of a
// cap): the vertices become membrane particles and the edges their bonds.
//
// Sharp features are kept: input edges whose faces meet at more than `feature_angle` are
// feature lines, along which vertices only slide (and are projected onto the lines), and input
// vertices where feature lines end, branch or turn sharply are corners and never move. Without
// this a box would come out with rounded edges and a cylinder's rim would creep onto its side.
//
// Alternatives not taken: refining the input by subdivision alone keeps its bad triangles
// (a cap's fan stays a fan); Poisson-disk sampling then triangulating the samples needs a
// surface reconstruction that is not robust for thin or non-convex shapes; projecting onto a
// convex hull works for star-shaped bodies only.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/mesh/surface_mesh.h"

namespace dem {

struct RemeshOptions {
    double edge_length = 0.0;     // [m] target L (> 0)
    int iterations = 12;          // [-] split-collapse-flip-smooth passes
    double feature_angle = 35.0;  // [deg] dihedral above which an input edge is a feature line
    // Rescale the target once so that the mean edge (not only the range) is L: the site density
    // of a membrane then follows from its spacing, 2 / (sqrt(3) L^2).
    bool match_mean = true;
};

struct RemeshResult {
    SurfaceMesh mesh;
    // Per vertex: 0 on a smooth part of the surface, 1 on a feature line, 2 a corner.
    std::vector<uint8_t> feature;
    double min_edge = 0, max_edge = 0, mean_edge = 0;  // [m] of the result
};

// Remeshes a closed, outward-wound mesh (check it first: dem/mesh/mesh_checks.h). Throws
// std::invalid_argument when edge_length is not > 0.
RemeshResult remesh_isotropic(const SurfaceMesh& input, const RemeshOptions& opt);

}  // namespace dem
