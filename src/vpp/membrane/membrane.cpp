#include "vpp/membrane/membrane.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "dem/io/checkpoint.h"
#include "dem/mesh/mesh_checks.h"
#include "dem/mesh/mesh_shapes.h"
#include "dem/mesh/remesh.h"

namespace vpp {

using dem::Vec3;

namespace {

uint64_t ekey(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// The one-ring of every vertex of a closed, consistently wound triangulation, counter-clockwise
// seen from outside (for triangle (v, x, y) the ring goes x -> y). CSR: start has n + 1 entries.
// `open`: the triangulation may have a boundary (a tube); a vertex on it has an open fan and gets
// an empty ring (nothing asks for it: boundary sites are never vacant nor loaded).
void rings(std::size_t n, const std::vector<std::array<uint32_t, 3>>& tris, std::vector<uint32_t>& start,
           std::vector<uint32_t>& ring, bool open = false) {
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> next(n);
    for (const auto& t : tris)
        for (int k = 0; k < 3; ++k) next[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
    start.assign(1, 0);
    ring.clear();
    for (std::size_t v = 0; v < n; ++v) {
        auto& nx = next[v];
        std::sort(nx.begin(), nx.end());
        bool on_boundary = false;
        if (open) {
            // Closed fan: every ring vertex is once a start and once an end of a triangle's edge.
            std::vector<uint32_t> a, b;
            for (const auto& [x, y] : nx) a.push_back(x), b.push_back(y);
            std::sort(b.begin(), b.end());
            on_boundary = a != b;  // a is sorted already (nx is)
        }
        if (!nx.empty() && !on_boundary) {
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

namespace {
std::vector<uint8_t> draw_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed,
                                    const std::vector<uint8_t>* eligible);
}  // namespace

std::vector<uint8_t> choose_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed) {
    return draw_vacancies(sites, fraction, seed, nullptr);
}

std::vector<uint8_t> choose_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed,
                                      const std::vector<uint8_t>& eligible) {
    if (eligible.size() != sites.vertices.size())
        throw std::invalid_argument("membrane: the eligible sites' mask has another size than the sites");
    return draw_vacancies(sites, fraction, seed, &eligible);
}

namespace {
std::vector<uint8_t> draw_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed,
                                    const std::vector<uint8_t>* eligible) {
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
    rings(n, sites.triangles, start, ring, eligible != nullptr);
    // Fisher-Yates with the engine's raw output (std::shuffle's use of it is not specified, so
    // the same seed would give other vacancies with another standard library).
    std::vector<uint32_t> order(n);
    for (uint32_t v = 0; v < n; ++v) order[v] = v;
    std::mt19937_64 rng(seed);
    for (std::size_t k = n; k > 1; --k) std::swap(order[k - 1], order[rng() % k]);
    std::vector<uint8_t> vacant(n, 0);
    std::size_t pool = n;  // the sites that may be vacant
    if (eligible) pool = std::size_t(std::count_if(eligible->begin(), eligible->end(), [](uint8_t e) { return e != 0; }));
    const std::size_t target = std::size_t(std::llround(fraction * double(pool)));
    std::size_t count = 0;
    for (uint32_t v : order) {
        if (count >= target) break;
        if (eligible && (!(*eligible)[v] || start[v] == start[v + 1])) continue;  // not eligible, or an open fan
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
}  // namespace

namespace {
void check_def(const MembraneDef& d) {
    const FoilDef& f = d.foil;
    if (!(f.particle_radius > 0) || !(f.young > 0) || !(f.thickness > 0) || !(f.density > 0))
        throw std::invalid_argument("membrane: foil radius, Young modulus, thickness and density must be > 0");
    if (!(d.stiffness_factor > 0)) throw std::invalid_argument("membrane: stiffness_factor must be > 0");
    if (!(d.prestrain >= 0 && d.prestrain < 1)) throw std::invalid_argument("membrane: prestrain must be in [0, 1)");
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
    if (d.vacancies && m.open()) {
        // The boundary's sites are held by the walls that close the surface: never vacant.
        std::vector<uint8_t> eligible(ns, 1);
        for (const auto& loop : m.boundary_sites)
            for (uint32_t s : loop) eligible[s] = 0;
        vacant = choose_vacancies(m.sites, d.vacancy_fraction, d.seed, eligible);
    } else if (d.vacancies) {
        vacant = choose_vacancies(m.sites, d.vacancy_fraction, d.seed);
    }

    m.material = add_foil_material(w, f);
    // One arm for every bond of the World (dem::BondList): the membrane's.
    w.set_bond_arm(f.bond_arm);
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
        const double area = edge_area[ekey(a, b)];
        const double kn = membrane_bond_stiffness(d, len, area);
        // Built stretched by the prestrain: the rest length is shorter than the site edge (kn from
        // the built length: the network's moduli per built area, as without it).
        m.bonds.push_back(w.add_bond(uint32_t(m.particle[a]), uint32_t(m.particle[b]), kn, f.stiffness_ratio * kn,
                                     len / (1.0 + d.prestrain)));
        m.bond_length.push_back(len);
        m.bond_area.push_back(area);
    }

    // The particles' closed triangulation: site triangles without vacancies, holes fan-filled.
    for (const auto& t : m.sites.triangles)
        if (!vacant[t[0]] && !vacant[t[1]] && !vacant[t[2]])
            m.triangles.push_back({uint32_t(m.particle[t[0]]), uint32_t(m.particle[t[1]]), uint32_t(m.particle[t[2]])});
    if (m.vacancies > 0) {
        std::vector<uint32_t> start, ring;
        rings(ns, m.sites.triangles, start, ring, m.open());
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
    for (const auto& loop : m.boundary_sites) {
        std::vector<uint32_t> ring;
        for (uint32_t s : loop) ring.push_back(uint32_t(m.particle[s]));
        m.boundary.push_back(std::move(ring));
    }
    // The particles' triangulation must bound the body as the sites did (holes filled well); an
    // open one closed over its boundary loops as enclosed_volume closes it.
    if (m.vacancies > 0 || m.open()) {
        // Only the membrane's particles are vertices of it: other particles of the World are
        // left out of the check through a compact copy.
        std::vector<int64_t> map(w.particles.pos.size(), -1);
        dem::SurfaceMesh c;
        for (uint32_t p : m.particles) map[p] = int64_t(c.vertices.size()), c.vertices.push_back(w.particles.pos[p]);
        for (const auto& t : m.triangles) c.triangles.push_back({uint32_t(map[t[0]]), uint32_t(map[t[1]]), uint32_t(map[t[2]])});
        for (const auto& loop : m.boundary) {
            Vec3 centre;
            for (uint32_t p : loop) centre += w.particles.pos[p];
            const uint32_t ci = uint32_t(c.vertices.size());
            c.vertices.push_back(centre / double(loop.size()));
            for (std::size_t k = 0; k < loop.size(); ++k)
                c.triangles.push_back({ci, uint32_t(map[loop[(k + 1) % loop.size()]]), uint32_t(map[loop[k]])});
        }
        dem::check_closed_surface(c, "membrane particles' triangulation");
    }
}

Membrane membrane_tube_sites(const MembraneDef& d, double radius, double height, double z0, int segments) {
    check_def(d);
    if (!(radius > 2.0 * d.foil.particle_radius) || !(height > 2.0 * d.foil.particle_radius) || segments < 8)
        throw std::invalid_argument("membrane tube: radius and height must exceed the foil particle's diameter, and "
                                    "segments be at least 8");
    const Membrane closed = membrane_sites(d, dem::make_cylinder_mesh(radius, height, segments, 1, z0));
    // The end discs: the remesher keeps their sites on the discs' planes (projected onto them)
    // and the rims' sites on the rims (feature lines), so a triangle with all three corners on
    // one end plane lies on a disc; the rest is the lateral surface.
    const double z1 = z0 + height, tol = 1e-9 * height;
    auto end_of = [&](const Vec3& p) { return std::abs(p.z - z0) <= tol ? 0 : std::abs(p.z - z1) <= tol ? 1 : -1; };
    const std::size_t ns = closed.sites.vertices.size();
    std::vector<int64_t> map(ns, -1);
    Membrane m;
    m.spacing = closed.spacing;
    m.min_edge = closed.min_edge, m.max_edge = closed.max_edge, m.mean_edge = closed.mean_edge;
    for (const auto& t : closed.sites.triangles) {
        const int e0 = end_of(closed.sites.vertices[t[0]]);
        if (e0 >= 0 && e0 == end_of(closed.sites.vertices[t[1]]) && e0 == end_of(closed.sites.vertices[t[2]])) continue;
        std::array<uint32_t, 3> nt{};
        for (int k = 0; k < 3; ++k) {
            if (map[t[k]] < 0) map[t[k]] = 0;  // used; numbered below in site order
            nt[k] = t[k];
        }
        m.sites.triangles.push_back(nt);
    }
    for (std::size_t s = 0; s < ns; ++s)
        if (map[s] >= 0) {
            map[s] = int64_t(m.sites.vertices.size());
            m.sites.vertices.push_back(closed.sites.vertices[s]);
            m.site_feature.push_back(closed.site_feature[s]);
        }
    for (auto& t : m.sites.triangles)
        for (uint32_t& v : t) v = uint32_t(map[v]);
    // Boundary: the directed edges of the kept triangles whose reverse is none of theirs.
    std::unordered_map<uint64_t, int> directed;
    for (const auto& t : m.sites.triangles)
        for (int k = 0; k < 3; ++k) directed[(uint64_t(t[k]) << 32) | t[(k + 1) % 3]] += 1;
    std::unordered_map<uint32_t, uint32_t> next;
    for (const auto& t : m.sites.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], b = t[(k + 1) % 3];
            if (directed.count((uint64_t(b) << 32) | a)) continue;
            if (next.count(a))
                throw std::logic_error("membrane tube: a rim site starts two boundary edges (the rim is not a loop)");
            next[a] = b;
        }
    // Loops in site order of their first site, every site of one loop on one rim.
    std::vector<uint8_t> seen(m.sites.vertices.size(), 0);
    std::vector<std::pair<int, std::vector<uint32_t>>> loops;
    for (uint32_t s = 0; s < m.sites.vertices.size(); ++s) {
        if (seen[s] || !next.count(s)) continue;
        std::vector<uint32_t> loop;
        const int end = end_of(m.sites.vertices[s]);
        for (uint32_t v = s; !seen[v]; v = next.at(v)) {
            if (end_of(m.sites.vertices[v]) != end || end < 0 || m.site_feature[v] == 0)
                throw std::logic_error("membrane tube: a boundary site off the rims (the remeshed discs did not separate)");
            seen[v] = 1;
            loop.push_back(v);
            if (!next.count(v)) throw std::logic_error("membrane tube: a rim's boundary does not close");
        }
        loops.push_back({end, std::move(loop)});
    }
    if (loops.size() != 2 || loops[0].first == loops[1].first)
        throw std::logic_error("membrane tube: the lateral surface's boundary is not two rims");
    if (loops[0].first == 1) std::swap(loops[0], loops[1]);
    for (auto& [end, loop] : loops) m.boundary_sites.push_back(std::move(loop));
    return m;
}

dem::PressureFans membrane_pressure_fans(const Membrane& m) {
    // Rings over the World's particle indices, then kept for the membrane's particles only.
    uint32_t n = 0;
    for (uint32_t p : m.particles) n = std::max(n, p + 1);
    std::vector<uint32_t> start, ring;
    rings(n, m.triangles, start, ring, m.open());
    dem::PressureFans f;
    f.start.push_back(0);
    for (uint32_t p : m.particles) {
        if (start[p] == start[p + 1]) continue;  // on an open membrane's boundary
        f.node.push_back(p);
        f.ring.insert(f.ring.end(), ring.begin() + start[p], ring.begin() + start[p + 1]);
        f.start.push_back(uint32_t(f.ring.size()));
    }
    return f;
}

double enclosed_volume(const Membrane& m, const std::vector<Vec3>& pos) {
    double six_v = 0.0;
    for (const auto& [a, b, c] : m.triangles) six_v += dot(pos[a], cross(pos[b], pos[c]));
    for (const auto& loop : m.boundary) {
        Vec3 centre;
        for (uint32_t p : loop) centre += pos[p];
        centre /= double(loop.size());
        for (std::size_t k = 0; k < loop.size(); ++k)
            six_v += dot(centre, cross(pos[loop[(k + 1) % loop.size()]], pos[loop[k]]));
    }
    return six_v / 6.0;
}

void save_checkpoint_without_fans(const std::string& path, dem::World& w, const std::string& blob) {
    dem::PressureFans fans;
    std::swap(fans, w.pressure.fans);
    try {
        dem::save_checkpoint(path, w, blob);
    } catch (...) {
        std::swap(fans, w.pressure.fans);
        throw;
    }
    std::swap(fans, w.pressure.fans);
}

}  // namespace vpp
