// The seal between membrane and object (vpp/device/suction.h).
#include "vpp/device/suction.h"

#include <algorithm>
#include <cmath>

#include "dem/core/triangle.h"

namespace vpp {

using dem::Vec3;

SuctionSeal capture_seal(const dem::PressureFans& fans, const std::vector<Vec3>& pos, double radius,
                         const std::vector<dem::Facet>& object, const Vec3& u, const SuctionDef& d) {
    SuctionSeal s;
    s.u0 = u;
    if (object.empty() || fans.empty()) return s;
    // The object's box grown by a particle and the capture: only particles inside it can touch.
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const dem::Facet& f : object)
        for (const Vec3& v : f.vertices) {
            const Vec3 p = v + u;
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
        }
    const double reach = radius + d.capture;
    std::vector<int32_t> local(fans.node.size(), -1);  // fan index -> footprint index
    std::vector<int32_t> fan_of_particle;               // particle -> fan index (for the rings)
    uint32_t top = 0;
    for (uint32_t n : fans.node) top = std::max(top, n);
    for (uint32_t n : fans.ring) top = std::max(top, n);
    fan_of_particle.assign(std::size_t(top) + 1, -1);
    for (std::size_t k = 0; k < fans.node.size(); ++k) fan_of_particle[fans.node[k]] = int32_t(k);

    for (std::size_t k = 0; k < fans.node.size(); ++k) {
        const Vec3& x = pos[fans.node[k]];
        if (x.x < lo.x - reach || x.y < lo.y - reach || x.z < lo.z - reach || x.x > hi.x + reach || x.y > hi.y + reach ||
            x.z > hi.z + reach)
            continue;
        double best = 1e300;
        Vec3 closest, facet_normal;
        for (const dem::Facet& f : object) {
            const Vec3 a = f.vertices[0] + u, b = f.vertices[1] + u, c = f.vertices[2] + u;
            const Vec3 q = dem::closest_point_on_triangle(x, a, b, c);
            const double dist = norm(x - q);
            if (dist < best) {
                best = dist;
                closest = q;
                facet_normal = cross(b - a, c - a);
            }
        }
        if (best - radius > d.capture) continue;
        // The outward normal from the closest point to the particle's centre (on an edge or a
        // vertex, the facets' normals are ambiguous; the centre's direction is not); the facet's
        // own normal where the centre lies on the surface.
        Vec3 n = best > 1e-12 * radius ? (x - closest) / best : facet_normal / norm(facet_normal);
        local[k] = int32_t(s.particle.size());
        s.particle.push_back(fans.node[k]);
        s.normal.push_back(n);
        s.x0.push_back(x);
        s.area.push_back(norm(dem::fan_area(pos, fans, k)));
        s.gap0.push_back(best - radius);
    }
    const std::size_t m = s.particle.size();
    s.rim.assign(m, 0);
    s.air.resize(m);
    s.start.assign(1, 0);
    for (std::size_t k = 0, i = 0; k < fans.node.size(); ++k) {
        if (local[k] < 0) continue;
        for (uint32_t r = fans.start[k]; r < fans.start[k + 1]; ++r) {
            const int32_t f = fan_of_particle[fans.ring[r]];
            const int32_t j = f < 0 ? -1 : local[std::size_t(f)];
            if (j < 0)
                s.rim[i] = 1;  // a neighbour off the footprint (or off the fans: a clamped particle)
            else
                s.next.push_back(uint32_t(j));
        }
        s.start.push_back(uint32_t(s.next.size()));
        s.air[i] = d.ambient * s.area[i] * (d.gap + std::max(s.gap0[i], 0.0));
        ++i;
    }
    return s;
}

SuctionStep step_seal(SuctionSeal& s, const std::vector<Vec3>& pos, const Vec3& u, double dt, const SuctionDef& d,
                      std::vector<Vec3>& ext_force) {
    SuctionStep r;
    r.pressure_min = d.ambient;
    const std::size_t m = s.particle.size();
    const Vec3 shift = u - s.u0;
    std::vector<double> volume(m), gap(m);
    std::vector<uint8_t> open(m);
    for (std::size_t i = 0; i < m; ++i) {
        gap[i] = s.gap0[i] + dot(pos[s.particle[i]] - s.x0[i] - shift, s.normal[i]);
        // Open: off the surface by more than a hundredth of the film (a separation within the film's
        // roughness, or a rounding of the positions, does not open the seal).
        open[i] = gap[i] > 0.01 * d.gap;
        volume[i] = s.area[i] * (d.gap + std::max(gap[i], 0.0));
        ext_force[s.particle[i]] = Vec3{};
        r.open += open[i];
    }
    // The pockets: open particles connected through the one-rings, in footprint order (a
    // deterministic traversal: the same pockets and sums for any thread count).
    std::vector<uint8_t> seen(m, 0);
    std::vector<uint32_t> members, stack;
    const double pa2 = d.ambient * d.ambient;
    for (std::size_t first = 0; first < m; ++first) {
        if (!open[first] || seen[first]) continue;
        members.clear();
        stack.assign(1, uint32_t(first));
        seen[first] = 1;
        while (!stack.empty()) {
            const uint32_t i = stack.back();
            stack.pop_back();
            members.push_back(i);
            for (uint32_t e = s.start[i]; e < s.start[i + 1]; ++e) {
                const uint32_t j = s.next[e];
                if (open[j] && !seen[j]) {
                    seen[j] = 1;
                    stack.push_back(j);
                }
            }
        }
        std::sort(members.begin(), members.end());  // sums in footprint order
        double air = 0, v = 0, leak = 0;
        for (uint32_t i : members) {
            air += s.air[i];
            v += volume[i];
            if (s.rim[i]) leak += gap[i] * gap[i] * gap[i];  // sum of h^3 over the pocket's slits to the outside
        }
        // The leak: isothermal viscous flow through each open rim particle's slit (gap h, as wide
        // as it is long): d(pV)/dt = h^3 (p_amb^2 - p^2) / (24 mu) (plane Poiseuille flow of a
        // gas), explicit over the step and never past the ambient pressure.
        const double p_old = air / v;
        const double inflow = dt * leak * (pa2 - p_old * p_old) / (24.0 * d.viscosity);
        air = p_old < d.ambient ? std::min(air + inflow, d.ambient * v) : std::max(air + inflow, d.ambient * v);
        const double p = air / v;
        r.pressure_min = std::min(r.pressure_min, p);
        if (p >= d.ambient * (1.0 - 1e-9)) {
            r.leaked += members.size();
        } else {
            r.sealed += members.size();
            r.sealed_volume += v;
        }
        const bool below = p < d.ambient * (1.0 - 1e-9);  // a refilled pocket pulls nothing (not a rounding's 1e-16 N)
        for (uint32_t i : members) {
            s.air[i] = p * volume[i];
            if (!below) continue;
            r.sealed_area += s.area[i];
            const Vec3 f = s.normal[i] * ((d.ambient - p) * s.area[i]);
            ext_force[s.particle[i]] = -f;  // toward the object
            r.object_force += f;            // toward the particle
        }
    }
    return r;
}

}  // namespace vpp
