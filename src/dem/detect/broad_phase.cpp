// The broad phase (dem/detect/broad_phase.h): candidate lists from a cell grid.
#include "dem/detect/broad_phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "dem/core/parallel.h"
#include "dem/detect/geometry.h"
#include "dem/detect/rebuild_rule.h"

namespace dem {

namespace {

// A gap [m] as float, rounded down (the candidate filter must never overestimate it).
float gap_down(double g) {
    float f = float(g);
    if (double(f) > g) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

// Facets are registered in every cell of a coarser grid (2 x 2 x 2 particle cells) that their box
// (grown by rmax + skin) touches, so a particle only has to look at its own coarse cell's list.
// Coarse because facets are often large (a cylinder wall of full height): in the particle grid
// their lists were among the largest arrays of a run.
struct FacetCells {
    std::array<int64_t, 3> dims{};      // coarse cells per axis
    std::vector<uint32_t> start, items;  // the facets of coarse cell c: items[start[c] .. start[c + 1])
    int64_t cell(int64_t x, int64_t y, int64_t z) const { return (z * dims[1] + y) * dims[0] + x; }
};

// The facets now (facet_now) in the coarse cells of `grid`, each facet's box grown by `grow` [m].
FacetCells facet_cells(const CellGrid& grid, const std::vector<Facet>& facets,
                       const std::vector<std::array<Vec3, 3>>& facet_now, double grow) {
    FacetCells fc;
    fc.dims = {(grid.dims[0] + 1) / 2, (grid.dims[1] + 1) / 2, (grid.dims[2] + 1) / 2};
    if (facets.empty()) return fc;
    fc.start.assign(std::size_t(fc.dims[0] * fc.dims[1] * fc.dims[2] + 1), 0);
    std::vector<std::array<int64_t, 6>> range(facets.size());
    std::vector<uint8_t> inside(facets.size(), 0);
    for (std::size_t f = 0; f < facets.size(); ++f) {
        Vec3 lo = facet_now[f][0], hi = lo;
        for (int v = 1; v < 3; ++v)
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], facet_now[f][v][d]);
                hi[d] = std::max(hi[d], facet_now[f][v][d]);
            }
        bool ok = true;
        for (int d = 0; d < 3; ++d) {
            const double a = (lo[d] - grow - grid.origin[d]) / grid.cell;
            const double b = (hi[d] + grow - grid.origin[d]) / grid.cell;
            if (b < 0.0 || a >= double(grid.dims[d])) ok = false;
            range[f][d] = std::clamp<int64_t>(int64_t(std::floor(a)), 0, grid.dims[d] - 1) / 2;
            range[f][d + 3] = std::clamp<int64_t>(int64_t(std::floor(b)), 0, grid.dims[d] - 1) / 2;
        }
        inside[f] = ok;
    }
    // Two passes over the facets' cells: count per cell, then fill.
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<uint32_t> fill;
        if (pass == 1) {
            for (std::size_t c = 0; c + 1 < fc.start.size(); ++c) fc.start[c + 1] += fc.start[c];
            fc.items.resize(fc.start.back());
            fill.assign(fc.start.begin(), fc.start.end() - 1);
        }
        for (std::size_t f = 0; f < facets.size(); ++f) {
            if (!inside[f]) continue;
            const auto& r = range[f];
            for (int64_t z = r[2]; z <= r[5]; ++z)
                for (int64_t y = r[1]; y <= r[4]; ++y)
                    for (int64_t x = r[0]; x <= r[3]; ++x) {
                        const int64_t c = fc.cell(x, y, z);
                        if (pass == 0) ++fc.start[c + 1];
                        else fc.items[fill[c]++] = uint32_t(f);
                    }
        }
    }
    return fc;
}

// What the next rebuild test measures from: the particles' positions (in float, with the bound
// of their rounding) and the walls' displacements at `time` [s]; no move since.
void keep_reference(BroadPhase& b, const Particles& p, const std::vector<Plane>& planes,
                    const std::vector<Facet>& facets, double time) {
    const std::size_t n = p.size();
    b.ref_pos.resize(n);
    double big = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 x = p.pos[i];
        b.ref_pos[i] = {float(x.x), float(x.y), float(x.z)};
        big = std::max({big, std::abs(x.x), std::abs(x.y), std::abs(x.z)});
    }
    // A float rounds a coordinate by at most 2^-24 of it (relative): |x - ref| <= |x - float
    // ref| + sqrt(3) 2^-24 max|x|; twice that for safety.
    b.ref_round = 2.0 * 1.7320508075688772 * big * 0x1p-24;
    b.wall_ref_disp.resize(planes.size() + facets.size());
    for (std::size_t k = 0; k < planes.size(); ++k) b.wall_ref_disp[k] = planes[k].motion.displacement(time);
    for (std::size_t k = 0; k < facets.size(); ++k)
        b.wall_ref_disp[planes.size() + k] = facets[k].motion.displacement(time);
    b.max_disp = b.wall_move = 0.0;
}

}  // namespace

bool BroadPhase::needs_rebuild(std::size_t n, const std::vector<Plane>& planes, const std::vector<Facet>& facets,
                               double time) {
    if (dirty || ref_pos.size() != n) return true;
    if (particles_past_skin(max_disp, skin)) return true;
    double move = 0.0;
    for (std::size_t k = 0; k < planes.size(); ++k)
        move = std::max(move, norm(planes[k].motion.displacement(time) - wall_ref_disp[k]));
    for (std::size_t k = 0; k < facets.size(); ++k)
        move = std::max(move, norm(facets[k].motion.displacement(time) - wall_ref_disp[planes.size() + k]));
    wall_move = move;
    return walls_past_skin(max_disp, wall_move, skin);
}

void BroadPhase::record_moves(double max_d2) { max_disp = max_disp_after(max_d2, ref_round); }

void BroadPhase::rebuild(const Scene& s, CandidateList& pp, CandidateList& pw) {
    const std::vector<Plane>& planes = *s.planes;
    const std::vector<Facet>& facets = *s.facets;
    const std::vector<Vec3>& plane_point = *s.plane_point;
    const std::vector<std::array<Vec3, 3>>& facet_now = *s.facet_now;
    const BondTables& bt = *s.bonds;
    const Particles& p = *s.p;
    const int32_t* owner = s.owner;
    const std::size_t n = p.size();
    skin = s.skin;
    const double rmax = n ? *std::max_element(p.radius.begin(), p.radius.end()) : 0.0;
    grid.build(p.pos, 2.0 * rmax + skin, std::max<int64_t>(int64_t(4 * n), 4096));

    const FacetCells fc = facet_cells(grid, facets, facet_now, rmax + skin);

    // The old lists go first; the live contacts find their pairs again through the stores' (i, j).
    pp.clear();
    pw.clear();
    pp.start.assign(n + 1, 0);
    pw.start.assign(n + 1, 0);
    const int nt = std::max(1, s.threads);
    const uint32_t nplanes = uint32_t(planes.size());
    // Particle i's candidates j > i, emit(j, gap) in the grid's order (not j's).
    const auto pair_row = [&](std::size_t i, auto&& emit) {
        const Vec3 xi = p.pos[i];
        const double ri = p.radius[i];
        grid.for_each_neighbour(grid.coords(xi), [&](uint32_t j) {
            // The distance first: it rejects most of the 27 cells' particles.
            const double reach = ri + p.radius[j] + skin;
            const double d2 = norm2(p.pos[j] - xi);
            if (j <= i || !(d2 < reach * reach) || !(p.mask[i] & p.mask[j])) return;
            if (!moves(p, i) && !moves(p, j)) return;
            if (owner && owner[i] >= 0 && owner[i] == owner[j]) return;
            for (uint32_t b = bt.start[i]; b < bt.start[i + 1]; ++b)
                if (bt.partner[b] == j) return;
            emit(j, gap_down(std::sqrt(d2) - (ri + p.radius[j])));
        });
    };
    // Particle i's wall candidates, emit(w, gap) in ascending w (planes, then facets).
    const auto wall_row = [&](std::size_t i, auto&& emit) {
        if (!moves(p, i) && !(p.flags[i] & kPrescribed)) return;  // fixed: no wall contacts
        const Vec3 xi = p.pos[i];
        const double ri = p.radius[i];
        for (uint32_t w = 0; w < nplanes; ++w) {
            if (!(planes[w].mask & p.mask[i])) continue;
            const double sd = dot(xi - plane_point[w], planes[w].normal);
            const double dist = planes[w].one_sided ? sd : std::abs(sd);
            if (dist < ri + skin) emit(w, gap_down(dist - ri));
        }
        if (facets.empty()) return;
        const auto c = grid.coords(xi);
        const int64_t cell = fc.cell(c[0] / 2, c[1] / 2, c[2] / 2);
        for (uint32_t k = fc.start[cell]; k < fc.start[cell + 1]; ++k) {
            const uint32_t f = fc.items[k];
            if (!(facets[f].mask & p.mask[i])) continue;
            const double reach = ri + skin;
            const double d2 = distance2_to_triangle(xi, facet_now[f]);
            if (d2 < reach * reach) emit(nplanes + f, gap_down(std::sqrt(d2) - ri));
        }
    };
    // Count, scan, fill: each particle's rows are counted, the counts summed into the rows' starts,
    // then each row written in place and sorted by partner (an insertion per entry: a row holds a
    // dozen). Threads take contiguous ranges of particles; no list is joined afterwards, and the
    // result does not depend on the thread count.
    s.team->run(nt, [&](int tid) {
        const auto [r0, r1] = thread_range(int64_t(n), tid, nt);
        for (std::size_t i = std::size_t(r0); i < std::size_t(r1); ++i) {
            uint32_t np = 0, nw = 0;
            pair_row(i, [&](uint32_t, float) { ++np; });
            wall_row(i, [&](uint32_t, float) { ++nw; });
            pp.start[i + 1] = np;
            pw.start[i + 1] = nw;
        }
    });
    for (CandidateList* cl : {&pp, &pw}) {
        for (std::size_t i = 0; i < n; ++i) cl->start[i + 1] += cl->start[i];
        cl->other.resize(cl->start[n]);
        cl->gap.resize(cl->start[n]);
    }
    s.team->run(nt, [&](int tid) {
        const auto [r0, r1] = thread_range(int64_t(n), tid, nt);
        for (std::size_t i = std::size_t(r0); i < std::size_t(r1); ++i) {
            uint32_t* const other = pp.other.data() + pp.start[i];
            float* const gap = pp.gap.data() + pp.start[i];
            uint32_t m = 0;
            pair_row(i, [&](uint32_t j, float g) {
                uint32_t e = m++;
                for (; e > 0 && other[e - 1] > j; --e) {
                    other[e] = other[e - 1];
                    gap[e] = gap[e - 1];
                }
                other[e] = j;
                gap[e] = g;
            });
            uint32_t e = pw.start[i];
            wall_row(i, [&](uint32_t w, float g) {
                pw.other[e] = w;
                pw.gap[e++] = g;
            });
        }
    });
    pp.slot.assign(pp.size(), kNoSlot);
    pw.slot.assign(pw.size(), kNoSlot);

    keep_reference(*this, p, planes, facets, s.time);
    dirty = false;
    ++rebuilds;
}

}  // namespace dem
