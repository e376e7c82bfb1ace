// Broad phase: a uniform cell grid built by counting sort (deterministic, maps onto a GPU
// sort and scan), used to list candidate pairs closer than the sum of radii plus a skin.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "dem/core/vec3.h"

namespace dem {

// Thrown when the particles' positions stop being finite numbers, or a particle is thrown
// astronomically far (a diverged step); the caller names the settings that size the step.
struct SimulationUnstable : std::runtime_error {
    using std::runtime_error::runtime_error;
};

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

    // Calls f(item) for every item in the 3x3x3 block of cells around cell `c` that lies inside
    // the grid, cell by cell (z, then y, then x), items in their stored order.
    template <class F>
    void for_each_neighbour(const std::array<int64_t, 3>& c, F&& f) const {
        for (int64_t z = std::max<int64_t>(c[2] - 1, 0); z <= std::min(c[2] + 1, dims[2] - 1); ++z)
            for (int64_t y = std::max<int64_t>(c[1] - 1, 0); y <= std::min(c[1] + 1, dims[1] - 1); ++y)
                for (int64_t x = std::max<int64_t>(c[0] - 1, 0); x <= std::min(c[0] + 1, dims[0] - 1); ++x) {
                    const int64_t cell = index({x, y, z});
                    for (uint32_t k = start[cell]; k < start[cell + 1]; ++k) f(items[k]);
                }
    }

    // Bin `pos` into cells of at least `min_cell` [m]; the cell grows if the box would need
    // more than `max_cells` cells (a tall falling column must not allocate a huge grid).
    void build(const std::vector<Vec3>& pos, double min_cell, int64_t max_cells);
};

}  // namespace dem
