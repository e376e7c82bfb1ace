// The fill's sites and grains (device/fill_sites.h).
#include "vpp/device/fill_sites.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene/config.h"
#include "vpp/device/fill_geometry.h"
#include "vpp/device/pour.h"
#include "vpp/device/scene.h"
#include "vpp/membrane/foil.h"

namespace vpp::device_detail {

using dem::Vec3;

FillLattice fill_lattice(const DeviceDef& d) {
    const double r = d.grain_radius, h = d.lattice_spacing * r;
    // cubic: a cell of edge h, one site; fcc: a cell of edge h sqrt(2), four sites (nearest
    // neighbours h apart along face diagonals).
    const bool fcc = d.lattice == "fcc";
    FillLattice L;
    L.edge = fcc ? h * std::numbers::sqrt2 : h;
    L.basis = fcc ? std::vector<Vec3>{{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}} : std::vector<Vec3>{{0, 0, 0}};
    // A jitter of up to 0.9 (h - 2r) / 2 per axis (fcc: / sqrt 2, as its neighbours lie along face
    // diagonals): loose, random, never overlapping.
    L.jitter = 0.5 * (h - 2.0 * r) * 0.9 / (fcc ? std::numbers::sqrt2 : 1.0);
    return L;
}

bool clear_of_tools(const std::vector<dem::SurfaceMesh>& tool_surfaces, const Vec3& p, double r) {
    for (const dem::SurfaceMesh& ts : tool_surfaces)
        if (inside(ts, p) || distance_to_surface(ts, p) < r + 0.1 * r) return false;
    return true;
}

namespace {

// The lattice fill's sites: inside `surface`, the clearance `clear` [m] from it and clear of the
// tools, in lattice order (z, y, x, basis).
std::vector<Vec3> lattice_sites(const DeviceDef& d, const FillLattice& L, const dem::SurfaceMesh& surface,
                                const std::vector<dem::SurfaceMesh>& tool_surfaces, double clear) {
    const double r = d.grain_radius, h = d.lattice_spacing * r, a = L.edge;
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3& v : surface.vertices) {
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    // The lattice's first site: half a spacing in from the surface's bounding box (cubic); fcc:
    // at the clearance (and a hundredth of a radius), so that a box is filled up to its faces
    // on its low sides (and on its high sides too where its edges are 2 clear + 0.01 r + a
    // multiple of h / sqrt 2).
    const double off = d.lattice == "fcc" ? (clear + 0.01 * r) / a : 0.5 * h / a;
    const int nx = int((hi.x - lo.x) / a) + 1, ny = int((hi.y - lo.y) / a) + 1, nz = int((hi.z - lo.z) / a) + 1;
    std::vector<Vec3> sites;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (const Vec3& b : L.basis) {
                    const Vec3 p = lo + a * Vec3{i + off + b.x, j + off + b.y, k + off + b.z};
                    if (!inside(surface, p) || distance_to_surface(surface, p) < clear) continue;
                    if (clear_of_tools(tool_surfaces, p, r)) sites.push_back(p);
                }
    return sites;
}

}  // namespace

void add_grains(DeviceScene& scene, const dem::SurfaceMesh& surface, const std::vector<dem::SurfaceMesh>& tool_surfaces) {
    const DeviceDef& d = scene.def;
    const double r = d.grain_radius;
    // The grains' surfaces clear the membrane particles' (their centres sit on the surface) by a
    // tenth of a radius, and the tools'.
    const double clear = r + d.membrane.foil.particle_radius + 0.1 * r;
    const FillLattice L = fill_lattice(d);
    std::vector<Vec3> sites = scene.pour ? pour_sites(d, scene.opening, L, tool_surfaces)
                                         : lattice_sites(d, L, surface, tool_surfaces, clear);
    if (sites.empty())
        throw cfg::ConfigError("config key 'grains.radius' = " + cfg::number_text(r) +
                               ": no grain fits inside the membrane (a clearance of " + cfg::number_text(clear) +
                               " m from it is needed)");
    // Lowest first (poured), lattice order within a layer; n of them (the pour's column: its own).
    if (!scene.pour) {
        const std::size_t n = std::max<std::size_t>(1, std::size_t(std::llround(d.fill * double(sites.size()))));
        std::stable_sort(sites.begin(), sites.end(), [](const Vec3& a, const Vec3& b) { return a.z < b.z; });
        sites.resize(std::min(n, sites.size()));
    }
    uint64_t rng = 0x5eed0000ull + d.seed;
    dem::SphereDef s;
    s.radius = r;
    s.material = scene.grain_mat;
    s.mask = kGrainMask;
    dem::World& world = scene.world;
    world.reserve(world.particles.size() + sites.size());
    for (const Vec3& p : sites) {
        const double jit = L.jitter;
        const Vec3 j{(2 * uniform(rng) - 1) * jit, (2 * uniform(rng) - 1) * jit, (2 * uniform(rng) - 1) * jit};
        s.position = p + j;
        world.add_sphere(s);
    }
}

}  // namespace vpp::device_detail
