// The seal between membrane and object (vpp/device/suction.h) against closed forms: on a flat
// patch of membrane particles lying on a flat object, a sealed pocket lifted uniformly by dz
// holds its air at p = p_amb h0 / (h0 + dz) (isothermal gas law) and pulls the object with
// (p_amb - p) times the pocket's area; a pocket that reaches the footprint's rim refills through
// it as the isothermal slit flow's closed form says, and once full pulls nothing; the forces on particles and object sum to zero; pockets that merge keep their air.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vpp/device/suction.h"

namespace suction_test {

using dem::Vec3;

// An n x n square grid of particles of radius r at spacing 2r, at height z = r (touching the
// plane z = 0). The inner (n-2) x (n-2) are the fans' nodes, each with its 4 neighbours as its
// ring (so the grid's outer row is off the fans: the footprint's rim lies next to it).
struct Patch {
    int n;
    double r;
    std::vector<Vec3> pos;
    dem::PressureFans fans;
    uint32_t at(int i, int j) const { return uint32_t(i * n + j); }
    Patch(int n_, double r_) : n(n_), r(r_) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) pos.push_back({2 * r * i, 2 * r * j, r});
        fans.start.push_back(0);
        for (int i = 1; i < n - 1; ++i)
            for (int j = 1; j < n - 1; ++j) {
                fans.node.push_back(at(i, j));
                for (uint32_t q : {at(i + 1, j), at(i, j + 1), at(i - 1, j), at(i, j - 1)}) fans.ring.push_back(q);
                fans.start.push_back(uint32_t(fans.ring.size()));
            }
    }
};

// A square plate z = 0 (two facets, normal +z) covering [-L, L]^2 around (cx, cy).
std::vector<dem::Facet> plate(double cx, double cy, double L) {
    dem::Facet a, b;
    a.vertices = {Vec3{cx - L, cy - L, 0}, Vec3{cx + L, cy - L, 0}, Vec3{cx + L, cy + L, 0}};
    b.vertices = {Vec3{cx - L, cy - L, 0}, Vec3{cx + L, cy + L, 0}, Vec3{cx - L, cy + L, 0}};
    return {a, b};
}

constexpr int kN = 9;
constexpr double kR = 5e-4;
constexpr double kDt = 1e-7;   // [s] a step of the gripper's order
constexpr double kLong = 1.0;  // [s] a step past any leak's time: an open rim refills the pocket in it

struct Fixture {
    Patch patch{kN, kR};
    vpp::SuctionDef def;
    vpp::SuctionSeal seal;
    std::vector<Vec3> ext;
    Fixture() {
        def.enabled = true;
        def.gap = 1e-5;
        def.ambient = 1e5;
        const double c = 2 * kR * (kN - 1) / 2.0;
        seal = vpp::capture_seal(patch.fans, patch.pos, kR, plate(c, c, 1.0), Vec3{}, def);
        ext.assign(patch.pos.size(), Vec3{});
    }
    // Local footprint index of grid particle (i, j), -1 when not in it.
    int local(int i, int j) const {
        for (std::size_t k = 0; k < seal.particle.size(); ++k)
            if (seal.particle[k] == patch.at(i, j)) return int(k);
        return -1;
    }
    bool is_rim(int i, int j) const { return i == 1 || j == 1 || i == kN - 2 || j == kN - 2; }
};

TEST(Suction, CaptureTakesTheParticlesOnTheObjectWithTheirNormalsAndRim) {
    Fixture f;
    ASSERT_EQ(f.seal.particle.size(), std::size_t((kN - 2) * (kN - 2)));  // every fan node touches the plate
    for (std::size_t k = 0; k < f.seal.particle.size(); ++k) {
        EXPECT_NEAR(f.seal.normal[k].z, 1.0, 1e-12);
        EXPECT_NEAR(f.seal.gap0[k], 0.0, 1e-15);
        EXPECT_NEAR(f.seal.area[k], 4.0 * (2 * kR) * (2 * kR) / 6.0, 1e-18);  // the 4-ring's fan: 2/3 h^2
    }
    for (int i = 1; i < kN - 1; ++i)
        for (int j = 1; j < kN - 1; ++j) EXPECT_EQ(f.seal.rim[std::size_t(f.local(i, j))], f.is_rim(i, j) ? 1 : 0);
    // A particle lifted past `capture` is not in the footprint.
    Fixture g;
    g.patch.pos[g.patch.at(4, 4)].z += 1e-6;
    const double c = 2 * kR * (kN - 1) / 2.0;
    g.seal = vpp::capture_seal(g.patch.fans, g.patch.pos, kR, plate(c, c, 1.0), Vec3{}, g.def);
    EXPECT_EQ(g.seal.particle.size(), std::size_t((kN - 2) * (kN - 2) - 1));
}

TEST(Suction, ASealedPocketFollowsTheGasLawAndPullsTheObject) {
    for (double dz : {2e-6, 1e-5, 1e-4}) {
        Fixture f;
        int lifted = 0;
        for (int i = 1; i < kN - 1; ++i)
            for (int j = 1; j < kN - 1; ++j)
                if (!f.is_rim(i, j)) {
                    f.patch.pos[f.patch.at(i, j)].z += dz;
                    ++lifted;
                }
        const vpp::SuctionStep s = vpp::step_seal(f.seal, f.patch.pos, Vec3{}, kDt, f.def, f.ext);
        const double p = f.def.ambient * f.def.gap / (f.def.gap + dz);
        const double area = lifted * f.seal.area[0];
        EXPECT_EQ(s.sealed, std::size_t(lifted));
        EXPECT_EQ(s.leaked, 0u);
        EXPECT_NEAR(s.pressure_min, p, 1e-9 * f.def.ambient);
        EXPECT_NEAR(s.object_force.z, (f.def.ambient - p) * area, 1e-9 * f.def.ambient * area);
        EXPECT_NEAR(s.object_force.x, 0.0, 1e-12);
        EXPECT_NEAR(s.sealed_volume, area * (f.def.gap + dz), 1e-9 * area * dz);
        // The object pulled down by dz, the rim following it, instead of the rest lifted: the
        // same opening, the same pull.
        Fixture g;
        for (int i = 1; i < kN - 1; ++i)
            for (int j = 1; j < kN - 1; ++j)
                if (g.is_rim(i, j)) g.patch.pos[g.patch.at(i, j)].z -= dz;
        const vpp::SuctionStep t = vpp::step_seal(g.seal, g.patch.pos, Vec3{0, 0, -dz}, kDt, g.def, g.ext);
        EXPECT_EQ(t.sealed, std::size_t(lifted));
        EXPECT_NEAR(t.object_force.z, s.object_force.z, 1e-9 * s.object_force.z);
        // The rim not following: every particle open, the pocket leaks.
        Fixture h;
        const vpp::SuctionStep l = vpp::step_seal(h.seal, h.patch.pos, Vec3{0, 0, -dz}, kLong, h.def, h.ext);
        EXPECT_EQ(l.sealed, 0u);
        EXPECT_EQ(l.leaked, std::size_t((kN - 2) * (kN - 2)));
        EXPECT_EQ(l.object_force.z, 0.0);
    }
}

TEST(Suction, APocketReachingTheRimLeaksAndPullsNothing) {
    Fixture f;
    for (int i = 2; i < kN - 2; ++i)
        for (int j = 2; j < kN - 2; ++j) f.patch.pos[f.patch.at(i, j)].z += 1e-5;
    f.patch.pos[f.patch.at(1, 4)].z += 1e-5;  // a rim particle opens next to the pocket: a channel out
    const vpp::SuctionStep s = vpp::step_seal(f.seal, f.patch.pos, Vec3{}, kLong, f.def, f.ext);
    EXPECT_EQ(s.sealed, 0u);
    EXPECT_EQ(s.leaked, std::size_t((kN - 4) * (kN - 4) + 1));
    EXPECT_EQ(s.object_force.z, 0.0);
    EXPECT_EQ(s.pressure_min, f.def.ambient);
    for (const Vec3& e : f.ext) EXPECT_EQ(norm(e), 0.0);
    // Its air is the surroundings' now: closing it again and reopening finds ambient air.
    const int k = f.local(4, 4);
    EXPECT_NEAR(f.seal.air[std::size_t(k)], f.def.ambient * f.seal.area[std::size_t(k)] * (f.def.gap + 1e-5), 1e-20);
}

TEST(Suction, AnOpenRimRefillsThePocketAsTheSlitFlowSays) {
    // A pocket of fixed shape leaking through one rim slit of height h: d(pV)/dt = K (pa^2 - p^2),
    // K = h^3 / (24 mu), so p(t) = pa tanh(pa K t / V + atanh(p0 / pa)).
    Fixture f;
    const double dz = 2e-5, h = 3e-6;
    for (int i = 1; i < kN - 1; ++i)
        for (int j = 1; j < kN - 1; ++j)
            if (!f.is_rim(i, j)) f.patch.pos[f.patch.at(i, j)].z += dz;
    f.patch.pos[f.patch.at(1, 4)].z += h;
    double air = 0, v = 0;
    for (std::size_t k = 0; k < f.seal.particle.size(); ++k) {
        const double g = f.patch.pos[f.seal.particle[k]].z - kR;
        if (g > 0.01 * f.def.gap) {
            air += f.seal.air[k];
            v += f.seal.area[k] * (f.def.gap + g);
        }
    }
    const double pa = f.def.ambient, K = h * h * h / (24.0 * f.def.viscosity), p0 = air / v;
    const double tau = v / (pa * K);  // the refill's time scale [s]
    const int steps = 4000;
    const double dt = 1.5 * tau / steps;
    vpp::SuctionStep s;
    for (int n = 0; n < steps; ++n) s = vpp::step_seal(f.seal, f.patch.pos, Vec3{}, dt, f.def, f.ext);
    const double t = steps * dt;
    const double expected = pa * std::tanh(pa * K * t / v + std::atanh(p0 / pa));
    EXPECT_LT(p0, 0.5 * pa);
    EXPECT_NEAR(s.pressure_min, expected, 1e-3 * pa);  // explicit steps of tau / 2700
    EXPECT_GT(s.pressure_min, p0 + 0.3 * (pa - p0));     // it did refill a good part
}

TEST(Suction, ForcesOnParticlesAndObjectSumToZero) {
    Fixture f;
    uint64_t state = 12345;
    for (int i = 2; i < kN - 2; ++i)
        for (int j = 2; j < kN - 2; ++j) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            f.patch.pos[f.patch.at(i, j)] += Vec3{1e-6, -2e-6, 3e-5 * double(state >> 11) * 0x1.0p-53};
        }
    const vpp::SuctionStep s = vpp::step_seal(f.seal, f.patch.pos, Vec3{}, kDt, f.def, f.ext);
    ASSERT_GT(s.sealed, 0u);
    Vec3 sum = s.object_force;
    for (const Vec3& e : f.ext) sum += e;
    EXPECT_LT(norm(sum), 1e-12 * norm(s.object_force));
    EXPECT_GT(s.object_force.z, 0.0);
}

TEST(Suction, PocketsThatMergeKeepTheirAir) {
    Fixture f;
    // Two pockets, columns 2-3 and 5-6, split by the closed column 4; then column 4 opens too.
    auto lift = [&](int j0, int j1, double dz) {
        for (int i = 2; i < kN - 2; ++i)
            for (int j = j0; j <= j1; ++j) f.patch.pos[f.patch.at(i, j)].z += dz;
    };
    lift(2, 3, 1e-5);
    lift(5, 6, 3e-5);
    const vpp::SuctionStep a = vpp::step_seal(f.seal, f.patch.pos, Vec3{}, kDt, f.def, f.ext);
    EXPECT_EQ(a.sealed, std::size_t(4 * (kN - 4)));
    double air = 0;
    for (double m : f.seal.air) air += m;
    lift(4, 4, 2e-5);
    const vpp::SuctionStep b = vpp::step_seal(f.seal, f.patch.pos, Vec3{}, kDt, f.def, f.ext);
    EXPECT_EQ(b.sealed, std::size_t(5 * (kN - 4)));
    double after = 0;
    for (double m : f.seal.air) after += m;
    EXPECT_NEAR(after, air, 1e-12 * air);  // the closed column's own film joins: counted in both sums
    // One pressure over the merged pocket: p = its air over its volume.
    EXPECT_NEAR(b.pressure_min * b.sealed_volume, [&] {
        double m = 0;
        for (int i = 2; i < kN - 2; ++i)
            for (int j = 2; j <= 6; ++j) m += f.seal.air[std::size_t(f.local(i, j))];
        return m;
    }(), 1e-9 * air);
}

}  // namespace suction_test
