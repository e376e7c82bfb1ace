#include "dem/detect/cell_grid.h"

#include <string>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dem {

std::array<int64_t, 3> CellGrid::coords(const Vec3& p) const {
    std::array<int64_t, 3> c;
    for (int d = 0; d < 3; ++d) {
        const int64_t k = int64_t(std::floor((p[d] - origin[d]) / cell));
        c[d] = std::clamp<int64_t>(k, 0, dims[d] - 1);
    }
    return c;
}

void CellGrid::build(const std::vector<Vec3>& pos, double min_cell, int64_t max_cells) {
    Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
            std::numeric_limits<double>::max()};
    Vec3 hi = -lo;
    for (const Vec3& p : pos)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    if (pos.empty()) lo = hi = Vec3{};
    // A position that is not finite (an unstable step: a time step too large for the stiffest
    // spring) would size the grid from NaN and fail as "cannot create std::vector larger than
    // max_size()"; say what happened instead.
    for (int d = 0; d < 3; ++d)
        if (!std::isfinite(hi[d] - lo[d])) {
            std::size_t bad = 0;
            while (bad < pos.size() && std::isfinite(pos[bad].x) && std::isfinite(pos[bad].y) && std::isfinite(pos[bad].z))
                ++bad;
            throw SimulationUnstable("the simulation became unstable: particle " + std::to_string(bad) +
                                     " has a position that is not a finite number (the explicit step diverged: a time "
                                     "step too large for the stiffest contact or bond)");
        }
    cell = min_cell;
    for (;;) {
        int64_t total = 1;
        for (int d = 0; d < 3; ++d) {
            dims[d] = int64_t((hi[d] - lo[d]) / cell) + 1;
            total *= dims[d];
        }
        if (total <= max_cells) break;
        cell *= 1.25;
    }
    origin = lo;
    const int64_t nc = ncells();
    start.assign(std::size_t(nc + 1), 0);
    std::vector<uint32_t> cell_of(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) {
        cell_of[i] = uint32_t(index(coords(pos[i])));
        ++start[cell_of[i] + 1];
    }
    for (int64_t c = 0; c < nc; ++c) start[c + 1] += start[c];
    items.resize(pos.size());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < pos.size(); ++i) items[fill[cell_of[i]]++] = uint32_t(i);
}

}  // namespace dem
