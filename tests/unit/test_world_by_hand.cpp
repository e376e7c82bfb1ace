// A World changed by hand between steps (walls or particles added, flags set): what the API
// accepts keeps the state consistent, and what it cannot make consistent it refuses with a
// message, before anything is changed. And the kinetic energy the applications read off the
// particle arrays.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/world/world.h"

using namespace dem;

namespace {

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }

// 60 grains (radius 4 mm) on a ramp of 8 facets tilted 15 degrees (friction 0.5, restitution 0.1:
// they settle in 0.02 s and roll slowly down, from facet to facet, with shear springs), a floor
// plane under it; with `far_plane`, a plane 10 m away (never
// touched) is added before the facets, so that the walls are numbered as after
// add_plane(far) on the world without it.
World ramp(bool far_plane) {
    World w;
    w.params.gravity = {0, 0, -9.81};
    w.params.local_damping = 0.5;
    Material m;
    m.young = 1e7;
    m.friction = 0.5;
    m.restitution = 0.1;
    w.add_material(m);
    Plane floor;
    floor.point = {0, 0, -0.05};
    floor.normal = {0, 0, 1};
    w.add_plane(floor);
    if (far_plane) {
        Plane far;
        far.point = {0, 0, 10};
        far.normal = {0, 0, -1};
        w.add_plane(far);
    }
    const double t = std::tan(15.0 * std::acos(-1.0) / 180.0), L = 0.025;  // [-], [m] the strips' width
    const auto z = [&](double x) { return -t * x; };
    for (int k = 0; k < 4; ++k) {
        const double x0 = k * L, x1 = (k + 1) * L;
        Facet f;
        f.vertices = {Vec3{x0, 0, z(x0)}, Vec3{x1, 0, z(x1)}, Vec3{x1, 0.1, z(x1)}};
        w.add_facet(f);
        f.vertices = {Vec3{x0, 0, z(x0)}, Vec3{x1, 0.1, z(x1)}, Vec3{x0, 0.1, z(x0)}};
        w.add_facet(f);
    }
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 10; ++i) {
            SphereDef s;
            s.radius = 0.004;
            const double x = 0.005 + 0.0095 * i;
            s.position = {x, 0.01 + 0.016 * j + 0.001 * (i % 3), z(x) + 0.0045 / std::cos(std::atan(t))};
            w.add_sphere(s);
        }
    w.params.dt = 0.2 * w.critical_dt();
    return w;
}

void run(World& w, int steps) {
    for (int s = 0; s < steps; ++s) w.step();
}

}  // namespace

// A plane added after the facets numbers every facet one higher: their contacts must follow, each
// keeping its own shear history. Against the world that had the (never touched) plane from the
// start, rebuilt at the same step: the same state bit for bit, also the reactions per wall right
// after the plane came. (Before the contacts followed, a grain's spring on facet f went to facet
// f - 1, or was dropped: found by a review of what a checkpoint saves after a hand change.)
TEST(WorldByHand, APlaneAddedAfterTheFacetsLeavesEachFacetItsContacts) {
    World ref = ramp(true), w = ramp(false);
    run(ref, 4000);
    run(w, 4000);
    std::size_t on_facets = 0;
    w.for_each_touching([&](const TouchingContact& c) { on_facets += c.wall && c.j >= 1; });
    ASSERT_GT(on_facets, 30u);  // the grains rest on several facets
    Plane far;
    far.point = {0, 0, 10};
    far.normal = {0, 0, -1};
    EXPECT_EQ(w.add_plane(far), 1u);
    ref.invalidate_candidates();
    ASSERT_EQ(w.wall_count(), ref.wall_count());
    for (std::size_t k = 0; k < w.wall_count(); ++k) {
        EXPECT_EQ(bits(w.wall_force(k).x), bits(ref.wall_force(k).x)) << "wall " << k;
        EXPECT_EQ(bits(w.wall_force(k).z), bits(ref.wall_force(k).z)) << "wall " << k;
    }
    EXPECT_EQ(w.broken_invariant(), nullptr);
    run(ref, 2000);
    run(w, 2000);
    std::vector<TouchingContact> a, b;
    ref.for_each_touching([&](const TouchingContact& c) { a.push_back(c); });
    w.for_each_touching([&](const TouchingContact& c) { b.push_back(c); });
    ASSERT_EQ(a.size(), b.size());
    std::size_t differ = 0;
    for (std::size_t c = 0; c < a.size(); ++c)
        differ += a[c].i != b[c].i || a[c].j != b[c].j || bits(a[c].shear.x) != bits(b[c].shear.x) ||
                  bits(a[c].force.z) != bits(b[c].force.z);
    EXPECT_EQ(differ, 0u);
    for (std::size_t i = 0; i < w.particles.size(); ++i)
        for (int d = 0; d < 3; ++d)
            ASSERT_EQ(bits(w.particles.pos[i][d]), bits(ref.particles.pos[i][d])) << "particle " << i;
}

// What would leave the world unable to step, or a checkpoint unable to load, is refused with a
// message, the world unchanged.
TEST(WorldByHand, RefusesWhatItCannotMakeConsistent) {
    World w = ramp(false);
    const std::size_t n = w.particles.size(), nw = w.wall_count();
    const auto refused = [&](auto&& f, const std::string& what) {
        try {
            f();
            ADD_FAILURE() << "no exception; expected '" << what << "'";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    Plane p;
    p.material = 3;
    refused([&] { w.add_plane(p); }, "plane material index out of range");
    Facet f;
    f.vertices = {Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{0, 1, 1}};
    f.material = 1;
    refused([&] { w.add_facet(f); }, "facet material index out of range");
    SphereDef s;
    s.radius = 0.004;
    s.flags = kPrescribed;
    refused([&] { w.add_sphere(s); }, "set by set_prescribed() and add_clump()");
    s.flags = kClumpMember;
    refused([&] { w.add_sphere(s); }, "set by set_prescribed() and add_clump()");
    refused([&] { w.set_fixed(uint32_t(n)); }, "set_fixed: particle 60 does not exist (60 particles)");
    refused([&] { w.set_prescribed(uint32_t(n), 0); }, "set_prescribed: particle 60 does not exist");
    refused([&] { w.set_prescribed(0, 0); }, "set_prescribed: motion 0 does not exist (0 motions)");
    EXPECT_EQ(w.particles.size(), n);
    EXPECT_EQ(w.wall_count(), nw);
    EXPECT_EQ(w.broken_invariant(), nullptr);
    run(w, 10);  // and it still steps
}

// dem::kinetic_energy (dem/core/particles.h), the one sum the damper, the devices and the foil's
// envelope check read to tell a sample at rest: which particles count, and the same bits as the
// loops it replaced.
namespace {

// Five spheres by hand: free ones, one fixed (inverse mass and inertia 0) and one prescribed
// (inverse mass 0, turning freely) that still carry a velocity, so that leaving them out shows.
Particles five_spheres() {
    Particles p;
    const double mass[] = {2.0, 0.5, 3.0, 1.25, 0.1};
    const Vec3 vel[] = {{1, 0, 0}, {0.3, -0.2, 0.1}, {5, 5, 5}, {0, 0, -2}, {1e-3, 2e-3, -3e-3}};
    const Vec3 angvel[] = {{0, 0, 1}, {2, 0, 0}, {9, 9, 9}, {0.5, 0.5, 0}, {10, -10, 10}};
    for (int i = 0; i < 5; ++i) {
        p.pos.push_back({double(i), 0, 0});
        p.vel.push_back(vel[i]);
        p.angvel.push_back(angvel[i]);
        p.mass.push_back(mass[i]);
        p.inv_mass.push_back(1.0 / mass[i]);
        p.inv_inertia.push_back(1.0 / (0.4 * mass[i] * 0.01 * 0.01));
        p.flags.push_back(0);
    }
    p.inv_mass[2] = p.inv_inertia[2] = 0.0;  // fixed
    p.flags[2] = kFixed;
    p.inv_mass[3] = 0.0;  // prescribed: its translation follows a motion
    p.flags[3] = kPrescribed;
    return p;
}

}  // namespace

TEST(Particles, KineticEnergyCountsTheFreeParticlesOnly) {
    const Particles p = five_spheres();
    const KineticEnergy e = kinetic_energy(p, 0, 5);
    // Translation: particles 0, 1 and 4; rotation: 0, 1, 3 and 4.
    double t = 0, r = 0;
    for (int i : {0, 1, 4}) t += 0.5 * p.mass[i] * norm2(p.vel[i]);
    for (int i : {0, 1, 3, 4}) r += 0.5 / p.inv_inertia[i] * norm2(p.angvel[i]);
    EXPECT_EQ(bits(e.translation), bits(t));
    EXPECT_EQ(bits(e.rotation), bits(r));
    EXPECT_EQ(bits(e.total()), bits(t + r));
    EXPECT_DOUBLE_EQ(e.translation, 0.5 * 2.0 * 1.0 + 0.5 * 0.5 * 0.14 + 0.5 * 0.1 * 14e-6);
    // A range and a list of the same indices give the same bits; a list is summed in its order.
    const std::vector<uint32_t> ids = {0, 1, 2, 3, 4};
    const KineticEnergy l = kinetic_energy(p, ids);
    EXPECT_EQ(bits(l.translation), bits(e.translation));
    EXPECT_EQ(bits(l.rotation), bits(e.rotation));
    const std::vector<uint32_t> some = {4, 0};
    EXPECT_EQ(bits(kinetic_energy(p, some).translation),
              bits(0.5 * p.mass[4] * norm2(p.vel[4]) + 0.5 * p.mass[0] * norm2(p.vel[0])));
    // Nothing to sum: zero.
    EXPECT_EQ(kinetic_energy(p, 3, 3).total(), 0.0);
    EXPECT_EQ(kinetic_energy(p, std::span<const uint32_t>{}).total(), 0.0);
}

// The loops it replaced, as they were written: the damper's and the devices' grains (every sphere
// of a range, translation; grains are free) and the envelope's foil nodes (two passes, translation
// then rotation, each over the free ones), summed as they summed.
TEST(Particles, KineticEnergyGivesTheBitsOfTheLoopsItReplaced) {
    Particles p = five_spheres();
    p.inv_mass[2] = 1.0 / p.mass[2];  // every grain free, as a damper's are
    p.inv_mass[3] = 1.0 / p.mass[3];
    double grains = 0;
    for (uint32_t i = 1; i < 5; ++i) grains += 0.5 * p.mass[i] * norm2(p.vel[i]);
    EXPECT_EQ(bits(kinetic_energy(p, 1, 5).translation), bits(grains));
    p = five_spheres();
    const std::vector<uint32_t> nodes = {3, 1, 4, 0, 2};
    double tr = 0, rot = 0;
    for (uint32_t i : nodes)
        if (p.inv_mass[i] != 0.0) tr += 0.5 * p.mass[i] * norm2(p.vel[i]);
    for (uint32_t i : nodes)
        if (p.inv_inertia[i] != 0.0) rot += 0.5 / p.inv_inertia[i] * norm2(p.angvel[i]);
    const KineticEnergy e = kinetic_energy(p, nodes);
    EXPECT_EQ(bits(e.translation), bits(tr));
    EXPECT_EQ(bits(e.total()), bits(tr + rot));
}
