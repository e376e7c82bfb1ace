// The foil's membrane tensions (membrane/foil_tension.h): the virial of the bonds of a cylinder
// lattice's free band.
#include "vpp/membrane/foil_tension.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace vpp {

using dem::Vec3;

FoilTension cylinder_tension(const FoilLattice& L, const dem::World& w) {
    if (!L.closed || L.rows < 5) throw std::invalid_argument("cylinder_tension: needs a cylinder lattice of at least 5 rows");
    const auto& p = w.particles.pos;
    // The band: rows 1 .. rows - 2, its mean radius and height.
    double r_sum = 0.0, z_lo = 0.0, z_hi = 0.0;
    std::size_t n = 0;
    for (int k = 1; k + 1 < L.rows; ++k)
        for (uint32_t i : L.row(k)) {
            r_sum += std::hypot(p[i].x, p[i].y);
            ++n;
        }
    const std::vector<uint32_t> lo = L.row(1), hi = L.row(L.rows - 2);
    for (uint32_t i : lo) z_lo += p[i].z;
    for (uint32_t i : hi) z_hi += p[i].z;
    const double R = r_sum / double(n), h = z_hi / double(hi.size()) - z_lo / double(lo.size());
    const double area = 2.0 * std::numbers::pi * R * h;  // [m^2]
    const dem::BondList& b = w.bonds();
    double hoop = 0.0, axial = 0.0;  // [N m]
    for (const LatticeBond& lb : L.bonds) {
        const bool in_band = lb.along_row ? (lb.k >= 2 && lb.k <= L.rows - 3) : (lb.k >= 1 && lb.k <= L.rows - 3);
        if (!in_band) continue;
        const Vec3 l = p[b.j[lb.index]] - p[b.i[lb.index]];
        const Vec3 tension = -b.force[lb.index];  // the force on j is the pull towards i
        if (lb.along_row) {
            const Vec3 mid = 0.5 * (p[b.j[lb.index]] + p[b.i[lb.index]]);
            const double rm = std::hypot(mid.x, mid.y);
            const Vec3 t{-mid.y / rm, mid.x / rm, 0.0};
            hoop += dot(tension, t) * dot(l, t);
        } else {
            axial += tension.z * l.z;
        }
    }
    return {hoop / area, axial / area};
}

}  // namespace vpp
