// Verification of the foil model (issue 3): stiffness convention, tributary areas, hoop strain,
// the empty envelope under underpressure, and energy of the bond network.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "vpp/settings/config.h"
#include "vpp/foil_checks/envelope.h"
#include "vpp/membrane/foil.h"
#include "vpp/membrane/foil_tension.h"
#include "vpp/foil_checks/tension.h"

using dem::Vec3;

namespace {
vpp::Config defaults() { return vpp::Config(vpp::CommandSet::Foil); }
}  // namespace

TEST(Foil, ParticleModulusIsThePapersValue) {
    // E_s = 2 E_f t_f / (2 r_f) with the paper's numbers; the paper prints 18.545 MPa (rounded r_f).
    const vpp::FoilDef f = vpp::Config().foil;  // the table's (the paper's) foil
    EXPECT_NEAR(vpp::particle_modulus(f), 18.545e6, 0.0005 * 18.545e6);
    // kn = 2 E_s r_f = 2 E_f t_f = 36.65 kN/m (spec section 4).
    EXPECT_NEAR(vpp::bond_normal_stiffness(f), 2.0 * f.young * f.thickness, 1e-9);
}

TEST(Foil, StripTensileStiffnessMatchesRealFoil) {
    // The paper's 37 x 12 strip pulled to 2%: F/eps = E_f t_f w within 3%.
    const vpp::TensionResult r = vpp::run_tension(defaults(), "", true);
    std::printf("strip: effective %.6g Pa, target %.6g Pa, error %.3f%%\n", r.effective_modulus,
                r.target_modulus, 100.0 * (r.effective_modulus / r.target_modulus - 1.0));
    EXPECT_NEAR(r.effective_modulus / r.target_modulus, 1.0, 0.03);
}

TEST(Foil, CylinderChoosesEvenColumnsAndOddRows) {
    // Paper: 82 sites around (80 is the other candidate), about 51 rings, about 3150 particles.
    dem::World w;
    const vpp::FoilDef f = vpp::Config().foil;  // the table's (the paper's) foil
    const vpp::FoilLattice L = vpp::build_cylinder(w, f, 0.0255, 0.100);
    EXPECT_EQ(L.cols, 82);
    EXPECT_EQ(L.rows, 51);
    EXPECT_EQ(L.particles.size(), 26u * 82u + 25u * 41u);
    EXPECT_NEAR(L.radius, f.particle_radius / std::sin(std::numbers::pi / 82), 1e-15);
    // Chain neighbours are exactly 2 r_f apart; bonds only along chains (4 per 2x2 block).
    for (std::size_t b = 0; b < w.bonds().size(); ++b) {
        const double d = norm(w.particles.pos[w.bonds().j[b]] - w.particles.pos[w.bonds().i[b]]);
        ASSERT_NEAR(d, 2.0 * f.particle_radius, 1e-12);
    }
    EXPECT_EQ(w.bonds().size(), 26u * 82u + 25u * 41u * 2u);  // ring bonds + axial bonds
}

TEST(Foil, TributaryAreasSumToLateralAreaAndCancel) {
    dem::World w;
    const vpp::FoilDef f = vpp::Config().foil;  // the table's (the paper's) foil
    const vpp::FoilLattice L = vpp::build_cylinder(w, f, 0.0255, 0.100);
    const auto nodes = vpp::cylinder_pressure_nodes(L);
    double sum_abs = 0;
    Vec3 net;
    for (const auto& q : nodes) {
        const Vec3 a = dem::tributary_area(w.particles.pos, q);
        sum_abs += norm(a);
        net += a;
        // Outward: along the radial direction of the node.
        const Vec3 x = w.particles.pos[q.node];
        ASSERT_GT(dot(a, Vec3{x.x, x.y, 0.0}), 0.0);
    }
    // Loaded band: rows 1 .. rows-2, height (rows - 3) * 2 r_f.
    const double lateral = 2.0 * std::numbers::pi * L.radius * (L.rows - 3) * L.spacing;
    std::printf("sum |A_j| = %.8g m^2, lateral area %.8g m^2, ratio %.6f\n", sum_abs, lateral, sum_abs / lateral);
    EXPECT_NEAR(sum_abs / lateral, 1.0, 0.01);
    EXPECT_LT(norm(net), 1e-12 * sum_abs);
}

namespace foil_hoop_test {

constexpr double kOverpressure = 2000.0;  // [Pa] inside the pressurised cylinders below

// The table's (the paper's) foil as a capped cylinder of radius `radius` [m], 40 mm tall, its end
// rings fixed, under kOverpressure inside, ready to step: no gravity, local damping 0.3, 0.3 of
// the critical step.
vpp::FoilLattice pressurised_cylinder(dem::World& w, double radius, bool exact_radius = false) {
    const vpp::FoilLattice L = vpp::build_cylinder(w, vpp::Config().foil, radius, 0.04, 0.0, exact_radius);
    for (int k : {0, L.rows - 1})
        for (uint32_t i : L.row(k)) w.set_fixed(i);
    w.pressure.nodes = vpp::cylinder_pressure_nodes(L);
    w.pressure.dp = -kOverpressure;
    w.params.gravity = {0, 0, 0};
    w.params.local_damping = 0.3;
    w.params.dt = 0.3 * w.critical_dt();
    return L;
}

// pressurised_cylinder stepped 40,000 times: the hoop strain of its mid-height ring and membrane
// theory's p R / (E_f t_f) (R the built site circle).
struct HoopStrain {
    double strain, expected;
};
HoopStrain hoop_strain_under_pressure(double radius, bool exact_radius) {
    dem::World w;
    const vpp::FoilDef f = vpp::Config().foil;
    const vpp::FoilLattice L = pressurised_cylinder(w, radius, exact_radius);
    const int mid = (L.rows / 2) % 2 == 0 ? L.rows / 2 : L.rows / 2 + 1;  // a full ring
    auto mean_radius = [&] {
        double s = 0;
        const auto ring = L.row(mid);
        for (uint32_t i : ring) s += std::hypot(w.particles.pos[i].x, w.particles.pos[i].y);
        return s / double(ring.size());
    };
    const double r0 = mean_radius();
    for (int s = 0; s < 40000; ++s) w.step();
    return {mean_radius() / r0 - 1.0, kOverpressure * L.radius / (f.young * f.thickness)};
}

}  // namespace foil_hoop_test

TEST(Foil, HoopStrainUnderInternalPressure) {
    // Capped cylinder (end rings fixed), internal overpressure p: hoop strain p R / (E_f t_f)
    // at mid-height within 10% (membrane theory; the lattice has no Poisson coupling).
    const auto [strain, expected] = foil_hoop_test::hoop_strain_under_pressure(0.0255, false);
    std::printf("hoop strain %.6g, membrane theory %.6g, ratio %.4f\n", strain, expected, strain / expected);
    EXPECT_NEAR(strain / expected, 1.0, 0.10);
}

TEST(Foil, EmptyEnvelopeFoldsInwardAndComesToRest) {
    // The paper's sanity check at dp = 0.01 MPa on a shorter envelope (test time).
    vpp::Config c = defaults();
    c.damper.height = 0.05;
    c.process.ramp_time = 0.01;
    c.process.hold_time = 0.03;
    c.simulation.threads = 1;
    const vpp::EnvelopeResult r = vpp::run_envelope(c, "", true);
    std::printf("envelope: volume ratio %.4f, min gap %.4f r_f, KE final %.3g J, peak %.3g J, r_max %.6g m\n",
                r.final_volume_ratio, r.min_gap, r.final_kinetic_energy, r.peak_kinetic_energy,
                r.max_radial_excursion);
    EXPECT_LT(r.final_volume_ratio, 0.9);     // folds inward
    EXPECT_GT(r.final_volume_ratio, 0.05);    // and does not pass through itself
    EXPECT_GT(r.min_gap, -0.1);               // overlaps stay a small fraction of r_f
    EXPECT_LE(r.max_radial_excursion, r.radius * 1.001);  // nothing leaves the envelope
    // At rest: the membrane's translational kinetic energy below 1e-3 of its peak and below 1e-5
    // of the pressure work dp |dV|; all kinetic energy (incl. free spin) below 1% of its peak.
    const double work = c.process.underpressure * r.initial_volume * (1.0 - r.final_volume_ratio);
    std::printf("translational KE final %.3g J (peak %.3g J), pressure work %.3g J\n",
                r.final_translational_energy, r.peak_translational_energy, work);
    EXPECT_LT(r.final_translational_energy, 1e-3 * r.peak_translational_energy);
    EXPECT_LT(r.final_translational_energy, 1e-5 * work);
    EXPECT_LT(r.final_kinetic_energy, 0.01 * r.peak_kinetic_energy);
}

TEST(Foil, BondNetworkConservesEnergyWithoutDamping) {
    // A strip with random velocities, no damping, no walls: the bond network neither creates nor
    // loses energy. E = kinetic (synchronous velocities v(t), not the leapfrog's half-step ones,
    // whose offset alone moves E by a few per cent) + bond elastic energy, checked every 100 of
    // 100000 steps at dt = 0.1 of the critical step: |E - E0| < 1% of E0 both ways. Leapfrog
    // keeps a bounded ripple and no drift: measured +0.25% at most (and -0.12% over twice the
    // steps); a local damping of only 0.001 loses 99% of E in this run. Bonds never break even
    // when stretched far.
    dem::World w;
    w.params.gravity = {0, 0, 0};
    vpp::FoilDef f = vpp::Config().foil;
    vpp::FoilLattice L = vpp::build_strip(w, f, 6, 9);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (uint32_t i : L.particles) {
        w.particles.vel[i] = {0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng)};
        w.particles.angvel[i] = {20 * u(rng), 20 * u(rng), 20 * u(rng)};
    }
    w.params.dt = 0.1 * w.critical_dt();
    auto energy = [&] {  // after compute_forces(): positions and bond springs at t
        const auto& p = w.particles;
        double e = 0;
        for (uint32_t i : L.particles)
            e += 0.5 * p.mass[i] * norm2(w.velocity_at_time(i)) + 0.5 / p.inv_inertia[i] * norm2(w.angular_velocity_at_time(i));
        const auto& b = w.bonds();
        for (std::size_t k = 0; k < b.size(); ++k) {
            const double d = norm(p.pos[b.j[k]] - p.pos[b.i[k]]) - b.phys[k].rest_length;
            e += 0.5 * b.phys[k].kn * d * d + 0.5 * norm2(b.shear[k]) / b.phys[k].ks;
        }
        return e;
    };
    w.compute_forces();
    const double e0 = energy();
    double emin = e0, emax = e0;
    for (int s = 0; s < 100000; ++s) {
        w.integrate();
        w.compute_forces();
        if (s % 100 == 0) {
            const double e = energy();
            emin = std::min(emin, e);
            emax = std::max(emax, e);
        }
    }
    std::printf("bond network: E0 %.6g J, min %.6g J (%+.4f%%), max %.6g J (%+.4f%%)\n", e0, emin,
                100.0 * (emin / e0 - 1.0), emax, 100.0 * (emax / e0 - 1.0));
    EXPECT_LT(emax, 1.01 * e0);  // creates no energy
    EXPECT_GT(emin, 0.99 * e0);  // and loses none (no damping anywhere)
}

TEST(Foil, BondsNeverBreak) {
    // Pull two bonded foil particles to +50% and push them to -50%: the axial force stays
    // kn * (L0 - L) (linear, tension and compression): the bond still acts, with its full
    // stiffness, far beyond any strain of a run. (Nothing in the engine removes a bond, so
    // counting the bonds would prove nothing; the force does.)
    dem::World w;
    w.params.gravity = {0, 0, 0};
    vpp::FoilDef f = vpp::Config().foil;
    vpp::FoilLattice L = vpp::build_strip(w, f, 1, 2);
    const double L0 = L.spacing, kn = vpp::bond_normal_stiffness(f);
    for (double strain : {0.5, -0.5}) {
        w.particles.pos[L.particles[1]] = w.particles.pos[L.particles[0]] + Vec3{L0 * (1 + strain), 0, 0};
        w.invalidate_candidates();
        w.compute_forces();
        EXPECT_NEAR(w.particles.force[L.particles[1]].x, -kn * L0 * strain, 1e-9 * kn * L0);
    }
}

// ---- The foil's membrane tensions (vpp/membrane/foil_tension.h) against closed forms: a uniform
// stretch of the lattice (N = E_f t_f eps, the strip's stiffness per unit width, times the
// polygon's perimeter over the circle's) and a pressurised thin cylinder (N_theta = p R).

namespace foil_tension_test {

// The polygon of n sites against its circle: perimeter n 2 R sin(pi/n) over 2 pi R. The virial
// sums the bonds' (chords') lengths and divides by the circle's area.
double polygon_factor(int n) { return n * std::sin(std::numbers::pi / n) / std::numbers::pi; }

// Stretches every foil particle of L affinely (radially by 1 + er, along z by 1 + ez), then the
// forces once: the bonds' springs at that strain, no motion.
vpp::FoilTension stretched(dem::World& w, const vpp::FoilLattice& L, double er, double ez) {
    for (uint32_t i : L.particles) {
        dem::Vec3& p = w.particles.pos[i];
        p = {p.x * (1.0 + er), p.y * (1.0 + er), p.z * (1.0 + ez)};
    }
    w.params.gravity = {0, 0, 0};
    w.params.dt = 1e-7;
    w.compute_forces();
    return vpp::cylinder_tension(L, w);
}

}  // namespace foil_tension_test

// A uniform hoop strain eps: each row bond (chord c) stretches by c eps and pulls kn c eps; the
// row chains are 4 r_f apart, so N_theta = kn c eps / (4 r_f) = E_f t_f eps (kn = 2 E_f t_f,
// c = 2 r_f), times the polygon factor of the virial (0.99975 for 82 columns); the column bonds
// stay unstretched (the lattice has no Poisson coupling): N_z = 0. An axial strain the other way
// round. To 1e-9: the springs are linear and the strain exact.
TEST(FoilTension, AUniformStretchGivesTheFoilsStiffnessPerUnitWidth) {
    const vpp::FoilDef f = vpp::Config().foil;  // the paper's foil
    const double Et = f.young * f.thickness;    // [N/m]
    const double eps = 1e-3;
    {
        dem::World w;
        const vpp::FoilLattice L = vpp::build_cylinder(w, f, 0.0255, 0.04);
        const vpp::FoilTension t = foil_tension_test::stretched(w, L, eps, 0.0);
        const double expected = Et * eps * foil_tension_test::polygon_factor(L.cols);
        std::printf("hoop stretch %g: N_theta %.9g N/m, E_f t_f eps x polygon %.9g N/m; N_z %.3g N/m\n", eps, t.hoop,
                    expected, t.axial);
        EXPECT_NEAR(t.hoop / expected, 1.0, 1e-9);
        EXPECT_LT(std::abs(t.axial), 1e-9 * expected);
    }
    {
        dem::World w;
        const vpp::FoilLattice L = vpp::build_cylinder(w, f, 0.0255, 0.04);
        const vpp::FoilTension t = foil_tension_test::stretched(w, L, 0.0, eps);
        const double expected = Et * eps * foil_tension_test::polygon_factor(L.cols);
        std::printf("axial stretch %g: N_z %.9g N/m, E_f t_f eps x polygon %.9g N/m; N_theta %.3g N/m\n", eps, t.axial,
                    expected, t.hoop);
        EXPECT_NEAR(t.axial / expected, 1.0, 1e-9);
        EXPECT_LT(std::abs(t.hoop), 1e-9 * expected);
    }
}

// A thin cylinder under an internal overpressure p carries N_theta = p R around (Barlow's
// formula; the caps of this one are the fixed end rings, which take the axial load: N_z about
// 0). The lattice at rest under p = 2 kPa: N_theta against p R, R the band's mean radius, within
// 0.5%: the pressure acts on the n/2 intersection nodes, between which the row chains run
// straight (a polygon of n/2 sides: N_theta = p R cos(2 pi / n) at the nodes' radius, 0.3% below
// p R at n = 82), and the rows next to the fixed rings are held in a little.
TEST(FoilTension, APressurisedCylinderCarriesPR) {
    dem::World w;
    const vpp::FoilLattice L = foil_hoop_test::pressurised_cylinder(w, 0.0255);
    const double p = foil_hoop_test::kOverpressure;
    for (int s = 0; s < 40000; ++s) w.step();
    w.compute_forces();
    const vpp::FoilTension t = vpp::cylinder_tension(L, w);
    double r_sum = 0;
    std::size_t n = 0;
    for (int k = 1; k + 1 < L.rows; ++k)
        for (uint32_t i : L.row(k)) {
            r_sum += std::hypot(w.particles.pos[i].x, w.particles.pos[i].y);
            ++n;
        }
    const double R = r_sum / double(n);
    std::printf("p %g Pa: N_theta %.6g N/m, p R %.6g N/m (ratio %.5f), N_z %.4g N/m\n", p, t.hoop, p * R, t.hoop / (p * R),
                t.axial);
    EXPECT_NEAR(t.hoop / (p * R), 1.0, 0.005);
    EXPECT_LT(std::abs(t.axial), 0.02 * p * R);
}

// ---- The foil at its exact radius (foil.exact_radius; build_cylinder with exact_radius, docs/foil.md
// "At the exact radius"): the paper's rule builds the cylinder on the circle of chord 2 r_f for
// the even column count closest to the radius asked, 20.77 / 25.80 / 30.21 mm for the paper's
// 20.5 / 25.5 / 30.5 mm; at the exact radius the same columns lie on the circle asked for, the
// bonds rest at their sites' distances and the bar rule keeps E_f t_f per unit width.

namespace foil_exact_radius_test {
constexpr double kRadii[] = {0.0205, 0.0255, 0.0305};  // [m] the paper's radius study
}  // namespace foil_exact_radius_test

// Every site on the circle asked for (to 1e-12 of it), the column and row counts of the paper's
// rule, the row bonds resting at the chord 2 R sin(pi / n), the column bonds at 2 r_f; the
// paper's rule itself lies 1.3 / 1.2 / -1.0% off these radii (the reason for the key).
TEST(FoilExactRadius, TheSitesLieOnTheCircleAskedFor) {
    const vpp::FoilDef f = vpp::Config().foil;
    for (double radius : foil_exact_radius_test::kRadii) {
        dem::World w, w0;
        const vpp::FoilLattice L = vpp::build_cylinder(w, f, radius, 0.04, 0.0, true);
        const vpp::FoilLattice L0 = vpp::build_cylinder(w0, f, radius, 0.04);
        EXPECT_EQ(L.cols, L0.cols);
        EXPECT_EQ(L.rows, L0.rows);
        EXPECT_EQ(L.particles.size(), L0.particles.size());
        EXPECT_EQ(w.bonds().size(), w0.bonds().size());
        EXPECT_EQ(L.radius, radius);
        for (uint32_t i : L.particles)
            ASSERT_NEAR(std::hypot(w.particles.pos[i].x, w.particles.pos[i].y), radius, 1e-12 * radius);
        const double chord = 2.0 * radius * std::sin(std::numbers::pi / L.cols);
        EXPECT_NEAR(L.column_pitch, chord, 1e-15);
        for (const vpp::LatticeBond& b : L.bonds)
            ASSERT_NEAR(w.bonds().phys[b.index].rest_length, b.along_row ? chord : 2.0 * f.particle_radius,
                        1e-12 * chord);
        std::printf("r_p %.1f mm: %d columns; the paper's rule %.4f mm (%+.2f%%), exact %.4f mm, chord %.4f r_f\n",
                    1e3 * radius, L.cols, 1e3 * L0.radius, 100.0 * (L0.radius / radius - 1.0), 1e3 * L.radius,
                    chord / f.particle_radius);
        EXPECT_GT(std::abs(L0.radius / radius - 1.0), 0.009);  // the rule's circle is not the radius
    }
}

// As built, no bond carries a force: each rests at its sites' distance (the forces of the first
// compute_forces below 1e-9 of a bond's force at 1% strain... strain 1e-9).
TEST(FoilExactRadius, TheBondsStartUnstressed) {
    const vpp::FoilDef f = vpp::Config().foil;
    for (double radius : foil_exact_radius_test::kRadii) {
        dem::World w;
        const vpp::FoilLattice L = vpp::build_cylinder(w, f, radius, 0.04, 0.0, true);
        w.params.gravity = {0, 0, 0};
        w.params.dt = 1e-7;
        w.compute_forces();
        double worst = 0;
        for (const vpp::LatticeBond& b : L.bonds) {
            const dem::BondPhys& ph = w.bonds().phys[b.index];
            worst = std::max(worst, norm(w.bonds().force[b.index]) / (ph.kn * ph.rest_length));
        }
        std::printf("r_p %.1f mm: largest bond force / (kn L0) %.3g\n", 1e3 * radius, worst);
        EXPECT_LT(worst, 1e-9);
    }
}

// The foil's stiffness per unit width stays the rules' E_f t_f both ways: a uniform hoop (axial)
// strain eps gives N_theta (N_z) = E_f t_f eps times the polygon factor n sin(pi/n) / pi of the
// virial, to 1e-9 (linear springs, exact strain). The paper's bond kn = 2 E_f t_f on chords of
// 2 R sin(pi/n) would be off by the chord's ratio to 2 r_f: -1.3 / -1.2 / +1.0%.
TEST(FoilExactRadius, TheFoilKeepsItsStiffnessPerUnitWidth) {
    const vpp::FoilDef f = vpp::Config().foil;
    const double Et = f.young * f.thickness, eps = 1e-3;
    for (double radius : foil_exact_radius_test::kRadii)
        for (bool hoop : {true, false}) {
            dem::World w;
            const vpp::FoilLattice L = vpp::build_cylinder(w, f, radius, 0.04, 0.0, true);
            const vpp::FoilTension t = foil_tension_test::stretched(w, L, hoop ? eps : 0.0, hoop ? 0.0 : eps);
            const double expected = Et * eps * foil_tension_test::polygon_factor(L.cols);
            const double got = hoop ? t.hoop : t.axial;
            std::printf("r_p %.1f mm, %s strain %g: %.9g N/m against %.9g N/m\n", 1e3 * radius, hoop ? "hoop" : "axial",
                        eps, got, expected);
            EXPECT_NEAR(got / expected, 1.0, 1e-9);
        }
}

// Under an internal overpressure p the exact-radius cylinder (30.5 mm: the longest chords, 1%
// past 2 r_f) takes the membrane's hoop strain p R / (E_f t_f) at mid-height, as the paper's
// cylinder does (Foil.HoopStrainUnderInternalPressure: +0.2%), within 0.5% (measured +0.3%): the
// rows' chains carry the rules' stiffness per unit height. The paper's kn on these chords would
// give -0.7% (the chords' 1.0097 times 2 r_f stiffens the rows by that much).
TEST(FoilExactRadius, HoopStrainUnderInternalPressure) {
    const auto [strain, expected] = foil_hoop_test::hoop_strain_under_pressure(0.0305, true);
    std::printf("exact radius 30.5 mm: hoop strain %.6g, membrane theory %.6g, ratio %.4f\n", strain, expected,
                strain / expected);
    EXPECT_NEAR(strain / expected, 1.0, 0.005);
}
