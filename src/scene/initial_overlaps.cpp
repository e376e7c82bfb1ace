#include "scene/initial_overlaps.h"

#include <algorithm>
#include <cmath>

#include "dem/detect/geometry.h"

namespace scene {

using dem::Vec3;

namespace {

// Integer cells of side h over a box; keys of three 21-bit coordinates.
struct Cells {
    Vec3 lo;
    double h = 1.0;
    int64_t n[3] = {1, 1, 1};

    // Clamped as a double first: a body far outside the spheres' box (a wall at 1e100, found by
    // fuzzing) would overflow the conversion to an integer, which is undefined behaviour.
    int64_t coord(double x, int k) const {
        const double q = std::floor((x - lo[k]) / h);
        if (!(q > 0.0)) return 0;  // below the box, or NaN
        return q >= double(n[k] - 1) ? n[k] - 1 : int64_t(q);
    }
    uint64_t key(int64_t i, int64_t j, int64_t k) const { return (uint64_t(i) << 42) | (uint64_t(j) << 21) | uint64_t(k); }
    // Cells touched by the box [a, b]; -1 when more than `limit`.
    int64_t span(const Vec3& a, const Vec3& b, int64_t limit) const {
        int64_t c = 1;
        for (int k = 0; k < 3; ++k) {
            c *= coord(b[k], k) - coord(a[k], k) + 1;
            if (c > limit) return -1;
        }
        return c;
    }
};

constexpr int64_t kMaxCellsPerBody = 4096;  // a body touching more cells is tested against all spheres

Cells make_cells(const dem::Particles& p) {
    Cells c;
    const std::size_t n = p.size();
    Vec3 lo = p.pos[0], hi = p.pos[0];
    std::vector<double> r(p.radius.begin(), p.radius.end());
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], p.pos[i][k] - p.radius[i]);
            hi[k] = std::max(hi[k], p.pos[i][k] + p.radius[i]);
        }
    std::nth_element(r.begin(), r.begin() + long(n / 2), r.end());
    c.lo = lo;
    c.h = 2.0 * r[n / 2];
    for (int k = 0; k < 3; ++k) c.h = std::max(c.h, (hi[k] - lo[k]) / double(1 << 20));  // keys fit 21 bits
    for (int k = 0; k < 3; ++k) c.n[k] = std::max<int64_t>(1, int64_t(std::floor((hi[k] - lo[k]) / c.h)) + 1);
    return c;
}

void consider(OverlapReport& rep, const Overlap& o) {
    ++rep.count;
    const Overlap& w = rep.worst;
    if (rep.count == 1 || o.fraction > w.fraction ||
        (o.fraction == w.fraction && (o.a < w.a || (o.a == w.a && o.b < w.b))))
        rep.worst = o;
}

// owner: per particle its clump or -1 (nullptr: no clumps); one clump's members overlap by design.
bool interacts(const dem::Particles& p, const int32_t* owner, uint32_t i, uint32_t j) {
    if (owner && owner[i] >= 0 && owner[i] == owner[j]) return false;
    return (p.mask[i] & p.mask[j]) && (dem::moves(p, i) || dem::moves(p, j));
}

void test_pair(const dem::Particles& p, const int32_t* owner, uint32_t i, uint32_t j, double tolerance,
               OverlapReport& rep) {
    if (!interacts(p, owner, i, j)) return;
    const double ov = p.radius[i] + p.radius[j] - norm(p.pos[j] - p.pos[i]);
    const double rmin = std::min(p.radius[i], p.radius[j]);
    if (ov > tolerance * rmin) consider(rep, {std::min(i, j), std::max(i, j), false, ov, ov / rmin});
}

// (cell key, sphere) for every cell each sphere's box touches; big spheres apart.
void bin_spheres(const dem::Particles& p, const Cells& c, std::vector<std::pair<uint64_t, uint32_t>>& items,
                 std::vector<uint32_t>& big) {
    for (uint32_t i = 0; i < uint32_t(p.size()); ++i) {
        const Vec3 r{p.radius[i], p.radius[i], p.radius[i]};
        const Vec3 a = p.pos[i] - r, b = p.pos[i] + r;
        if (c.span(a, b, kMaxCellsPerBody) < 0) {
            big.push_back(i);
            continue;
        }
        for (int64_t x = c.coord(a.x, 0); x <= c.coord(b.x, 0); ++x)
            for (int64_t y = c.coord(a.y, 1); y <= c.coord(b.y, 1); ++y)
                for (int64_t z = c.coord(a.z, 2); z <= c.coord(b.z, 2); ++z) items.push_back({c.key(x, y, z), i});
    }
    std::sort(items.begin(), items.end());
}

}  // namespace

OverlapReport sphere_overlaps(const dem::World& w, double tolerance) {
    OverlapReport rep;
    const dem::Particles& p = w.particles;
    const int32_t* owner = w.clumps().owner.empty() ? nullptr : w.clumps().owner.data();
    if (p.size() < 2) return rep;
    const Cells c = make_cells(p);
    std::vector<std::pair<uint64_t, uint32_t>> items;
    std::vector<uint32_t> big;
    bin_spheres(p, c, items, big);
    for (std::size_t s = 0; s < items.size();) {
        std::size_t e = s;
        while (e < items.size() && items[e].first == items[s].first) ++e;
        for (std::size_t u = s; u < e; ++u)
            for (std::size_t v = u + 1; v < e; ++v) {
                const uint32_t i = items[u].second, j = items[v].second;
                // Test the pair only in the cell holding the low corner of the boxes' overlap.
                Vec3 corner;
                bool disjoint = false;
                for (int k = 0; k < 3; ++k) {
                    corner[k] = std::max(p.pos[i][k] - p.radius[i], p.pos[j][k] - p.radius[j]);
                    disjoint = disjoint || corner[k] > std::min(p.pos[i][k] + p.radius[i], p.pos[j][k] + p.radius[j]);
                }
                if (disjoint || c.key(c.coord(corner.x, 0), c.coord(corner.y, 1), c.coord(corner.z, 2)) != items[s].first)
                    continue;
                test_pair(p, owner, i, j, tolerance, rep);
            }
        s = e;
    }
    // Big spheres against everything (each big-big pair once).
    std::vector<uint8_t> is_big(p.size(), 0);
    for (uint32_t b : big) is_big[b] = 1;
    for (uint32_t b : big)
        for (uint32_t j = 0; j < uint32_t(p.size()); ++j)
            if (j != b && (!is_big[j] || j > b)) test_pair(p, owner, b, j, tolerance, rep);
    return rep;
}

OverlapReport wall_overlaps(const dem::World& w, double tolerance) {
    OverlapReport rep;
    const dem::Particles& p = w.particles;
    const uint32_t n = uint32_t(p.size());
    auto touches_walls = [&](uint32_t i) { return !(p.flags[i] & dem::kFixed); };  // fixed: no wall contacts
    for (uint32_t k = 0; k < uint32_t(w.planes.size()); ++k) {
        const dem::Plane& pl = w.planes[k];
        const Vec3 nrm = normalized(pl.normal), pt = pl.point + pl.motion.displacement(0.0);
        for (uint32_t i = 0; i < n; ++i) {
            if (!(pl.mask & p.mask[i]) || !touches_walls(i)) continue;
            const double s = dot(p.pos[i] - pt, nrm);
            const double ov = p.radius[i] - (pl.one_sided ? s : std::abs(s));
            if (ov > tolerance * p.radius[i]) consider(rep, {i, k, true, ov, ov / p.radius[i]});
        }
    }
    if (w.facets.empty() || n == 0) return rep;
    const Cells c = make_cells(p);
    std::vector<std::pair<uint64_t, uint32_t>> items;
    std::vector<uint32_t> big;
    bin_spheres(p, c, items, big);
    std::vector<uint32_t> seen(n, UINT32_MAX);  // facet that last tested sphere i
    const uint32_t nplanes = uint32_t(w.planes.size());
    for (uint32_t f = 0; f < uint32_t(w.facets.size()); ++f) {
        const dem::Facet& fc = w.facets[f];
        std::array<Vec3, 3> v = fc.vertices;
        for (Vec3& x : v) x += fc.motion.displacement(0.0);
        auto test = [&](uint32_t i) {
            if (seen[i] == f) return;
            seen[i] = f;
            if (!(fc.mask & p.mask[i]) || !touches_walls(i)) return;
            dem::ContactGeom g;
            if (!dem::sphere_facet(p.pos[i], p.radius[i], v, fc.one_sided, g)) return;
            if (g.overlap > tolerance * p.radius[i]) consider(rep, {i, nplanes + f, true, g.overlap, g.overlap / p.radius[i]});
        };
        Vec3 a = v[0], b = v[0];
        for (const Vec3& x : v)
            for (int k = 0; k < 3; ++k) {
                a[k] = std::min(a[k], x[k]);
                b[k] = std::max(b[k], x[k]);
            }
        for (uint32_t i : big) test(i);
        if (c.span(a, b, kMaxCellsPerBody) < 0) {  // a facet across many cells: every sphere
            for (uint32_t i = 0; i < n; ++i) test(i);
            continue;
        }
        // A sphere overlapping the facet has its box in a cell of the facet's box.
        for (int64_t x = c.coord(a.x, 0); x <= c.coord(b.x, 0); ++x)
            for (int64_t y = c.coord(a.y, 1); y <= c.coord(b.y, 1); ++y)
                for (int64_t z = c.coord(a.z, 2); z <= c.coord(b.z, 2); ++z) {
                    const uint64_t key = c.key(x, y, z);
                    auto it = std::lower_bound(items.begin(), items.end(), std::pair<uint64_t, uint32_t>{key, 0});
                    for (; it != items.end() && it->first == key; ++it) test(it->second);
                }
    }
    return rep;
}

}  // namespace scene
