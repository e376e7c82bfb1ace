// The batch engine's bitwise comparisons on the tests' small damper (tests/physics/test_batch_damper.cpp
// and the device tests, tests/device): a case loaded from the sample after its cycle, and every
// bit a run reads compared (positions, velocities, spins, forces, contacts, wall forces, bonds'
// shear, the energy ledger).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dem/io/checkpoint.h"
#include "dem/world/world.h"

namespace batch_test {

using dem::World;

// The sample in `ckpt` (a run.ckpt after its cycle), at underpressure dp [Pa] and grain friction mu, with the
// top cap and the ring pressed down 2 mm over the next 0.03 s (past the 10,000 steps), its energy
// ledger started afresh (or off), every material's restitution (below 1: normal dashpots in every
// contact, grain, foil and cap, whose work the ledger books) as given.
inline World load_case(const std::string& ckpt, double dp, double mu, bool energy = true, double restitution = 1.0) {
    World w;
    dem::load_checkpoint(ckpt, w);
    w.params.track_energy = energy;
    w.reset_energy();
    w.pressure.dp = dp;
    w.materials[0].friction = mu;
    for (dem::Material& m : w.materials) m.restitution = restitution;  // grains, foil and caps
    w.invalidate_contact_physics();
    const double t1 = w.time + 0.03;
    const auto press = [&](dem::Motion& m) {
        if (m.history.empty()) return;
        m.history.push_back({t1, m.history.back().displacement + dem::Vec3{0, 0, -0.002}});
    };
    for (dem::Plane& p : w.planes) press(p.motion);
    for (dem::Motion& m : w.motions) press(m);
    return w;
}

// The mixed cases of the batch tests: two packings (seeds), two underpressures, two grain
// frictions; the ledger on in most; the cases at friction 0.6 with restitution 0.5 (normal
// dashpots in every contact, whose forward halves the ledger sums per block: two of them with the
// ledger on).
struct Case {
    int seed;
    double dp, mu;  // [Pa], [-]
    bool energy;
    double restitution;  // [-]
};
inline std::vector<Case> eight_cases() {
    std::vector<Case> cases;
    for (int seed : {1, 2})
        for (double dp : {40e3, 80e3})
            for (double mu : {0.2, 0.6}) cases.push_back({seed, dp, mu, cases.size() % 3 != 1, mu > 0.5 ? 0.5 : 1.0});
    return cases;
}

inline void expect_same(const World& a, const World& b, const std::string& what) {
    ASSERT_EQ(a.particles.size(), b.particles.size()) << what;
    ASSERT_EQ(a.steps, b.steps) << what;
    ASSERT_EQ(a.time, b.time) << what;
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
        ASSERT_EQ(a.particles.pos[i], b.particles.pos[i]) << what << ", particle " << i;
        ASSERT_EQ(a.particles.vel[i], b.particles.vel[i]) << what << ", particle " << i;
        ASSERT_EQ(a.particles.angvel[i], b.particles.angvel[i]) << what << ", particle " << i;
        ASSERT_EQ(a.particles.force[i], b.particles.force[i]) << what << ", particle " << i;
    }
    ASSERT_EQ(a.contact_count(), b.contact_count()) << what;
    for (std::size_t k = 0; k < a.wall_count(); ++k) ASSERT_EQ(a.wall_force(k), b.wall_force(k)) << what << ", wall " << k;
    for (std::size_t k = 0; k < a.bonds().size(); ++k) ASSERT_EQ(a.bonds().shear[k], b.bonds().shear[k]) << what;
    const dem::EnergyLedger &p = a.energy(), &q = b.energy();
    ASSERT_EQ(p.steps, q.steps) << what;
    const double pv[] = {p.boundary_work, p.pressure_work, p.gravity_work, p.external_work, p.friction_slip,
                         p.shear_release, p.damping_dissipation, p.viscous_dissipation, p.kinetic, p.elastic_contacts,
                         p.elastic_bonds, p.stored0, p.time, p.t0, p.pending_boundary, p.pending_pressure,
                         p.pending_gravity, p.pending_external, p.pending_damping, p.pending_viscous};
    const double qv[] = {q.boundary_work, q.pressure_work, q.gravity_work, q.external_work, q.friction_slip,
                         q.shear_release, q.damping_dissipation, q.viscous_dissipation, q.kinetic, q.elastic_contacts,
                         q.elastic_bonds, q.stored0, q.time, q.t0, q.pending_boundary, q.pending_pressure,
                         q.pending_gravity, q.pending_external, q.pending_damping, q.pending_viscous};
    for (std::size_t k = 0; k < std::size(pv); ++k) ASSERT_EQ(pv[k], qv[k]) << what << ", ledger entry " << k;
}

}  // namespace batch_test
