// Legacy-format VTK (ASCII PolyData) frames that ParaView opens directly: particles as points
// with radius/velocity/id fields (use a Glyph filter with 'radius' as scale), walls as triangles.
#pragma once

#include <string>

#include "dem/world/world.h"

namespace dem {

// Writes particles of `world` to `path` (atomically); with_bonds adds the bonds as lines.
// `subset` (optional) restricts the output to those particle indices.
void write_particles_vtk(const std::string& path, const World& world, bool with_bonds = false,
                         const std::vector<uint32_t>* subset = nullptr);
// Writes the facets at their current position, and planes as squares of half-size `plane_size` [m].
void write_walls_vtk(const std::string& path, const World& world, double plane_size);

}  // namespace dem
