// The membrane from a closed surface mesh (vpp/membrane, issue 47) against closed forms:
// zero net pressure force on closed surfaces, the enclosed volume, the thin-shell strain of a
// pressurised sphere, and the built-in cylinder's counts and tributary areas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>
#include <numbers>
#include <string>

#include "dem/io/checkpoint.h"
#include "dem/mesh/mesh_checks.h"
#include "dem/mesh/mesh_shapes.h"
#include "dem/world/world.h"
#include "vpp/settings/config.h"
#include "vpp/membrane/foil.h"
#include "vpp/membrane/membrane.h"
#include "vpp/membrane/air.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_membrane {

namespace {

using dem::Vec3;
constexpr double kPi = std::numbers::pi;

vpp::MembraneDef paper_membrane() {
    vpp::MembraneDef d;
    d.foil = vpp::Config().foil;  // the paper's foil: E_f, t_f, r_f = r_k / 3, rho_f, ks/kn 0.5
    return d;
}

struct PressureSums {
    Vec3 net;           // [m^2] sum of A
    double abs = 0.0;   // [m^2] sum of |A|: below the area at sharp edges, where A is a vector sum
    double half = 0.0;  // [m^2] sum of A_x over the nodes with x > x_c: the body's projected area
};
PressureSums sums(const dem::World& w, double x_c) {
    PressureSums s;
    for (std::size_t k = 0; k < w.pressure.fans.node.size(); ++k) {
        const Vec3 a = dem::fan_area(w.particles.pos, w.pressure.fans, k);
        s.net += a;
        s.abs += norm(a);
        if (w.particles.pos[w.pressure.fans.node[k]].x > x_c) s.half += a.x;
    }
    return s;
}

}  // namespace

TEST(Membrane, NetPressureForceIsZeroOnClosedSurfaces) {
    // sum A over a closed triangulation vanishes identically: |sum A| / sum |A| at round-off,
    // with and without vacancies, on a sphere, a box (sharp edges), a capped cylinder and a
    // torus. The tributary areas as vectors: the x components over the half x > x_c sum to the
    // area of the body's cut by the plane x = x_c (divergence theorem on the half body; dp
    // times it is the force that holds one half against the other).
    struct Shape {
        const char* name;
        dem::SurfaceMesh mesh;
        double area, volume, projected, x_c;  // closed forms [m^2], [m^3], cut [m^2]; cut at x [m]
    };
    const double R = 0.02, a = 0.03, b = 0.02, c = 0.05, H = 0.04;
    const Shape shapes[] = {
        {"sphere", dem::make_icosphere(R, 32), 4 * kPi * R * R, 4.0 / 3.0 * kPi * R * R * R, kPi * R * R, 0.0},
        {"box", dem::make_box_mesh({0, 0, 0}, {a, b, c}, 1), 2 * (a * b + a * c + b * c), a * b * c, b * c, a / 2},
        {"cylinder", dem::make_cylinder_mesh(R, H, 128, 1), 2 * kPi * R * H + 2 * kPi * R * R, kPi * R * R * H, 2 * R * H,
         0.0},
        // A torus (major 20 mm, tube 8 mm): neither convex nor star-shaped, genus 1. The cut
        // x = 0 crosses its tube twice: two discs of 8 mm.
        {"torus", dem::make_torus(0.02, 0.008, 96, 40), 4 * kPi * kPi * 0.02 * 0.008,
         2 * kPi * kPi * 0.02 * 0.008 * 0.008, 2 * kPi * 0.008 * 0.008, 0.0},
    };
    for (const Shape& s : shapes)
        for (bool vac : {false, true}) {
            dem::World w;
            vpp::MembraneDef d = paper_membrane();
            d.vacancies = vac;
            const vpp::Membrane m = vpp::build_membrane(w, d, s.mesh);
            w.pressure.fans = vpp::membrane_pressure_fans(m);
            ASSERT_EQ(w.broken_invariant(), nullptr);
            const PressureSums p = sums(w, s.x_c);
            const double vol = vpp::enclosed_volume(m, w.particles.pos);
            std::printf("%s%s: %zu particles (%zu vacancies), %zu bonds, edges %.3f..%.3f (mean %.3f) x spacing; "
                        "|sum A| / sum|A| = %.2e, sum|A| / area %.5f, half-body cut / closed form %.5f, "
                        "volume / closed form %.5f\n",
                        s.name, vac ? " with vacancies" : "", m.particles.size(), m.vacancies, m.bonds.size(),
                        m.min_edge / m.spacing, m.max_edge / m.spacing, m.mean_edge / m.spacing, norm(p.net) / p.abs,
                        p.abs / s.area, p.half / s.projected, vol / s.volume);
            EXPECT_LT(norm(p.net) / p.abs, 1e-13) << s.name;
            // Chords of curved surfaces and the nodes straddling the half's edge: within 2%.
            EXPECT_NEAR(p.half / s.projected, 1.0, 0.02) << s.name;
            EXPECT_NEAR(vol / s.volume, 1.0, 0.02) << s.name;
            if (vac) {
                EXPECT_NEAR(double(m.vacancies) / double(m.sites.vertices.size()), 0.25, 0.03) << s.name;
            }
            // The World's pressure force sums to zero as well (dp = 10 kPa).
            w.pressure.dp = 1e4;
            w.params.gravity = {0, 0, 0};
            w.params.dt = 1e-7;
            w.compute_forces();
            Vec3 f;
            for (uint32_t i : m.particles) f += w.particles.force[i];
            EXPECT_LT(norm(f), 1e-12 * w.pressure.dp * s.area) << s.name;  // bonds at rest: pressure only
        }
}

TEST(Membrane, StiffnessRulesGiveTheirNetworkModuli) {
    // The equibiaxial stiffness of a network is its virial sum_e kn_e L_e^2 / (2 A) (each bond
    // stretched by eps carries kn eps L along itself); for MatchFoil it is (3 + a) / (2 (1 + a))
    // E_f t_f exactly on any triangulation (sum_e A_e = 3 A), the biaxial modulus E/(1 - nu) of a
    // sheet of Young modulus E_f t_f and Poisson ratio (1 - a)/(3 + a).
    for (auto rule : {vpp::MembraneStiffness::MatchFoil, vpp::MembraneStiffness::PaperBar}) {
        dem::World w;
        vpp::MembraneDef d = paper_membrane();
        d.stiffness = rule;
        const vpp::Membrane m = vpp::build_membrane(w, d, dem::make_icosphere(0.02, 8));
        double virial = 0;
        const auto& bl = w.bonds();
        for (uint32_t k : m.bonds) virial += bl.phys[k].kn * bl.phys[k].rest_length * bl.phys[k].rest_length;
        const double Yb = virial / (2.0 * dem::surface_area(m.sites));
        const double Eft = d.foil.young * d.foil.thickness, alpha = d.foil.stiffness_ratio;
        const double Yb_foil = Eft / (1.0 - vpp::network_poisson(alpha));
        std::printf("%s: biaxial stiffness %.4g N/m = %.4f E_f t_f / (1 - nu_net) (E_f t_f = %.4g N/m)\n",
                    rule == vpp::MembraneStiffness::MatchFoil ? "MatchFoil" : "PaperBar", Yb, Yb / Yb_foil, Eft);
        if (rule == vpp::MembraneStiffness::MatchFoil) {
            EXPECT_NEAR(Yb / Yb_foil, 1.0, 1e-9);
        } else {
            EXPECT_GT(Yb / Yb_foil, 2.0);  // 3 bonds per site: about 3x the real foil
        }
    }
    // The closed forms on an equilateral lattice agree with each other.
    EXPECT_NEAR(vpp::network_young(1.0, 0.5) / (1 - vpp::network_poisson(0.5)), vpp::network_biaxial(1.0), 1e-12);
}

namespace {

// A sphere membrane of radius R [m] with foil particles of radius r_f [m] (spacing 2 r_f) under
// an internal overpressure p [Pa], relaxed with local damping; returns the mean radial strain
// and (through biaxial) the network's biaxial stiffness N / eps [N/m] from its virial.
double sphere_strain(double R, double r_f, double p, bool vacancies, double& biaxial, std::size_t& particles,
                     double stiffness_factor = 1.0, uint64_t seed = 1, double prestrain = 0.0) {
    dem::World w;
    vpp::MembraneDef d = paper_membrane();
    d.prestrain = prestrain;
    d.foil.particle_radius = r_f;
    d.vacancies = vacancies;
    d.stiffness_factor = stiffness_factor;
    d.seed = seed;
    const vpp::Membrane m = vpp::build_membrane(w, d, dem::make_icosphere(R, 16));
    particles = m.particles.size();
    double virial = 0;
    for (uint32_t k : m.bonds) virial += w.bonds().phys[k].kn * std::pow(w.bonds().phys[k].rest_length, 2);
    biaxial = virial / (2.0 * dem::surface_area(m.sites));
    w.pressure.fans = vpp::membrane_pressure_fans(m);
    w.params.gravity = {0, 0, 0};
    w.params.local_damping = 0.3;
    w.params.dt = 0.3 * w.critical_dt();
    auto mean_radius = [&] {
        Vec3 c;
        for (uint32_t i : m.particles) c += w.particles.pos[i];
        c /= double(m.particles.size());
        double s = 0;
        for (uint32_t i : m.particles) s += norm(w.particles.pos[i] - c);
        return s / double(m.particles.size());
    };
    const double r0 = mean_radius();
    // Ramp over ~10 breathing periods, then hold; the breathing period is
    // 2 pi R sqrt(rho_A / (2 N/eps)), rho_A the membrane's mass per area.
    double mass = 0;
    for (uint32_t i : m.particles) mass += w.particles.mass[i];
    const double period = 2 * kPi * R * std::sqrt(mass / dem::surface_area(m.sites) / (2 * biaxial));
    const int ramp = int(10 * period / w.params.dt), hold = int(30 * period / w.params.dt);
    for (int s = 0; s < ramp + hold; ++s) {
        w.pressure.dp = -p * std::min(1.0, double(s) / ramp);
        w.step();
    }
    return mean_radius() / r0 - 1.0;
}

}  // namespace

TEST(Membrane, SphereUnderPressureMatchesThinShellStrain) {
    // Membrane tension of a sphere N = p r / 2 (r = R (1 + eps) the current radius) against the
    // network's biaxial stiffness N = Yb eps / (1 + eps) (tension per current length):
    //   eps = p R (1 + eps)^2 / (2 Yb),   Yb = (3 + a) / (2 (1 + a)) E_f t_f for MatchFoil.
    // Refined by shrinking the foil particles (spacing 2 r_f) on a fixed sphere of R = 10 mm.
    const double R = 0.01, p = 4000.0;
    double prev_err = 1.0;
    for (double r_f : {2e-3, 1e-3, 0.5e-3}) {
        double Yb = 0;
        std::size_t n = 0;
        const double eps = sphere_strain(R, r_f, p, false, Yb, n);
        double closed = p * R / (2 * Yb);
        for (int k = 0; k < 20; ++k) closed = p * R * (1 + closed) * (1 + closed) / (2 * Yb);
        const double err = std::abs(eps / closed - 1.0);
        std::printf("sphere R = %g m, r_f = %g m (%zu particles): strain %.6e, thin shell %.6e, error %.3f%%\n", R, r_f, n,
                    eps, closed, 100 * err);
        EXPECT_LT(err, 0.05);
        EXPECT_LT(err, prev_err + 0.002);  // falls with refinement (within the last digit)
        prev_err = err;
    }
    EXPECT_LT(prev_err, 0.01);
}

TEST(Membrane, PrestrainShrinksAFreeSphereAndShiftsItsPressureStrain) {
    // Built stretched by eps0, the network rests on the sphere of radius R0 = R / (1 + eps0): free,
    // it shrinks there; under p its strain from R0 follows the thin shell of R0 (Yb the network's
    // biaxial stiffness, that of the unstretched build: the same kn on lengths and areas scaled
    // alike),
    //   e = p R0 (1 + e)^2 / (2 Yb),   r / R = (1 + e) / (1 + eps0).
    // Tolerances (r_f = 1 mm, the unstretched test's 0.65% there): the free shrinkage within 1% of
    // eps0 / (1 + eps0), the pressure's strain (r(p) - r(0)) / R within 5% of its closed form
    // (measured 0.06% and 0.6%). A large prestrain released with nothing inside crumples as it
    // overshoots (0.2: 1.2% more shrinkage at r_f = 1 mm, 10% at 0.5 mm); in a bag the grains
    // hold it out.
    const double R = 0.01, r_f = 1e-3, eps0 = 0.05, p = 40000.0;
    double Yb = 0;
    std::size_t n = 0;
    const double free = sphere_strain(R, r_f, 0.0, false, Yb, n, 1.0, 1, eps0);
    const double loaded = sphere_strain(R, r_f, p, false, Yb, n, 1.0, 1, eps0);
    const double Yb_rest = Yb * (1 + eps0) * (1 + eps0);  // sphere_strain's Yb: rest lengths on built areas
    const double R0 = R / (1 + eps0);
    double e = 0;
    for (int k = 0; k < 40; ++k) e = p * R0 * (1 + e) * (1 + e) / (2 * Yb_rest);
    const double want_free = 1 / (1 + eps0) - 1, want_shift = e / (1 + eps0);
    std::printf("prestrain %.2f: free r / R - 1 = %.5f (closed form %.5f); p = %g Pa shifts it by %.5f (closed form %.5f)\n",
                eps0, free, want_free, p, loaded - free, want_shift);
    EXPECT_NEAR(free, want_free, 0.01 * std::abs(want_free));
    EXPECT_NEAR(loaded - free, want_shift, 0.05 * want_shift);
    // A prestrain outside [0, 1) is refused.
    dem::World w;
    vpp::MembraneDef d = paper_membrane();
    d.prestrain = 1.0;
    EXPECT_THROW(vpp::build_membrane(w, d, dem::make_icosphere(R, 4)), std::invalid_argument);
}

TEST(Membrane, VacanciesSoftenTheNetwork) {
    // ~25% vacancies remove ~6 bonds each; the biaxial strain under the same p grows. Measured
    // over three seeds, not a closed form (the holes relax non-affinely, so the virial
    // overestimates the stiffness left): reported in docs/membrane.md with the compensation
    // MembraneDef::stiffness_factor it suggests.
    const double R = 0.01, p = 4000.0, r_f = 0.5e-3;
    double Yb_full = 0;
    std::size_t n_full = 0;
    const double e_full = sphere_strain(R, r_f, p, false, Yb_full, n_full);
    double mean_ratio = 0;
    for (uint64_t seed : {1, 2, 3}) {
        double Yb_vac = 0;
        std::size_t n_vac = 0;
        const double e_vac = sphere_strain(R, r_f, p, true, Yb_vac, n_vac, 1.0, seed);
        std::printf("vacancies, seed %llu: %zu -> %zu particles, virial stiffness ratio %.3f, strain ratio %.3f\n",
                    (unsigned long long)seed, n_full, n_vac, Yb_vac / Yb_full, e_vac / e_full);
        mean_ratio += e_vac / e_full / 3.0;
    }
    std::printf("vacancies: mean strain ratio %.3f\n", mean_ratio);
    EXPECT_GT(mean_ratio, 1.6);
    EXPECT_LT(mean_ratio, 2.8);
    // The documented compensation brings the strain back within 5% (seed 1).
    double Yb_comp = 0;
    std::size_t n_comp = 0;
    const double e_comp = sphere_strain(R, r_f, p, true, Yb_comp, n_comp, 2.1);
    std::printf("vacancies with stiffness_factor 2.1: strain ratio %.3f\n", e_comp / e_full);
    EXPECT_NEAR(e_comp / e_full, 1.0, 0.05);
}

TEST(Membrane, CylinderMeshAgainstBuiltInCylinder) {
    // The paper's damper cylinder (r_p = 25.5 mm, H = 100 mm) built-in and from a mesh of the
    // built-in's radius and height. The lattices differ by design (a square grid with every
    // second chain load-carrying against a triangulation), so the counts are compared with the
    // ratios their site densities predict for a lateral area S at spacing h = 2 r_f:
    //   built-in: 3/4 S/h^2 particles, S/h^2 bonds;
    //   mesh:     2/sqrt(3) S/h^2 sites, 3 bonds per site; with a fraction f of vacancies
    //             (1 - f) of the sites and 3 - 6 f bonds per site (f = 1/4: 1.5).
    // The tributary areas are compared as the half-body projections (sum of A_x over x > 0 per
    // projected area: 2 R times the loaded height), which both should make 1.
    const vpp::Config cfg;
    dem::World wc;
    const vpp::FoilLattice L = vpp::build_cylinder(wc, cfg.foil, cfg.damper.radius, cfg.damper.height);
    const auto nodes = vpp::cylinder_pressure_nodes(L);
    double cyl_half = 0;
    for (const auto& q : nodes)
        if (wc.particles.pos[q.node].x > 0) cyl_half += dem::tributary_area(wc.particles.pos, q).x;
    const double h = L.spacing, H = (L.rows - 1) * h;
    const double cyl_per_area = cyl_half / (2 * L.radius * (L.rows - 3) * h);

    for (bool vac : {false, true}) {
        dem::World w;
        vpp::MembraneDef d = paper_membrane();
        d.vacancies = vac;
        const vpp::Membrane m = vpp::build_membrane(w, d, dem::make_cylinder_mesh(L.radius, H, 256, 1));
        // Lateral particles: on the side or its rims (radius R), not on the caps' interiors.
        std::size_t lateral = 0;
        for (uint32_t i : m.particles)
            lateral += std::hypot(w.particles.pos[i].x, w.particles.pos[i].y) > L.radius * (1 - 2e-3);
        std::size_t lateral_bonds = 0;
        const auto& bl = w.bonds();
        for (uint32_t k : m.bonds) {
            const Vec3 &a = w.particles.pos[bl.i[k]], &b = w.particles.pos[bl.j[k]];
            lateral_bonds += std::hypot(a.x, a.y) > L.radius * (1 - 2e-3) && std::hypot(b.x, b.y) > L.radius * (1 - 2e-3);
        }
        w.pressure.fans = vpp::membrane_pressure_fans(m);
        const PressureSums s = sums(w, 0.0);
        const double projected = 2 * L.radius * H;
        // The vacancies drawn (about 25%, each taking its ~6 bonds) enter the expected ratios.
        const double f = double(m.vacancies) / double(m.sites.vertices.size());
        const double want_particles = (1 - f) * (2 / std::sqrt(3.0)) / 0.75;
        const double want_bonds = (3 - 6 * f) * (2 / std::sqrt(3.0)) / 1.0;
        const double rp = double(lateral) / double(L.particles.size()), rb = double(lateral_bonds) / double(wc.bonds().size());
        std::printf("cylinder%s: built-in %zu particles, %zu bonds, tributary/area %.5f; mesh %zu lateral particles "
                    "(ratio %.3f, lattice %.3f), %zu lateral bonds (ratio %.3f, lattice %.3f), tributary/area %.5f\n",
                    vac ? " with vacancies" : "", L.particles.size(), wc.bonds().size(), cyl_per_area, lateral, rp,
                    want_particles, lateral_bonds, rb, want_bonds, s.half / projected);
        EXPECT_NEAR(rp / want_particles, 1.0, 0.05);
        EXPECT_NEAR(rb / want_bonds, 1.0, 0.05);
        EXPECT_NEAR(s.half / projected, cyl_per_area, 0.01);
    }
}

TEST(Membrane, SitesOnceThenSeedsGiveTheSameAsBuildingAnew) {
    // membrane_sites + place_membrane (remesh once, draw per seed) equals build_membrane.
    vpp::MembraneDef d = paper_membrane();
    d.vacancies = true;
    const dem::SurfaceMesh bag = dem::make_icosphere(0.015, 16);
    const vpp::Membrane sites = vpp::membrane_sites(d, bag);
    std::size_t previous = 0;
    for (uint64_t seed : {1, 2}) {
        d.seed = seed;
        dem::World a, b;
        vpp::Membrane ma = sites;
        vpp::place_membrane(a, d, ma);
        const vpp::Membrane mb = vpp::build_membrane(b, d, bag);
        ASSERT_EQ(ma.particles.size(), mb.particles.size());
        EXPECT_EQ(ma.particle, mb.particle);
        EXPECT_EQ(ma.triangles, mb.triangles);
        EXPECT_EQ(a.bonds().size(), b.bonds().size());
        std::size_t h = 0;  // which sites are vacant differs between seeds
        for (std::size_t s = 0; s < ma.particle.size(); ++s) h = h * 31 + (ma.particle[s] < 0 ? s : 0);
        EXPECT_NE(h, previous);
        previous = h;
    }
    dem::World w;
    vpp::Membrane placed = sites;
    vpp::place_membrane(w, d, placed);
    EXPECT_THROW(vpp::place_membrane(w, d, placed), std::invalid_argument);
}

TEST(Membrane, CheckpointsRefuseFansRatherThanDropThem) {
    // The checkpoint format has no place for pressure fans yet: saving must fail loudly, not
    // resume a membrane without its pressure.
    dem::World w;
    const vpp::Membrane m = vpp::build_membrane(w, paper_membrane(), dem::make_icosphere(0.01, 8));
    w.pressure.fans = vpp::membrane_pressure_fans(m);
    const std::string path = ::testing::TempDir() + "/membrane_fans.ckpt";
    try {
        dem::save_checkpoint(path, w, "");
        ADD_FAILURE() << "a World with pressure fans was saved";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("pressure fans"), std::string::npos) << e.what();
    }
}

TEST(Membrane, FanPressureWorkBalancesTheLedgerAndIsThreadIndependent) {
    // A sphere membrane inflated by a ramped overpressure: the energy ledger's pressure work
    // (from the fans' per-particle slots) equals the gas work int p dV summed from the
    // enclosed volume each step, and the ledger closes (input = stored + dissipated); one and
    // two threads give the same bits.
    auto run = [](int threads, double& gas_work, dem::EnergyLedger& ledger, std::vector<Vec3>& pos) {
        dem::World w;
        vpp::MembraneDef d = paper_membrane();
        d.vacancies = true;
        const vpp::Membrane m = vpp::build_membrane(w, d, dem::make_icosphere(0.01, 16));
        w.pressure.fans = vpp::membrane_pressure_fans(m);
        w.params.gravity = {0, 0, 0};
        w.params.local_damping = 0.2;
        w.params.threads = threads;
        w.params.track_energy = true;
        w.params.dt = 0.3 * w.critical_dt();
        const double p = 4000.0;
        gas_work = 0;
        double v = vpp::enclosed_volume(m, w.particles.pos), dp_prev = 0;
        for (int s = 0; s < 4000; ++s) {
            w.pressure.dp = -p * std::min(1.0, s / 2000.0);
            const double dp_now = w.pressure.dp;
            w.step();
            const double v1 = vpp::enclosed_volume(m, w.particles.pos);
            gas_work += -0.5 * (dp_now + (s == 0 ? dp_now : dp_prev)) * (v1 - v);  // trapezoid on p dV
            dp_prev = dp_now;
            v = v1;
        }
        ledger = w.energy();
        pos = w.particles.pos;
    };
    double g1 = 0, g2 = 0;
    dem::EnergyLedger l1, l2;
    std::vector<Vec3> p1, p2;
    run(1, g1, l1, p1);
    run(2, g2, l2, p2);
    std::printf("pressure work: ledger %.6e J, int p dV %.6e J (ratio %.5f); residual %.2e of the input\n",
                l1.pressure_work, g1, l1.pressure_work / g1, std::abs(l1.residual()) / l1.input_work());
    EXPECT_NEAR(l1.pressure_work / g1, 1.0, 0.01);
    EXPECT_LT(std::abs(l1.residual()), 0.01 * l1.input_work());
    ASSERT_EQ(p1.size(), p2.size());
    EXPECT_EQ(std::memcmp(p1.data(), p2.data(), p1.size() * sizeof(Vec3)), 0);
    EXPECT_EQ(l1.pressure_work, l2.pressure_work);
}

TEST(Membrane, SealedAirFollowsBoylesLawAndAFastPumpHoldsTheSetPoint) {
    // The air model on a membrane: sealed (no pump, no leak) at p_atm, its enclosure shrunk by
    // hand to 90% linear size: p V = p_atm V0, dp = p_atm - p; the work summed is the
    // isothermal p_atm V0 ln(V1 / V0). A pump far faster than the volume changes holds dp_set.
    dem::World w;
    vpp::MembraneDef d = paper_membrane();
    const vpp::Membrane m = vpp::build_membrane(w, d, dem::make_icosphere(0.02, 16));
    w.pressure.fans = vpp::membrane_pressure_fans(m);
    w.params.dt = 1e-6;
    const double solids = 1e-5;  // [m^3] grains inside
    vpp::MembraneAirDef air;
    air.model = vpp::PressureModel::Pump;
    air.line.p_atm = vpp::kAtmosphericPressure;
    vpp::MembraneGas g;
    vpp::membrane_air_step(w, m, solids, 0.0, air, g);
    const double v0 = g.volume;
    EXPECT_NEAR(w.pressure.dp, 0.0, 1e-9);
    for (uint32_t i : m.particles) w.particles.pos[i] *= 0.9;
    vpp::membrane_air_step(w, m, solids, 0.0, air, g);
    const double v1 = vpp::enclosed_volume(m, w.particles.pos) - solids;
    const double p = vpp::kAtmosphericPressure * v0 / v1;
    std::printf("sealed: V %.5g -> %.5g m^3, dp %.6g Pa (Boyle %.6g), work %.6g J (isothermal %.6g)\n", v0, v1,
                w.pressure.dp, vpp::kAtmosphericPressure - p, g.work, vpp::kAtmosphericPressure * v0 * std::log(v1 / v0));
    EXPECT_NEAR(w.pressure.dp / (vpp::kAtmosphericPressure - p), 1.0, 1e-12);
    EXPECT_NEAR(g.work / (vpp::kAtmosphericPressure * v0 * std::log(v1 / v0)), 1.0, 1e-12);
    // A pump of speed 1e3 m^3/s evacuates to dp_set within a step and holds it exactly.
    air.line.speed = 1e3;
    vpp::membrane_air_step(w, m, solids, 6e4, air, g);
    EXPECT_EQ(w.pressure.dp, 6e4);
    // A membrane collapsed onto its solids is refused.
    EXPECT_THROW(vpp::membrane_air_step(w, m, 1.0, 6e4, air, g), std::runtime_error);
}

}  // namespace test_membrane
