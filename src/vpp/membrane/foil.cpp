#include "vpp/membrane/foil.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "dem/detect/cell_grid.h"

namespace vpp {

using dem::Vec3;

std::vector<uint32_t> FoilLattice::row(int k) const {
    std::vector<uint32_t> out;
    for (int c = 0; c < cols; ++c)
        if (at(k, c) >= 0) out.push_back(uint32_t(at(k, c)));
    return out;
}

std::vector<uint32_t> FoilLattice::column(int c) const {
    std::vector<uint32_t> out;
    for (int k = 0; k < rows; ++k)
        if (at(k, c) >= 0) out.push_back(uint32_t(at(k, c)));
    return out;
}

uint32_t add_foil_material(dem::World& w, const FoilDef& f) {
    dem::Material m;
    m.name = "foil";
    m.density = f.density;
    m.young = particle_modulus(f);
    m.stiffness_ratio = f.stiffness_ratio;
    m.friction = f.friction;
    m.restitution = 1.0;
    return w.add_material(m);
}

namespace {

bool vacant(int k, int c) { return (k % 2 == 1) && (c % 2 == 1); }

// Places particles at the given site positions and bonds chain neighbours. The sites of
// neighbouring columns are column_pitch [m] apart (2 r_f but on a cylinder at its exact radius).
FoilLattice place(dem::World& w, const FoilDef& f, int rows, int cols, bool closed,
                  const std::function<Vec3(int, int)>& site_pos, double column_pitch) {
    FoilLattice L;
    L.rows = rows;
    L.cols = cols;
    L.closed = closed;
    L.spacing = 2.0 * f.particle_radius;
    L.column_pitch = column_pitch;
    L.material = add_foil_material(w, f);
    L.site.assign(std::size_t(rows) * cols, -1);
    for (int k = 0; k < rows; ++k)
        for (int c = 0; c < cols; ++c) {
            if (vacant(k, c)) continue;
            dem::SphereDef d;
            d.position = site_pos(k, c);
            d.radius = f.particle_radius;
            d.material = L.material;
            d.mask = kFoilMask;
            d.flags = kFoil;
            const bool inter = (k % 2 == 0) && (c % 2 == 0);
            if (inter) d.flags |= kIntersection;
            const uint32_t id = w.add_sphere(d);
            L.site[std::size_t(k) * cols + c] = int32_t(id);
            L.particles.push_back(id);
            if (inter) L.intersections.push_back(id);
        }
    // The square grid (every pitch 2 r_f): the paper's bonds, rest length 2 r_f. Otherwise each
    // bond rests at its sites' distance (unstressed as built) with the bar rule's stiffness.
    const double kn_row = lattice_bond_kn(f, L, LatticeBond{.along_row = true});
    const double kn_col = lattice_bond_kn(f, L, LatticeBond{.along_row = false});
    const double rest = column_pitch == L.spacing ? L.spacing : -1.0;  // -1: the distance as placed
    for (int k = 0; k < rows; ++k)
        for (int c = 0; c < cols; ++c) {
            const int32_t a = L.at(k, c);
            if (a < 0) continue;
            // Along the row (even rows are full chains); wraps around on a cylinder.
            if (k % 2 == 0 && (c + 1 < cols || closed)) {
                const int32_t b = L.at(k, (c + 1) % cols);
                if (b >= 0)
                    L.bonds.push_back({w.add_bond(uint32_t(a), uint32_t(b), kn_row, f.stiffness_ratio * kn_row, rest), k, c, true});
            }
            // Along the column (even columns are full chains).
            if (c % 2 == 0 && k + 1 < rows) {
                const int32_t b = L.at(k + 1, c);
                if (b >= 0)
                    L.bonds.push_back({w.add_bond(uint32_t(a), uint32_t(b), kn_col, f.stiffness_ratio * kn_col, L.spacing), k, c, false});
            }
        }
    return L;
}

}  // namespace

FoilLattice build_strip(dem::World& w, const FoilDef& f, int rows, int cols) {
    if (rows < 1 || cols < 2) throw std::invalid_argument("a foil strip needs at least 1 x 2 sites");
    const double h = 2.0 * f.particle_radius;
    return place(w, f, rows, cols, false, [h](int k, int c) { return Vec3{c * h, k * h, 0.0}; }, h);
}

int choose_columns(double radius, double r_f) {
    // Radius of the circle through n sites with chord 2 r_f: r_f / sin(pi / n).
    auto rad = [r_f](int n) { return r_f / std::sin(std::numbers::pi / n); };
    int best = 4;
    for (int n = 4; n < 1000000; n += 2) {
        if (std::abs(rad(n) - radius) < std::abs(rad(best) - radius)) best = n;
        if (rad(n) > radius) break;
    }
    return best;
}

int choose_rows(double height, double r_f) {
    // The odd count nearest height / (2 r_f) + 1: both end rows are then full rings.
    const double gaps = height / (2.0 * r_f);
    return std::max(3, 2 * int(std::lround(gaps / 2.0)) + 1);
}

FoilLattice build_cylinder(dem::World& w, const FoilDef& f, double radius, double height, double z0,
                           bool exact_radius) {
    if (!(radius > 2.0 * f.particle_radius)) throw std::invalid_argument("foil cylinder radius too small");
    const int cols = choose_columns(radius, f.particle_radius);
    const int rows = choose_rows(height, f.particle_radius);
    // The site circle: the one of chord 2 r_f for that count, or the radius asked for.
    const double R = exact_radius ? radius : f.particle_radius / std::sin(std::numbers::pi / cols);
    const double h = 2.0 * f.particle_radius;
    const double pitch = exact_radius ? 2.0 * R * std::sin(std::numbers::pi / cols) : h;
    FoilLattice L = place(w, f, rows, cols, true, [&](int k, int c) {
        const double a = 2.0 * std::numbers::pi * c / cols;
        return Vec3{R * std::cos(a), R * std::sin(a), z0 + k * h};
    }, pitch);
    L.radius = R;
    return L;
}

double lattice_bond_kn(const FoilDef& f, const FoilLattice& L, const LatticeBond& b) {
    if (L.column_pitch == L.spacing) return bond_normal_stiffness(f);
    return b.along_row ? lattice_bond_stiffness(f, L.column_pitch, L.spacing)
                       : lattice_bond_stiffness(f, L.spacing, L.column_pitch);
}

std::vector<dem::PressureNode> cylinder_pressure_nodes(const FoilLattice& L) {
    std::vector<dem::PressureNode> out;
    for (int k = 2; k + 2 < L.rows; k += 2)
        for (int c = 0; c < L.cols; c += 2) {
            dem::PressureNode q;
            q.node = uint32_t(L.at(k, c));
            q.ring = {uint32_t(L.at(k, (c + 1) % L.cols)), uint32_t(L.at(k + 1, c)),
                      uint32_t(L.at(k, (c + L.cols - 1) % L.cols)), uint32_t(L.at(k - 1, c))};
            out.push_back(q);
        }
    return out;
}

double enclosed_volume(const FoilLattice& L, const std::vector<Vec3>& pos) {
    // Signed volume of a closed triangulated surface: sum of a . (b x c) / 6 over triangles.
    double six_v = 0.0;
    auto tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) { six_v += dot(a, cross(b, c)); };
    auto P = [&](int k, int c) { return pos[uint32_t(L.at(k, c % L.cols))]; };
    for (int k = 0; k + 2 < L.rows; k += 2)
        for (int c = 0; c < L.cols; ++c) {
            // Quad (k,c) (k,c+1) (k+2,c+1) (k+2,c), outward for counter-clockwise columns.
            tri(P(k, c), P(k, c + 1), P(k + 2, c + 1));
            tri(P(k, c), P(k + 2, c + 1), P(k + 2, c));
        }
    // Caps: fans from each end ring's centroid.
    for (int k : {0, L.rows - 1}) {
        Vec3 m;
        for (int c = 0; c < L.cols; ++c) m += P(k, c);
        m /= double(L.cols);
        for (int c = 0; c < L.cols; ++c) {
            if (k == 0) tri(m, P(k, c + 1), P(k, c));
            else tri(m, P(k, c), P(k, c + 1));
        }
    }
    return six_v / 6.0;
}

double min_nonbonded_gap(const FoilLattice& L, const dem::World& w) {
    const auto& p = w.particles;
    const double rf = 0.5 * L.spacing;
    std::vector<Vec3> pos;
    pos.reserve(L.particles.size());
    for (uint32_t i : L.particles) pos.push_back(p.pos[i]);
    dem::CellGrid g;
    g.build(pos, 4.0 * rf, std::max<int64_t>(int64_t(8 * pos.size()), 4096));
    // Bonded partners of each foil particle (up to four).
    std::vector<std::vector<uint32_t>> partners(p.size());
    const auto& b = w.bonds();
    for (std::size_t k = 0; k < b.size(); ++k) {
        partners[b.i[k]].push_back(b.j[k]);
        partners[b.j[k]].push_back(b.i[k]);
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < pos.size(); ++a) {
        const auto c = g.coords(pos[a]);
        g.for_each_neighbour(c, [&](uint32_t bidx) {
            if (bidx <= a) return;
            const uint32_t i = L.particles[a], j = L.particles[bidx];
            const auto& pi = partners[i];
            if (std::find(pi.begin(), pi.end(), j) != pi.end()) return;
            const double gap = norm(pos[bidx] - pos[a]) - p.radius[i] - p.radius[j];
            best = std::min(best, gap / rf);
        });
    }
    return best;
}

}  // namespace vpp
