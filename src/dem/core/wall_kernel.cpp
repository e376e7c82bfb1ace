// The wall contacts' kernel (dem/core/kernels.h, wall_pairs): few contacts (caps, a funnel), so
// scalar code over the calling thread's blocks of slots, with the same contact law as the pair
// kernels and the energy terms summed per block in slot order.
#include <algorithm>

#include "dem/contact/linear_law.h"
#include "dem/core/kernels.h"
#include "dem/detect/geometry.h"

namespace dem::kernels {

namespace {

template <bool kEnergy> void wall_pairs_impl(const WallPairArgs& a) {
    const Particles& p = *a.p;
    ActiveContacts& ws = *a.c;
    const std::vector<Plane>& planes = *a.planes;
    const std::vector<Facet>& facets = *a.facets;
    const std::vector<Vec3>& plane_point = *a.plane_point;
    const std::vector<std::array<Vec3, 3>>& facet_now = *a.facet_now;
    const std::vector<Vec3>& wall_vel = *a.wall_vel;
    const double dt = a.dt;
    const uint32_t nplanes = uint32_t(planes.size());
    const int64_t ns = int64_t(ws.size());
    std::vector<uint32_t>& opened = *a.opened;
    opened.clear();
    for (const auto& [b0, b1] : *a.blocks)
    for (int64_t b = b0; b < b1; ++b) {
        double sum[kPairSums] = {};
        for (int64_t s = b * kBlock; s < std::min(ns, (b + 1) * kBlock); ++s) {
            if (ws.cand[s] == kNoSlot) continue;
            const uint32_t i = ws.i[s], w = ws.j[s];
            const ContactPhys& ph = ws.phys[s];
            ContactGeom g;
            const bool touch = w < nplanes
                                   ? sphere_plane(p.pos[i], p.radius[i], plane_point[w], planes[w].normal,
                                                  planes[w].one_sided, g)
                                   : sphere_facet(p.pos[i], p.radius[i], facet_now[w - nplanes],
                                                  facets[w - nplanes].one_sided, g);
            if (!touch) {
                if constexpr (kEnergy) {  // opened this step: the shear spring's energy is lost
                    const Vec3 n = ws.prev_normal[s];
                    const Vec3 vrel = (p.vel[i] + cross(p.angvel[i], n * -p.radius[i])) - wall_vel[w];
                    sum[kRelease] += shear_release_energy(ph.ks, ws.shear[s], vrel, dt);
                }
                ws.shear[s] = ws.prev_normal[s] = ws.force[s] = ws.torque2[s] = ws.fv[s] = Vec3{};
                opened.push_back(uint32_t(s));
                continue;
            }
            const Vec3& n = g.normal;  // from the wall to the sphere
            const Vec3 vrel = (p.vel[i] + cross(p.angvel[i], n * -p.radius[i])) - wall_vel[w];
            ContactEnergyLanes<double> e;
            V3<double> f;
            if (ph.mu == 0.0) {
                f = normal_contact_force_lanes<kEnergy>(ph.kn, ph.cn, lanes(n), g.overlap, lanes(vrel), dt, &e);
                ws.torque2[s] = Vec3{};
            } else {
                V3<double> fs = lanes(ws.shear[s]), prev = lanes(ws.prev_normal[s]);
                const double spin_n = 0.5 * dot(n, p.angvel[i]);
                f = linear_contact_force_lanes<kEnergy>(ph.kn, ph.ks, ph.mu, ph.cn, lanes(n), g.overlap, lanes(vrel),
                                                        spin_n, dt, fs, prev, &e);
                ws.shear[s] = vec3(fs);
                ws.prev_normal[s] = vec3(prev);
                ws.torque2[s] = cross(n, -vec3(f)) * g.arm2;
            }
            ws.force[s] = vec3(f);
            ws.point[s] = p.pos[i] - n * g.arm2;
            if constexpr (kEnergy) {
                sum[kElastic] += e.elastic;
                sum[kSlip] += e.slip;
                sum[kViscous] += e.viscous;
                ws.fv[s] = vec3(e.fv);
            }
        }
        if constexpr (kEnergy) std::copy(sum, sum + kPairSums, a.energy + b * kPairSums);
    }
}

}  // namespace

void wall_pairs(const WallPairArgs& a) {
    if (a.energy) wall_pairs_impl<true>(a);
    else wall_pairs_impl<false>(a);
}

}  // namespace dem::kernels
