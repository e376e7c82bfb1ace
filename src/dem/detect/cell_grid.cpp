#include "dem/detect/cell_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

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
    // A position that is not finite (an unstable step: a time step too large for the stiffest
    // spring) would size the grid from infinity, or, a NaN, escape min and max and land in a cell
    // by an undefined cast; say what happened instead. Checked per particle: NaN fails every
    // comparison, so the extent alone does not show it.
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const Vec3& p = pos[i];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
            throw SimulationUnstable("the simulation became unstable: particle " + std::to_string(i) +
                                     " has a position that is not a finite number (the explicit step diverged: a time "
                                     "step too large for the stiffest contact or bond)");
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    }
    if (pos.empty()) lo = hi = Vec3{};
    // A particle thrown out by a diverging step may still be finite but astronomically far (found
    // at 1e16 m: the cell count overflowed and failed as "cannot create std::vector larger than
    // max_size()"). No scene spans 1e12 of its cells along an axis: the same diagnosis, naming the
    // particle farthest from the others' median along that axis.
    constexpr double kMaxCellsPerAxis = 1e12;
    for (int d = 0; d < 3; ++d)
        if ((hi[d] - lo[d]) / min_cell > kMaxCellsPerAxis) {
            std::vector<double> x(pos.size());
            for (std::size_t i = 0; i < pos.size(); ++i) x[i] = pos[i][d];
            std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(x.size() / 2), x.end());
            const double median = x[x.size() / 2];
            std::size_t far = 0;
            for (std::size_t i = 1; i < pos.size(); ++i)
                if (std::abs(pos[i][d] - median) > std::abs(pos[far][d] - median)) far = i;
            char at[64];
            std::snprintf(at, sizeof at, "%.3g m", pos[far][d] - median);
            throw SimulationUnstable("the simulation became unstable: particle " + std::to_string(far) + " was thrown " +
                                     at + " away from the others along axis " + "xyz"[d] +
                                     " (the explicit step diverged: a time step too large for the stiffest contact or "
                                     "bond, or forces the damping no longer holds)");
        }
    cell = min_cell;
    for (;;) {
        double total = 1.0;  // in double: three axes of up to 1e12 cells each overflow an int64
        for (int d = 0; d < 3; ++d) {
            dims[d] = int64_t((hi[d] - lo[d]) / cell) + 1;
            total *= double(dims[d]);
        }
        if (total <= double(max_cells)) break;
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
