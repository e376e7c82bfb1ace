// The pour's opening, column and strike-off (device/pour.h).
#include "vpp/device/pour.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "scene/config.h"
#include "vpp/device/fill_geometry.h"
#include "vpp/device/scene.h"
#include "vpp/membrane/foil.h"

namespace vpp::device_detail {

using dem::Vec3;

PourOpening open_membrane(const DeviceDef& d, dem::World& w, const Membrane& m) {
    const double r = d.grain_radius, rf = d.membrane.foil.particle_radius;
    const double clear = r + rf + 0.1 * r;  // as the lattice's
    const std::vector<Vec3>& pos = w.particles.pos;
    double z_top = -1e300, z_bottom = 1e300;
    for (uint32_t i : m.particles) {
        z_top = std::max(z_top, pos[i].z);
        z_bottom = std::min(z_bottom, pos[i].z);
    }
    const std::string key = "config key 'grains.opening_height' = " + cfg::number_text(d.opening_height);
    auto mm = [](double v) {  // [m], three digits: a message's lengths
        char b[32];
        std::snprintf(b, sizeof b, "%.3g", v);
        return std::string(b);
    };
    if (d.opening_height >= z_top - z_bottom)
        throw cfg::ConfigError(key + ": must be less than the membrane's height, " + mm(z_top - z_bottom) +
                               " m (its particles' centres from the lowest to the top): the opening is a part of its top");
    PourOpening o;
    o.z_seal = z_top - d.opening_height;
    double sx = 0, sy = 0;
    for (uint32_t i : m.particles)
        if (pos[i].z >= o.z_seal) {
            o.particles.push_back(i);
            sx += pos[i].x;
            sy += pos[i].y;
        }
    o.axis_x = sx / double(o.particles.size());
    o.axis_y = sy / double(o.particles.size());
    // The aperture: the nearest membrane particle to the axis, of those in the band a grain
    // diameter and a membrane particle's below the seal plane (the rim the grains pass).
    double ra = 1e300;
    for (uint32_t i : m.particles)
        if (pos[i].z < o.z_seal && pos[i].z >= o.z_seal - 2.0 * (r + rf))
            ra = std::min(ra, std::hypot(pos[i].x - o.axis_x, pos[i].y - o.axis_y));
    if (ra == 1e300)  // no membrane below the opening: it would be the whole membrane
        throw cfg::ConfigError(key + ": leaves no membrane within " + mm(2.0 * (r + rf)) +
                               " m below the opening's edge (the rim the grains pass); a smaller opening_height is needed");
    // A grain passes the rim when the aperture, clear of the membrane particles, is wider than a
    // grain's diameter and a tenth of its radius.
    if (!(ra - rf >= 2.1 * r))
        throw cfg::ConfigError(key + ": the opening's radius clear of the membrane particles is " +
                               mm(std::max(0.0, ra - rf)) + " m, less than a grain's diameter plus a tenth of its radius (" +
                               mm(2.1 * r) + " m): no room for a grain to pass; a larger opening_height (less than the "
                               "membrane's height, " + mm(z_top - z_bottom) + " m) or smaller grains are needed");
    o.column_radius = ra - clear;
    // Until the seal the grains pass through the opening; the rest of the membrane touches it.
    for (uint32_t i : m.particles) w.particles.mask[i] = kFoilMask | kMaskOpening;
    for (uint32_t i : o.particles) w.particles.mask[i] = kMaskOpening;
    return o;
}

std::vector<Vec3> pour_sites(const DeviceDef& d, const PourOpening& o, const FillLattice& L,
                             const std::vector<dem::SurfaceMesh>& tool_surfaces) {
    const double r = d.grain_radius, rf = d.membrane.foil.particle_radius;
    const double clear = r + rf + 0.1 * r;
    const double a = L.edge, jit = L.jitter;
    // Sites above the seal plane by the clearance and the jitter: no membrane particle but the
    // opening's (which the grains pass through) lies there, so no grain starts in contact. The
    // column's radius keeps the jittered grains the clearance inside the rim.
    const double z0 = o.z_seal + clear + jit * std::numbers::sqrt2;
    const double rc = std::max(0.0, o.column_radius - jit * std::numbers::sqrt2);
    const int n = int(rc / a) + 1;
    const std::size_t want = std::size_t(d.pour_count);
    std::vector<Vec3> sites;
    int empty_rows = 0;
    for (int k = 0; sites.size() < want; ++k) {
        const std::size_t before = sites.size();
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i)
                for (const Vec3& b : L.basis) {
                    const Vec3 p{o.axis_x + a * (i + b.x), o.axis_y + a * (j + b.y), z0 + a * (k + b.z)};
                    if (std::hypot(p.x - o.axis_x, p.y - o.axis_y) > rc) continue;
                    if (clear_of_tools(tool_surfaces, p, r)) sites.push_back(p);
                }
        empty_rows = sites.size() == before ? empty_rows + 1 : 0;
        if (empty_rows > 100)
            throw cfg::ConfigError("config key 'grains.pour_count' = " + std::to_string(d.pour_count) +
                                   ": the column above the opening has room for " + std::to_string(sites.size()) +
                                   " grains only (a tool fills it)");
    }
    // Lowest first, lattice order within a layer.
    std::stable_sort(sites.begin(), sites.end(), [](const Vec3& p, const Vec3& q) { return p.z < q.z; });
    sites.resize(want);
    return sites;
}

std::size_t strike_off(DeviceScene& scene) {
    const dem::Particles& p = scene.world.particles;
    const std::vector<uint32_t>& opening = scene.opening.particles;
    std::vector<uint32_t> out;
    for (uint32_t i = scene.first_grain; i < scene.end_grain; ++i) {
        if (!scene.active_grain(i)) continue;
        // Outside the membrane that the seal closes (above the opening, or spilled beside the bag).
        bool off = !inside_membrane(scene.membrane, p.pos, p.pos[i]);
        // Overlapping an opening particle: its contact would start deep, with a kick.
        for (std::size_t k = 0; k < opening.size() && !off; ++k)
            off = norm(p.pos[i] - p.pos[opening[k]]) < p.radius[i] + p.radius[opening[k]];
        if (off) out.push_back(i);
    }
    for (uint32_t i : out) scene.retire_grain(i);
    for (uint32_t i : scene.membrane.particles) scene.world.particles.mask[i] = kFoilMask;
    // The pairs of the opening and the grains become candidates, the retired grains' contacts go:
    // the next step's broad phase rebuilds the lists from the masks (ContactSet::reattach).
    scene.world.invalidate_candidates();
    return out.size();
}

}  // namespace vpp::device_detail
