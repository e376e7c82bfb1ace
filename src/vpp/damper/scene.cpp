// The damper's scene (damper/scene.h): the foil built from the config, the pour of the grains
// into it and a funnel above it, the caps; the grains' and the foil's measures.
#include "vpp/damper/scene.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <stdexcept>

#include "dem/walls/facet_sets.h"

namespace vpp {

namespace damper_detail {

namespace {

// Grain positions: a jittered cubic lattice inside the foil and the funnel above it, filled
// from the bottom up, so the grains never overlap each other, the foil or the funnel.
// A re-fill (refill = true) places its grains the same way above z_floor (the top of the grains
// already in) in the funnel that is there, as many of n as fit, with its own random stream.
// The sites are sized for the largest grain r_max (a size distribution's; else grains.radius).
std::vector<Vec3> generate_grains(const Config& c, const FoilLattice& L, std::size_t n, double z_top,
                                  double funnel_top_radius, double& funnel_height, double r_max, double z_floor = 0.0,
                                  uint64_t stream = 0, bool refill = false) {
    const double rk = r_max, rf = c.foil.particle_radius;
    const double gap = 0.05 * rk;                // [m] clearance to every wall
    const double s = 2.0 * rk * 1.04;            // [m] lattice spacing
    const double r_in = L.radius - rf;           // [m] inner surface of the foil
    std::mt19937_64 rng(c.simulation.seed + stream * 0x9E3779B97F4A7C15ull);
    std::uniform_real_distribution<double> jit(-0.015 * rk, 0.015 * rk);
    // Funnel: cone from r_in at z_top to funnel_top_radius; grow it until the sites suffice.
    if (!refill) funnel_height = 2.0 * r_in;
    for (int attempt = 0; attempt < (refill ? 1 : 40); ++attempt, funnel_height *= refill ? 1.0 : 1.25) {
        std::vector<Vec3> sites;
        const double slope = (funnel_top_radius - r_in) / funnel_height;
        const double half_angle = std::atan(slope);
        const int nxy = int(funnel_top_radius / s) + 1;
        for (int kz = 0;; ++kz) {
            const double z = z_floor + rk + gap + kz * s;
            if (z > z_top + funnel_height - rk - gap) break;
            // Largest centre radius at this height: inside the foil or inside the cone (the
            // wall distance of a cone point is its radial distance times cos(half angle)).
            double rmax;
            if (z + rk <= z_top) rmax = r_in - rk - gap;
            else rmax = r_in + slope * std::max(0.0, z - rk - z_top) - (rk + gap) / std::cos(half_angle);
            // Within one grain radius above z_top the funnel bottom edge and the top ring meet.
            if (z + rk > z_top && z - rk < z_top) rmax = std::min(rmax, r_in - rk - gap);
            const double off = (kz % 2) ? 0.5 * s : 0.0;  // stagger layers
            for (int ix = -nxy; ix <= nxy; ++ix)
                for (int iy = -nxy; iy <= nxy; ++iy) {
                    const double x = ix * s + off, y = iy * s + off;
                    if (std::hypot(x, y) <= rmax) sites.push_back({x, y, z});
                }
            if (sites.size() >= n + n / 20) break;
        }
        if (sites.size() < n && !refill) continue;
        std::vector<Vec3> out(sites.begin(), sites.begin() + long(std::min(n, sites.size())));
        for (Vec3& p : out) p += Vec3{jit(rng), jit(rng), jit(rng)};
        return out;
    }
    throw std::runtime_error("could not place the grains in the foil and funnel");
}

}  // namespace

DamperScene::DamperScene(const Config& c) : config(c) {
    // A checkpoint's sample holds its radii; its sieve curve is read only when given (a re-fill
    // of a sample in the fill stage needs it, refill() says so).
    if (config.grains.radius_distribution != RadiusDistribution::Sieve || !config.grains.sieve_curve.empty())
        sizes = grain_sizes(config);
    else
        sizes.kind = RadiusDistribution::Sieve;
    // A checkpoint's clumps hold their shape; its template is read only when given (a re-fill
    // in the fill stage needs it).
    if (clumps() && (config.grains.shape != GrainShape::Template || !config.grains.clump_template.empty()))
        shape = grain_shape(config);
    build_foil();
}

void DamperScene::build_foil() {
    // Foil first: its particles are 0 .. n_f - 1 and its material index 0.
    world.params.gravity = {0, 0, -9.81};
    world.params.local_damping = config.simulation.local_damping;
    world.params.threads = config.simulation.threads;
    world.params.skin = config.simulation.skin;
    world.set_bond_arm(config.foil.bond_arm);
    if (mesh_foil()) {
        // The lattice's cylinder (its ring radius and height, which the paper's rules choose
        // from damper.radius and damper.height, or damper.radius itself with foil.exact_radius),
        // built by the membrane builder: the two foils differ in their network only.
        const double rf = config.foil.particle_radius;
        const double R = config.damper.foil_exact_radius
                             ? config.damper.radius
                             : rf / std::sin(std::numbers::pi / choose_columns(config.damper.radius, rf));
        const double H = (choose_rows(config.damper.height, rf) - 1) * 2.0 * rf;
        const MembraneDef d = membrane_def();
        membrane = membrane_tube_sites(d, R, H, 0.0);
        place_membrane(world, d, membrane);
        lattice = FoilLattice{};
        lattice.radius = R;
        lattice.spacing = 2.0 * rf;
        lattice.material = membrane.material;
        lattice.particles = membrane.particles;
        z_top = H;
        bottom_ring = membrane.boundary[0];
        top_ring = membrane.boundary[1];
        std::vector<uint8_t> ring(world.particles.size(), 0);
        for (uint32_t i : bottom_ring) ring[i] = 1;
        for (uint32_t i : top_ring) ring[i] = 1;
        free_foil.clear();
        for (uint32_t i : membrane.particles)
            if (!ring[i]) free_foil.push_back(i);
        return;
    }
    lattice = build_cylinder(world, config.foil, config.damper.radius, config.damper.height, 0.0,
                             config.damper.foil_exact_radius);
    z_top = (lattice.rows - 1) * lattice.spacing;
    top_ring = lattice.row(lattice.rows - 1);
    bottom_ring = lattice.row(0);
    free_foil.clear();
    for (int k = 1; k + 1 < lattice.rows; ++k)
        for (uint32_t i : lattice.row(k)) free_foil.push_back(i);
}

MembraneDef DamperScene::membrane_def() const {
    // The paper's foil (E_f, t_f, r_f, rho_f, ks/kn) on bonds of 2 r_f, with the paper's 25% of
    // vacancies drawn at random (the lattice's odd-odd pattern has no analogue on a
    // triangulation), seeded by the sample's seed, and the MatchFoil rule: E t = E_f t_f on the
    // full network, times 2.05, which restores the biaxial stiffness the vacancies halve
    // (measured strain ratio 2.04-2.08 over 3 seeds, docs/membrane.md).
    constexpr double kVacancyStiffening = 2.05;  // [-]
    MembraneDef d;
    d.foil = config.foil;
    d.stiffness = MembraneStiffness::MatchFoil;
    d.stiffness_factor = kVacancyStiffening;
    d.vacancies = true;
    d.vacancy_fraction = 0.25;
    d.seed = config.simulation.seed;
    return d;
}

double DamperScene::pour(std::size_t n) {
    // Materials in fixed order: grain (frictionless while filling), cap, funnel.
    dem::Material g{"grain", config.grains.density, config.grains.young, config.grains.stiffness_ratio, 0.0, 1.0};
    world.add_material(g);
    dem::Material cap{"cap", config.grains.density, config.grains.young, config.grains.stiffness_ratio, 0.0, 1.0};
    world.add_material(cap);
    dem::Material fun{"funnel", config.grains.density, config.grains.young, config.grains.stiffness_ratio, 0.0, 1.0};
    world.add_material(fun);
    for (uint32_t i : bottom_ring) world.set_fixed(i);
    for (uint32_t i : top_ring) world.set_fixed(i);
    double funnel_h = 0;
    const double funnel_top_r = 1.6 * lattice.radius;
    const auto pos = generate_grains(config, lattice, n, z_top, funnel_top_r, funnel_h, grain_reach(sizes.max_radius()));
    add_grains(pos, draw_radii(pos.size(), 0), 0);
    double zmax = 0;
    for (const Vec3& p : pos) zmax = std::max(zmax, p.z);
    dem::Plane bottom;
    bottom.point = {0, 0, 0};
    bottom.normal = {0, 0, 1};
    bottom.material = kCapMat;
    bottom.mask = kMaskCap;
    world.add_plane(bottom);
    dem::Plane top = bottom;
    top.point = {0, 0, std::max(zmax + grain_reach(sizes.max_radius()) + 1e-3, z_top)};
    top.normal = {0, 0, -1};
    world.add_plane(top);
    for (dem::Facet f : dem::make_funnel_facets({0, 0, z_top}, lattice.radius, funnel_top_r, funnel_h, 72, true)) {
        f.material = kFunnelMat;
        f.mask = kMaskCap;
        world.add_facet(f);
    }
    return funnel_h;
}

std::vector<Vec3> DamperScene::refill_sites(std::size_t n, double funnel_height, uint64_t stream) const {
    return generate_grains(config, lattice, n, z_top, 1.6 * lattice.radius, funnel_height, grain_reach(sizes.max_radius()),
                           highest_grain_top(), stream, true);
}

void DamperScene::add_grains(const std::vector<Vec3>& pos, const std::vector<double>& radii, uint64_t stream) {
    if (!clumps()) {
        for (std::size_t k = 0; k < pos.size(); ++k) {
            dem::SphereDef d;
            d.position = pos[k];
            d.radius = radii[k];
            d.material = kGrainMat;
            d.mask = kGrainMask;
            world.add_sphere(d);
        }
        end_grain = uint32_t(world.particles.size());
        return;
    }
    // Uniform random orientations (Shoemake's unit quaternion from three uniform numbers), a
    // stream of their own (not the positions' nor the radii's), one per fill.
    std::mt19937_64 rng((config.simulation.seed ^ 0x0C1A5E0F0A11ull) + stream * 0x9E3779B97F4A7C15ull);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t k = 0; k < pos.size(); ++k) {
        const double u1 = u(rng), u2 = 2.0 * std::numbers::pi * u(rng), u3 = 2.0 * std::numbers::pi * u(rng);
        const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
        dem::ClumpDef d;
        d.position = pos[k];
        d.orientation = {a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3)};
        d.material = kGrainMat;
        d.mask = kGrainMask;
        world.add_clump(dem::scaled(shape, radii[k]), d);
    }
    end_grain = uint32_t(world.particles.size());
}

std::vector<double> DamperScene::draw_radii(std::size_t n, uint64_t stream) const {
    if (sizes.kind == scene::SizeDistribution::Kind::Single) return std::vector<double>(n, config.grains.radius);
    // A stream of its own (not the positions'), one per fill: the pour 0, re-fill k stream k.
    std::mt19937_64 rng((config.simulation.seed ^ 0x51E7E5C0FFEEull) + stream * 0x9E3779B97F4A7C15ull);
    std::vector<double> r(n);
    for (double& x : r) x = sizes.draw(rng);
    return r;
}

void DamperScene::apply_run_settings() {
    // What may change between a preparation and a run from it: contact properties, foil
    // stiffness, process and simulation settings (geometry is checked by the caller).
    dem::Material& g = world.materials[kGrainMat];
    g.young = config.grains.young;
    g.stiffness_ratio = config.grains.stiffness_ratio;
    g.friction = config.grains.friction;
    g.restitution = config.grains.restitution;  // pairs take the smaller: grain-foil and grain-cap too
    world.materials[kCapMat].friction = config.damper.cap_friction < 0 ? config.grains.friction : config.damper.cap_friction;
    world.materials[kCapMat].young = config.grains.young;
    dem::Material& f = world.materials[kFoilMat];
    f.young = particle_modulus(config.foil);
    f.stiffness_ratio = config.foil.stiffness_ratio;
    f.friction = config.foil.friction;
    if (mesh_foil()) {
        // Each bond's kn from its length and triangles' area, as the membrane builder gave it.
        const MembraneDef d = membrane_def();
        for (std::size_t k = 0; k < membrane.bonds.size(); ++k) {
            const double kn = membrane_bond_stiffness(d, membrane.bond_length[k], membrane.bond_area[k]);
            world.set_bond_stiffness(membrane.bonds[k], kn, config.foil.stiffness_ratio * kn);
        }
    } else if (lattice.column_pitch != lattice.spacing) {
        // The lattice at its exact radius: row and column bonds differ (the bar rule, foil.h).
        for (const LatticeBond& b : lattice.bonds) {
            const double kn = lattice_bond_kn(config.foil, lattice, b);
            world.set_bond_stiffness(b.index, kn, config.foil.stiffness_ratio * kn);
        }
    } else {
        const double kn = bond_normal_stiffness(config.foil);
        for (std::size_t b = 0; b < world.bonds().size(); ++b) world.set_bond_stiffness(uint32_t(b), kn, config.foil.stiffness_ratio * kn);
    }
    world.set_bond_arm(config.foil.bond_arm);
    world.invalidate_contact_physics();
    world.params.local_damping = cycling_local_damping(config);  // the preparation ran with simulation.local_damping
    world.params.threads = config.simulation.threads;
    world.params.skin = config.simulation.skin;
}

void DamperScene::set_foil_pressure() {
    // The lattice: the paper's intersection nodes off the end rows. The mesh: a fan on every
    // particle off the end rings. Either way the end rings carry no pressure: the caps close the
    // foil there (rigid walls, which the grains, not the air, load in the model).
    if (mesh_foil()) world.pressure.fans = membrane_pressure_fans(membrane);
    else world.pressure.nodes = cylinder_pressure_nodes(lattice);
}

std::vector<double> DamperScene::grain_radii() const {
    if (!clumps()) return std::vector<double>(world.particles.radius.begin() + first_grain, world.particles.radius.begin() + end_grain);
    std::vector<double> r;
    const double rho = world.materials[kGrainMat].density;
    for (double m : world.clumps().mass) r.push_back(std::cbrt(3.0 * m / (4.0 * std::numbers::pi * rho)));
    return r;
}

std::vector<double> DamperScene::grain_tops() const {
    const dem::Particles& p = world.particles;
    if (!clumps()) {
        std::vector<double> tops;
        for (uint32_t i = first_grain; i < end_grain; ++i) tops.push_back(p.pos[i].z + p.radius[i]);
        return tops;
    }
    const dem::Clumps& c = world.clumps();
    std::vector<double> tops(c.size(), -1e300);
    for (std::size_t k = 0; k < c.size(); ++k)
        for (uint32_t e = c.start[k]; e < c.start[k + 1]; ++e)
            tops[k] = std::max(tops[k], p.pos[c.member[e]].z + p.radius[c.member[e]]);
    return tops;
}

double DamperScene::grains_volume_now() const {
    if (clumps()) return grains_mass() / world.materials[kGrainMat].density;
    double v = 0.0;
    for (uint32_t i = first_grain; i < end_grain; ++i) {
        const double r = world.particles.radius[i];
        v += r * r * r;
    }
    return 4.0 / 3.0 * std::numbers::pi * v;
}

double DamperScene::grains_mass() const {
    double m = 0;
    if (clumps())
        for (double x : world.clumps().mass) m += x;
    else
        for (uint32_t i = first_grain; i < end_grain; ++i) m += world.particles.mass[i];
    return m;
}

double DamperScene::grain_volume() const {
    // Summed once: the grains are fixed after the preparation, and air_step asks every step.
    if (grain_volume_ == 0.0) grain_volume_ = grains_volume_now();
    return grain_volume_;
}

// Level of the grains' top surface [m]: the mean top (z + r) of the highest layer, i.e. of the
// n_layer highest grains, n_layer the grains of one hexagonal layer across the foil (0.907
// (r_in / r_k)^2). The single highest grain would say little: one grain resting on the others
// stands a radius above the surface, and a cap that meets only it ends above the packing.
double DamperScene::fill_level() const {
    const double r_in = lattice.radius - config.foil.particle_radius, rk = config.grains.radius;
    std::vector<double> tops = grain_tops();
    const std::size_t layer = std::clamp<std::size_t>(std::size_t(0.9069 * (r_in / rk) * (r_in / rk)), 1, tops.size());
    std::partial_sort(tops.begin(), tops.begin() + long(layer), tops.end(), std::greater<double>());
    double sum = 0;
    for (std::size_t k = 0; k < layer; ++k) sum += tops[k];
    return sum / double(layer);
}

double DamperScene::highest_grain_top() const {
    double top = 0;
    for (uint32_t i = first_grain; i < end_grain; ++i) top = std::max(top, world.particles.pos[i].z + world.particles.radius[i]);
    return top;
}

// Grain volume over the cylinder of this inner radius and height: the packing fraction of
// summary.json ("preparation", "start_of_cycling").
double DamperScene::packing_fraction(double inner_radius, double height) const {
    double v = 0;
    if (clumps()) v = grains_volume_now();
    else
        for (uint32_t i = first_grain; i < end_grain; ++i) v += 4.0 / 3.0 * std::numbers::pi * std::pow(world.particles.radius[i], 3);
    return v / (std::numbers::pi * inner_radius * inner_radius * height);
}

double DamperScene::foil_volume() const {
    return mesh_foil() ? enclosed_volume(membrane, world.particles.pos) : enclosed_volume(lattice, world.particles.pos);
}

double DamperScene::lid_area() const {
    // The polygon of the top ring's particle centres (shoelace, projected on the cap's plane).
    const std::vector<uint32_t>& ring = top_ring;
    double a2 = 0.0;
    for (std::size_t k = 0; k < ring.size(); ++k) {
        const Vec3& p = world.particles.pos[ring[k]];
        const Vec3& q = world.particles.pos[ring[(k + 1) % ring.size()]];
        a2 += p.x * q.y - q.x * p.y;
    }
    return 0.5 * std::abs(a2);
}

double DamperScene::top_ring_force_z() const {
    double f = 0;
    for (uint32_t i : top_ring) f += world.particles.force[i].z;
    return f;
}

}  // namespace damper_detail

std::size_t grain_count(const Config& c) {
    if (c.grains.radius_distribution != RadiusDistribution::Single)
        return std::size_t(std::llround(c.grains.volume_fraction * std::numbers::pi * c.damper.radius * c.damper.radius *
                                        c.damper.height / grain_sizes(c).mean_volume()));
    const double rk = c.grains.radius;
    return std::size_t(std::llround(c.grains.volume_fraction * std::numbers::pi * c.damper.radius * c.damper.radius *
                                    c.damper.height / (4.0 / 3.0 * std::numbers::pi * rk * rk * rk)));
}

double inertial_number(const Config& c, double height) {
    const double gamma_dot = peak_speed(c.process) / height;  // the stroke's fastest
    const double p = std::max(std::abs(c.process.underpressure), 1.0);
    return gamma_dot * 2.0 * c.grains.radius * std::sqrt(c.grains.density / p);
}

}  // namespace vpp
