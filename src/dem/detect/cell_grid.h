// Broad phase: a uniform cell grid built by counting sort (deterministic, maps onto a GPU
// sort and scan), used to list candidate pairs closer than the sum of radii plus a skin.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"

namespace dem {

struct CellGrid {
    Vec3 origin;                        // [m] corner of cell (0,0,0)
    double cell = 1.0;                  // [m] edge length
    std::array<int64_t, 3> dims{1, 1, 1};
    std::vector<uint32_t> start;        // CSR: cell -> range in `items`, size ncells+1
    std::vector<uint32_t> items;        // particle indices sorted by cell, then by index

    int64_t ncells() const { return dims[0] * dims[1] * dims[2]; }
    std::array<int64_t, 3> coords(const Vec3& p) const;
    int64_t index(const std::array<int64_t, 3>& c) const {
        return (c[2] * dims[1] + c[1]) * dims[0] + c[0];
    }

    // Bin `pos` into cells of at least `min_cell` [m]; the cell grows if the box would need
    // more than `max_cells` cells (a tall falling column must not allocate a huge grid).
    void build(const std::vector<Vec3>& pos, double min_cell, int64_t max_cells);
};

}  // namespace dem
