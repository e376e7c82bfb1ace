#include "vpp/membrane.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "dem/mesh/mesh_checks.h"
#include "dem/mesh/remesh.h"

namespace vpp {

using dem::Vec3;

namespace {

uint64_t ekey(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// The one-ring of every vertex of a closed, consistently wound triangulation, counter-clockwise
// seen from outside (for triangle (v, x, y) the ring goes x -> y). CSR: start has n + 1 entries.
void rings(std::size_t n, const std::vector<std::array<uint32_t, 3>>& tris, std::vector<uint32_t>& start,
           std::vector<uint32_t>& ring) {
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> next(n);
    for (const auto& t : tris)
        for (int k = 0; k < 3; ++k) next[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
    start.assign(1, 0);
    ring.clear();
    for (std::size_t v = 0; v < n; ++v) {
        auto& nx = next[v];
        std::sort(nx.begin(), nx.end());
        if (!nx.empty()) {
            uint32_t x = nx.front().first;
            for (std::size_t k = 0; k < nx.size(); ++k) {
                ring.push_back(x);
                const auto it = std::lower_bound(nx.begin(), nx.end(), std::pair<uint32_t, uint32_t>{x, 0});
                if (it == nx.end() || it->first != x) throw std::runtime_error("membrane: a vertex's triangles do not form a fan");
                x = it->second;
            }
        }
        start.push_back(uint32_t(ring.size()));
    }
}

// The ring vertex from which the hole left by vacant site v (its ring ring[b..e)) is filled by a
// fan: one whose triangles all face the way the site's own triangles did and whose diagonals
// are no edges already (that would make the membrane's triangulation non-manifold); the one
// with the best smallest angle-like quality (area / longest edge^2). -1 when none qualifies.
int hole_apex(const dem::SurfaceMesh& sites, const std::vector<uint32_t>& ring, uint32_t b, uint32_t e,
              const Vec3& normal, const std::vector<std::vector<uint32_t>>& nb) {
    const uint32_t k = e - b;
    int best = -1;
    double best_q = 0.0;
    auto P = [&](uint32_t i) { return sites.vertices[ring[b + i % k]]; };
    for (uint32_t a = 0; a < k; ++a) {
        double q = std::numeric_limits<double>::infinity();
        for (uint32_t i = 1; i + 1 < k && q > 0; ++i) {
            const Vec3 n = cross(P(a + i) - P(a), P(a + i + 1) - P(a));
            const double l2 = std::max({norm2(P(a + i) - P(a)), norm2(P(a + i + 1) - P(a)), norm2(P(a + i + 1) - P(a + i))});
            q = std::min(q, dot(n, normal) / (norm(normal) * l2));
            if (i >= 2) {
                const auto& na = nb[ring[b + a]];
                if (std::find(na.begin(), na.end(), ring[b + (a + i) % k]) != na.end()) q = 0;
            }
        }
        if (q > best_q) best_q = q, best = int(a);
    }
    return best;
}

Vec3 site_normal(const dem::SurfaceMesh& sites, const std::vector<uint32_t>& ring, uint32_t b, uint32_t e, uint32_t v) {
    Vec3 n;
    for (uint32_t i = b; i < e; ++i) n += cross(sites.vertices[ring[i]] - sites.vertices[v], sites.vertices[ring[i + 1 < e ? i + 1 : b]] - sites.vertices[v]);
    return n;
}

}  // namespace

double network_young(double kn, double a) { return 2.0 * std::sqrt(3.0) * kn * (1.0 + a) / (3.0 + a); }
double network_poisson(double a) { return (1.0 - a) / (3.0 + a); }
double network_biaxial(double kn) { return std::sqrt(3.0) * kn; }

double membrane_bond_stiffness(const MembraneDef& d, double length, double area) {
    const FoilDef& f = d.foil;
    if (d.stiffness == MembraneStiffness::PaperBar) {
        const double h = 2.0 * f.particle_radius;
        return d.stiffness_factor * particle_modulus(f) * h * h / length;
    }
    const double a = f.stiffness_ratio;
    const double c = (3.0 + a) / (3.0 * (1.0 + a));
    return d.stiffness_factor * c * f.young * f.thickness * area / (length * length);
}

std::vector<uint8_t> choose_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed) {
    // Every particle keeps at least 3 bonds: a site with only 2 left would hang on a hinge
    // across the surface (the bonds carry no moment), which the triangulation never needs. With
    // valence 6 this allows up to 1/3 vacancies, so the seeded random draw reaches 25%.
    constexpr int kMinBonds = 3;
    const std::size_t n = sites.vertices.size();
    std::vector<std::vector<uint32_t>> nb(n);
    for (const auto& [a, b] : dem::unique_edges(sites)) nb[a].push_back(b), nb[b].push_back(a);
    std::vector<int> degree(n);
    for (std::size_t v = 0; v < n; ++v) degree[v] = int(nb[v].size());
    std::vector<uint32_t> start, ring;
    rings(n, sites.triangles, start, ring);
    // Fisher-Yates with the engine's raw output (std::shuffle's use of it is not specified, so
    // the same seed would give other vacancies with another standard library).
    std::vector<uint32_t> order(n);
    for (uint32_t v = 0; v < n; ++v) order[v] = v;
    std::mt19937_64 rng(seed);
    for (std::size_t k = n; k > 1; --k) std::swap(order[k - 1], order[rng() % k]);
    std::vector<uint8_t> vacant(n, 0);
    const std::size_t target = std::size_t(std::llround(fraction * double(n)));
    std::size_t count = 0;
    for (uint32_t v : order) {
        if (count >= target) break;
        bool ok = true;
        for (uint32_t u : nb[v]) ok &= !vacant[u] && degree[u] - 1 >= kMinBonds;
        // Its hole must be fillable by a fan for the pressure and the volume.
        if (!ok || hole_apex(sites, ring, start[v], start[v + 1], site_normal(sites, ring, start[v], start[v + 1], v), nb) < 0)
            continue;
        vacant[v] = 1;
        for (uint32_t u : nb[v]) --degree[u];
        ++count;
    }
    return vacant;
}

namespace {
void check_def(const MembraneDef& d) {
    const FoilDef& f = d.foil;
    if (!(f.particle_radius > 0) || !(f.young > 0) || !(f.thickness > 0) || !(f.density > 0))
        throw std::invalid_argument("membrane: foil radius, Young modulus, thickness and density must be > 0");
    if (!(d.stiffness_factor > 0)) throw std::invalid_argument("membrane: stiffness_factor must be > 0");
    if (!(d.vacancy_fraction >= 0 && d.vacancy_fraction < 0.5))
        throw std::invalid_argument("membrane: vacancy_fraction must be in [0, 0.5)");
}
}  // namespace

Membrane membrane_sites(const MembraneDef& d, const dem::SurfaceMesh& surface) {
    check_def(d);
    dem::check_closed_surface(surface, "membrane surface");
    Membrane m;
    m.spacing = d.spacing > 0 ? d.spacing : 2.0 * d.foil.particle_radius;
    dem::RemeshOptions ro;
    ro.edge_length = m.spacing;
    ro.iterations = d.remesh_iterations;
    ro.feature_angle = d.feature_angle;
    dem::RemeshResult rr = dem::remesh_isotropic(surface, ro);
    // The remeshed surface must still bound the body (a collapse or flip gone wrong would show here).
    dem::check_closed_surface(rr.mesh, "membrane sites (remeshed surface)");
    m.sites = std::move(rr.mesh);
    m.site_feature = std::move(rr.feature);
    m.min_edge = rr.min_edge, m.max_edge = rr.max_edge, m.mean_edge = rr.mean_edge;
    return m;
}

Membrane build_membrane(dem::World& w, const MembraneDef& d, const dem::SurfaceMesh& surface) {
    Membrane m = membrane_sites(d, surface);
    place_membrane(w, d, m);
    return m;
}

void place_membrane(dem::World& w, const MembraneDef& d, Membrane& m) {
    check_def(d);
    const FoilDef& f = d.foil;
    if (!m.particles.empty()) throw std::invalid_argument("membrane: already placed (use a copy of membrane_sites' result)");
    const std::size_t ns = m.sites.vertices.size();
    std::vector<uint8_t> vacant(ns, 0);
    if (d.vacancies) vacant = choose_vacancies(m.sites, d.vacancy_fraction, d.seed);

    m.material = add_foil_material(w, f);
    m.particle.assign(ns, -1);
    for (std::size_t s = 0; s < ns; ++s) {
        if (vacant[s]) {
            ++m.vacancies;
            continue;
        }
        dem::SphereDef sd;
        sd.position = m.sites.vertices[s];
        sd.radius = f.particle_radius;
        sd.material = m.material;
        sd.mask = kFoilMask;
        sd.flags = kFoil;
        const uint32_t id = w.add_sphere(sd);
        m.particle[s] = int32_t(id);
        m.particles.push_back(id);
    }

    // Bonds on the site edges between particles; A_e from the sites' triangles.
    std::unordered_map<uint64_t, double> edge_area;
    for (std::size_t t = 0; t < m.sites.triangles.size(); ++t) {
        const double a = norm(dem::area_vector(m.sites, t));
        const auto& tri = m.sites.triangles[t];
        for (int k = 0; k < 3; ++k) edge_area[ekey(tri[k], tri[(k + 1) % 3])] += a;
    }
    for (const auto& [a, b] : dem::unique_edges(m.sites)) {
        if (vacant[a] || vacant[b]) continue;
        const double len = norm(m.sites.vertices[a] - m.sites.vertices[b]);
        const double kn = membrane_bond_stiffness(d, len, edge_area[ekey(a, b)]);
        m.bonds.push_back(w.add_bond(uint32_t(m.particle[a]), uint32_t(m.particle[b]), kn, f.stiffness_ratio * kn, len));
    }

    // The particles' closed triangulation: site triangles without vacancies, holes fan-filled.
    for (const auto& t : m.sites.triangles)
        if (!vacant[t[0]] && !vacant[t[1]] && !vacant[t[2]])
            m.triangles.push_back({uint32_t(m.particle[t[0]]), uint32_t(m.particle[t[1]]), uint32_t(m.particle[t[2]])});
    if (m.vacancies > 0) {
        std::vector<uint32_t> start, ring;
        rings(ns, m.sites.triangles, start, ring);
        std::vector<std::vector<uint32_t>> nb(ns);
        for (const auto& [a, b] : dem::unique_edges(m.sites)) nb[a].push_back(b), nb[b].push_back(a);
        for (uint32_t s = 0; s < ns; ++s) {
            if (!vacant[s]) continue;
            const uint32_t b = start[s], e = start[s + 1], k = e - b;
            const int a = hole_apex(m.sites, ring, b, e, site_normal(m.sites, ring, b, e, s), nb);
            if (a < 0) throw std::logic_error("membrane: a vacancy's hole cannot be filled");  // choose_vacancies checked it
            auto P = [&](uint32_t i) { return uint32_t(m.particle[ring[b + (uint32_t(a) + i) % k]]); };
            for (uint32_t i = 1; i + 1 < k; ++i) m.triangles.push_back({P(0), P(i), P(i + 1)});
        }
    }
    // The particles' triangulation must bound the body as the sites did (holes filled well).
    if (m.vacancies > 0) {
        // Only the membrane's particles are vertices of it: other particles of the World are
        // left out of the check through a compact copy.
        std::vector<int64_t> map(w.particles.pos.size(), -1);
        dem::SurfaceMesh c;
        for (uint32_t p : m.particles) map[p] = int64_t(c.vertices.size()), c.vertices.push_back(w.particles.pos[p]);
        for (const auto& t : m.triangles) c.triangles.push_back({uint32_t(map[t[0]]), uint32_t(map[t[1]]), uint32_t(map[t[2]])});
        dem::check_closed_surface(c, "membrane particles' triangulation");
    }
}

dem::PressureFans membrane_pressure_fans(const Membrane& m) {
    // Rings over the World's particle indices, then kept for the membrane's particles only.
    uint32_t n = 0;
    for (uint32_t p : m.particles) n = std::max(n, p + 1);
    std::vector<uint32_t> start, ring;
    rings(n, m.triangles, start, ring);
    dem::PressureFans f;
    f.start.push_back(0);
    for (uint32_t p : m.particles) {
        f.node.push_back(p);
        f.ring.insert(f.ring.end(), ring.begin() + start[p], ring.begin() + start[p + 1]);
        f.start.push_back(uint32_t(f.ring.size()));
    }
    return f;
}

double enclosed_volume(const Membrane& m, const std::vector<Vec3>& pos) {
    double six_v = 0.0;
    for (const auto& [a, b, c] : m.triangles) six_v += dot(pos[a], cross(pos[b], pos[c]));
    return six_v / 6.0;
}

}  // namespace vpp
