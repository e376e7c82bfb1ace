// Checkpoints: a run stopped and resumed from a checkpoint must give results bitwise identical
// to the uninterrupted run; damaged, foreign or future files must be refused with the path in
// the message; saving must be atomic.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/clumps/clump_shape.h"
#include "dem/world/world.h"
#include "dem/io/checkpoint.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_checkpoint {

using namespace dem;
namespace fs = std::filesystem;

namespace {

// 300 spheres on a jittered 10 x 10 x 3 lattice (radii 4.5-5 mm, pitch 9.5 mm: many pairs
// start overlapping), random velocities, friction, gravity, local damping 0.2, a box of
// one-sided planes whose lid follows a displacement history, two facets moving with a
// constant velocity, a bonded 10 x 4 membrane on top with follower pressure, one prescribed
// and one fixed particle, and an external force on one particle.
World make_scene(uint64_t seed = 12345) {
    World w;
    w.params.gravity = {0, 0, -9.81};
    w.params.local_damping = 0.2;
    Material grain;
    grain.name = "grain \xff\x01";
    grain.young = 1e6;
    grain.friction = 0.5;
    grain.restitution = 0.7;
    w.add_material(grain);
    Material wall;
    wall.name = "wall";
    wall.young = 2e6;
    wall.friction = 0.3;
    w.add_material(wall);

    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> rad(0.0045, 0.005), jit(-0.0003, 0.0003), vel(-0.5, 0.5);
    const double pitch = 0.0095;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 10; ++i) {
                SphereDef s;
                s.radius = rad(rng);
                s.position = {0.006 + i * pitch + jit(rng), 0.006 + j * pitch + jit(rng),
                              0.008 + k * pitch + jit(rng)};
                s.velocity = {vel(rng), vel(rng), vel(rng) - 0.3};
                s.angular_velocity = {vel(rng) * 20, vel(rng) * 20, vel(rng) * 20};
                w.add_sphere(s);
            }
    const double box = 0.1;
    auto plane = [&](Vec3 pt, Vec3 n) {
        Plane p;
        p.point = pt;
        p.normal = n;
        p.material = 1;
        p.one_sided = true;
        return w.add_plane(p);
    };
    plane({0, 0, 0}, {0, 0, 1});
    plane({0, 0, 0}, {1, 0, 0});
    plane({box, 0, 0}, {-1, 0, 0});
    plane({0, 0, 0}, {0, 1, 0});
    plane({0, box, 0}, {0, -1, 0});
    // Lid: starts above the packing and is pushed down (piecewise-linear history).
    const uint32_t lid = plane({0, 0, 0.045}, {0, 0, -1});
    w.planes[lid].motion.history = {{0.0, {0, 0, 0}}, {0.04, {0, 0, -0.01}}, {0.08, {0, 0, -0.012}},
                                    {0.2, {0, 0, -0.02}}};
    // Two facets (a ramp under the packing) drifting sideways, and a blade sweeping through.
    Facet f;
    f.material = 1;
    f.motion.velocity = {0.01, 0.0, 0.0};
    f.vertices = {Vec3{0, 0, 0.002}, Vec3{box, 0, 0.004}, Vec3{box, box, 0.004}};
    w.add_facet(f);
    f.vertices = {Vec3{0, 0, 0.002}, Vec3{box, box, 0.004}, Vec3{0, box, 0.002}};
    w.add_facet(f);
    f.one_sided = false;
    f.motion.velocity = {0.0, 0.05, 0.0};
    f.vertices = {Vec3{0.05, 0.0, 0.005}, Vec3{0.05, 0.03, 0.005}, Vec3{0.05, 0.015, 0.035}};
    w.add_facet(f);

    // The top layer's first 4 rows (40 particles) form a membrane: chain bonds along the rows
    // and the columns, and follower pressure on the interior nodes with 4-neighbour rings.
    auto idx = [](int i, int j) { return uint32_t((2 * 10 + j) * 10 + i); };
    const double kb = 1e6 * 0.005;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 10; ++i) {
            if (i + 1 < 10) w.add_bond(idx(i, j), idx(i + 1, j), kb, 0.5 * kb);
            if (j + 1 < 4) w.add_bond(idx(i, j), idx(i, j + 1), kb, 0.4 * kb);
        }
    for (int j = 1; j < 3; ++j)
        for (int i = 1; i < 9; i += 2)
            w.pressure.nodes.push_back(
                {idx(i, j), {idx(i + 1, j), idx(i, j + 1), idx(i - 1, j), idx(i, j - 1)}});
    w.pressure.dp = 5.0;

    Motion m;
    m.velocity = {0.0, 0.0, 0.2};
    w.set_prescribed(55, w.add_motion(m));  // a piston particle pushed up through the packing
    w.set_fixed(7);
    w.particles.ext_force.resize(w.particles.size());
    w.particles.ext_force[123] = {0.0, 0.01, 0.0};
    w.params.dt = 0.2 * w.critical_dt();
    return w;
}

void run(World& w, int steps) {
    for (int s = 0; s < steps; ++s) w.step();
}

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }

// Bitwise comparison of everything observable.
void expect_same(const World& a, const World& b) {
    ASSERT_EQ(a.particles.size(), b.particles.size());
    EXPECT_EQ(bits(a.time), bits(b.time));
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.rebuild_count(), b.rebuild_count());
    EXPECT_EQ(a.contact_count(), b.contact_count());
    std::size_t mismatches = 0;
    std::string first;  // where the first difference is, for the failure message
    auto cmp = [&](const Vec3& x, const Vec3& y, const char* what = "", std::size_t k = 0) {
        for (int d = 0; d < 3; ++d)
            if (bits(x[d]) != bits(y[d]) && mismatches++ == 0)
                first = std::string(what) + "[" + std::to_string(k) + "]." + "xyz"[d];
    };
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
        cmp(a.particles.pos[i], b.particles.pos[i], "pos", i);
        cmp(a.particles.vel[i], b.particles.vel[i], "vel", i);
        cmp(a.particles.angvel[i], b.particles.angvel[i], "angvel", i);
        cmp(a.particles.force[i], b.particles.force[i], "force", i);
        cmp(a.particles.torque[i], b.particles.torque[i], "torque", i);
        cmp(a.velocity_at_time(i), b.velocity_at_time(i), "velocity_at_time", i);
    }
    ASSERT_EQ(a.wall_count(), b.wall_count());
    for (std::size_t k = 0; k < a.wall_count(); ++k) {
        cmp(a.wall_force(k), b.wall_force(k), "wall_force", k);
        cmp(a.wall_torque(k), b.wall_torque(k), "wall_torque", k);
    }
    ASSERT_EQ(a.bonds().size(), b.bonds().size());
    for (std::size_t k = 0; k < a.bonds().size(); ++k) {
        cmp(a.bonds().shear[k], b.bonds().shear[k], "bond_shear", k);
        cmp(a.bonds().force[k], b.bonds().force[k], "bond_force", k);
    }
    ASSERT_EQ(a.candidate_count(), b.candidate_count());
    std::vector<TouchingContact> ca, cb;
    a.for_each_touching([&](const TouchingContact& c) { ca.push_back(c); });
    b.for_each_touching([&](const TouchingContact& c) { cb.push_back(c); });
    ASSERT_EQ(ca.size(), cb.size());
    for (std::size_t c = 0; c < ca.size(); ++c) {
        EXPECT_TRUE(ca[c].i == cb[c].i && ca[c].j == cb[c].j && ca[c].wall == cb[c].wall) << "contact " << c;
        cmp(ca[c].shear, cb[c].shear, "contact_shear", c);
        cmp(ca[c].force, cb[c].force, "contact_force", c);
    }
    EXPECT_EQ(mismatches, 0u) << "first difference at " << first;
}

// A fresh directory per test (ctest runs tests side by side).
fs::path temp_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("vppdem_ckpt_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::string& s) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << s;
}

// Loading `path` must throw a runtime_error whose message names the path and contains `what`.
void expect_load_error(const fs::path& path, const std::string& what) {
    World w = make_scene();
    const uint64_t steps = w.steps;
    try {
        load_checkpoint(path.string(), w);
        ADD_FAILURE() << "no exception for " << path;
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
        EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
    EXPECT_EQ(w.steps, steps);  // a failed load leaves the world alone
    EXPECT_EQ(w.particles.size(), 300u);
}

}  // namespace

TEST(Checkpoint, ResumedRunIsBitwiseIdentical) {
    const fs::path dir = temp_dir("resume");
    const std::string path = (dir / "state.ckpt").string();
    World ref = make_scene();
    run(ref, 500);
    save_checkpoint(path, ref, "stage=settle");
    const Vec3 lid_force = ref.wall_force(5), lid_point = ref.plane_point(5);
    run(ref, 500);
    // The scene must exercise what a restart could break: contacts with history, wall and
    // facet contacts, candidate rebuilds after the restart.
    EXPECT_GT(ref.particle_contact_count(), 100u);
    EXPECT_GT(ref.contact_count() - ref.particle_contact_count(), 10u);

    World resumed;
    EXPECT_EQ(load_checkpoint(path, resumed), "stage=settle");
    EXPECT_EQ(resumed.steps, 500u);
    // Queries right after loading answer as in the saved world.
    EXPECT_EQ(bits(resumed.wall_force(5).z), bits(lid_force.z));
    EXPECT_EQ(bits(resumed.plane_point(5).z), bits(lid_point.z));
    const uint64_t rebuilds_at_save = resumed.rebuild_count();
    // Saving the restored world gives the same bytes: nothing was lost on the way.
    save_checkpoint((dir / "again.ckpt").string(), resumed, "stage=settle");
    EXPECT_EQ(read_bytes(dir / "again.ckpt"), read_bytes(path));

    run(resumed, 500);
    EXPECT_GT(resumed.rebuild_count(), rebuilds_at_save);
    expect_same(ref, resumed);

    // Loading over a populated world replaces it entirely.
    World dirty = make_scene(999);
    run(dirty, 20);
    dirty.add_material(Material{});
    load_checkpoint(path, dirty);
    EXPECT_EQ(dirty.materials.size(), 2u);
    EXPECT_EQ(dirty.materials[0].name, "grain \xff\x01");
    run(dirty, 500);
    expect_same(ref, dirty);
    fs::remove_all(dir);
}

// The bonds' arm (BondArm) acts in World's bond kernel, is saved (section BARM, only when not
// the default) and restored: a resumed run with the bond-point arm gives the same bits, and a
// file of the default arm loaded over a bond-point world sets it back.
TEST(Checkpoint, TheBondArmActsAndIsRestored) {
    const fs::path dir = temp_dir("arm");
    const std::string path = (dir / "arm.ckpt").string(), plain = (dir / "plain.ckpt").string();
    World ref = make_scene(), radius = make_scene();
    ref.set_bond_arm(BondArm::kBondPoint);
    run(ref, 300);
    run(radius, 300);
    save_checkpoint(path, ref, "");
    save_checkpoint(plain, radius, "");
    EXPECT_NE(read_bytes(path).find("BARM"), std::string::npos);
    EXPECT_EQ(read_bytes(plain).find("BARM"), std::string::npos);  // the default's files as before
    run(ref, 300);
    run(radius, 300);
    // The arm changes the bonds' shear springs (their bonds turn as the membrane is pushed).
    double diff = 0;
    for (std::size_t b = 0; b < ref.bonds().size(); ++b) diff += norm(ref.bonds().shear[b] - radius.bonds().shear[b]);
    EXPECT_GT(diff, 0.0);
    World resumed;
    load_checkpoint(path, resumed);
    EXPECT_EQ(resumed.bonds().arm, BondArm::kBondPoint);
    run(resumed, 300);
    expect_same(ref, resumed);
    load_checkpoint(plain, resumed);
    EXPECT_EQ(resumed.bonds().arm, BondArm::kRadius);
    run(resumed, 300);
    expect_same(radius, resumed);
    fs::remove_all(dir);
}

// Stopping after every single step catches state that matters only at particular moments
// (e.g. the displacement since the last rebuild when a rebuild is due in the next step).
TEST(Checkpoint, RestartAfterEveryStepIsBitwiseIdentical) {
    const fs::path dir = temp_dir("every");
    const std::string path = (dir / "s.ckpt").string();
    World ref = make_scene();
    run(ref, 300);
    World chain = ref;
    const uint64_t rebuilds0 = ref.rebuild_count();
    for (int s = 0; s < 150; ++s) {
        save_checkpoint(path, chain, std::to_string(s));
        World next;
        ASSERT_EQ(load_checkpoint(path, next), std::to_string(s));
        chain = std::move(next);
        chain.step();
    }
    run(ref, 150);
    EXPECT_GE(ref.rebuild_count(), rebuilds0 + 3);  // rebuilds happen inside the chain
    expect_same(ref, chain);
    fs::remove_all(dir);
}

// A world changed by hand between steps (grains added, as the damper's re-fill does, spheres or
// clumps; the facets removed, as the end of its compression does) rebuilds its candidate lists
// only at the next step. A checkpoint taken right then must load and resume bit for bit: a
// damper killed after the re-fill's checkpoint could not be resumed ("candidate list of the
// wrong shape"; after the funnel went: "contact index out of range"; found by
// tools/kill_resume.py).
TEST(Checkpoint, AWorldChangedByHandResumesBeforeItsNextStep) {
    const fs::path dir = temp_dir("by_hand");
    const std::string path = (dir / "s.ckpt").string();
    for (const std::string change : {"spheres added", "a clump added", "facets cleared"}) {
        SCOPED_TRACE(change);
        World ref = make_scene();
        run(ref, 3);
        // Contacts with the facets are live (the funnel's case) and candidates exist.
        ASSERT_GT(ref.contact_count() - ref.particle_contact_count(), 10u);
        if (change == "spheres added") {
            for (int k = 0; k < 3; ++k) {
                SphereDef s;
                s.radius = 0.0045;
                s.position = {0.02 + 0.01 * k, 0.05, 0.09};
                ref.add_sphere(s);
            }
        } else if (change == "a clump added") {
            ClumpDef d;
            d.position = {0.05, 0.05, 0.09};
            ref.add_clump(builtin_clump_shape("dimer", 0.004), d);
        } else {
            ref.clear_facets();
        }
        EXPECT_EQ(ref.broken_invariant(), nullptr);
        save_checkpoint(path, ref, "by hand");
        World resumed;
        try {
            load_checkpoint(path, resumed);
        } catch (const std::exception& e) {
            ADD_FAILURE() << e.what();
            continue;
        }
        run(ref, 300);
        run(resumed, 300);
        expect_same(ref, resumed);
    }
    fs::remove_all(dir);
}

TEST(Checkpoint, AppBlobRoundTrips) {
    const fs::path dir = temp_dir("blob");
    const std::string path = (dir / "c.ckpt").string();
    World w = make_scene();
    run(w, 3);
    std::string all;
    for (int b = 0; b < 256; ++b) all.push_back(char(b));
    std::string big(1 << 20, '\0');
    for (std::size_t k = 0; k < big.size(); ++k) big[k] = char(k * 2654435761u >> 13);
    for (const std::string& blob : {std::string(), std::string("\0\xff\0", 3), all, big}) {
        save_checkpoint(path, w, blob);
        World r;
        EXPECT_EQ(load_checkpoint(path, r), blob);
        EXPECT_EQ(r.steps, 3u);
    }
    fs::remove_all(dir);
}

TEST(Checkpoint, RejectsDamagedForeignAndFutureFiles) {
    const fs::path dir = temp_dir("errors");
    const fs::path good = dir / "good.ckpt";
    World w = make_scene();
    run(w, 10);
    save_checkpoint(good.string(), w, "app");
    const std::string bytes = read_bytes(good);
    ASSERT_GT(bytes.size(), 1000u);

    expect_load_error(dir / "missing.ckpt", "no such file");
    expect_load_error(dir, "is a directory");

    const fs::path bad = dir / "bad.ckpt";
    for (std::size_t keep : {bytes.size() - 1, bytes.size() - 9, bytes.size() / 2, std::size_t(20),
                             std::size_t(12)}) {
        write_bytes(bad, bytes.substr(0, keep));
        expect_load_error(bad, "truncated or corrupt");
    }
    write_bytes(bad, bytes + "x");
    expect_load_error(bad, "size mismatch");
    write_bytes(bad, "");
    expect_load_error(bad, "truncated or corrupt");

    for (std::size_t at :
         {std::size_t(30), bytes.size() / 3, bytes.size() / 2, bytes.size() - 20, bytes.size() - 1}) {
        std::string flipped = bytes;
        flipped[at] = char(flipped[at] ^ 0x10);
        write_bytes(bad, flipped);
        expect_load_error(bad, "checksum mismatch");
    }

    std::string foreign = bytes;
    foreign[3] = 'X';
    write_bytes(bad, foreign);
    expect_load_error(bad, "not a vppdem checkpoint");
    write_bytes(bad, "hello, world\n");
    expect_load_error(bad, "not a vppdem checkpoint");

    // Issue 48: a flipped version byte said "format version 3" as if a newer vppdem had written
    // the file. The checksum covers the version: a damaged header is named so, with the file.
    std::string future = bytes;
    future[8] = 3;  // version field (little-endian uint32 after the magic)
    write_bytes(bad, future);
    expect_load_error(bad, "not a vppdem checkpoint of a known version");
    expect_load_error(bad, bad.string());
    // A sealed file of another version: written by another vppdem.
    dem::reseal_checkpoint_bytes(future);
    write_bytes(bad, future);
    expect_load_error(bad, "another vppdem (format version 3)");
    expect_load_error(bad, "reads format versions 1 and 2");

    World r;
    EXPECT_EQ(load_checkpoint(good.string(), r), "app");  // the original is still fine
    fs::remove_all(dir);
}

TEST(Checkpoint, SaveIsAtomic) {
    const fs::path dir = temp_dir("atomic");
    const fs::path path = dir / "run.ckpt";
    const fs::path part = dir / "run.ckpt.part";
    World w = make_scene();
    run(w, 5);
    save_checkpoint(path.string(), w, "first");
    EXPECT_TRUE(fs::exists(path));
    EXPECT_FALSE(fs::exists(part));

    // A stale PATH.part from a crashed save is overwritten and does not survive.
    write_bytes(part, "junk from an earlier crash");
    run(w, 5);
    save_checkpoint(path.string(), w, "second");
    EXPECT_FALSE(fs::exists(part));
    World r;
    EXPECT_EQ(load_checkpoint(path.string(), r), "second");
    EXPECT_EQ(r.steps, 10u);

    // If the new file cannot be written completely, the existing checkpoint stays as it was.
    const std::string before = read_bytes(path);
    fs::create_directory(part);  // makes creating PATH.part fail
    run(w, 5);
    try {
        save_checkpoint(path.string(), w, "third");
        ADD_FAILURE() << "save into a blocked PATH.part did not throw";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_bytes(path), before);
    EXPECT_EQ(load_checkpoint(path.string(), r), "second");
    fs::remove(part);

    // Saving into a directory that does not exist fails cleanly.
    EXPECT_THROW(save_checkpoint((dir / "no" / "such" / "dir.ckpt").string(), w, ""), std::runtime_error);
    fs::remove_all(dir);
}

// World's consistency rules (World::check_invariants) hold after every phase a caller can see
// (between compute_forces() and integrate() as well as after whole steps, with the energy
// ledger on), and a file written from a World that breaks one is refused by the reader naming
// the rule, before anything is derived from it.
TEST(Checkpoint, WorldInvariantsHoldAndTheReaderAppliesThem) {
    World w = make_scene();
    w.params.track_energy = true;
    for (int k = 0; k < 300; ++k) {
        w.compute_forces();
        ASSERT_EQ(w.broken_invariant(), nullptr) << "after compute_forces() of step " << k;
        w.integrate();
        ASSERT_EQ(w.broken_invariant(), nullptr) << "after step " << k;
    }
    EXPECT_NO_THROW(w.check_invariants());
    EXPECT_GT(w.contact_count(), 0u);

    const fs::path dir = temp_dir("invariants");
    const fs::path bad = dir / "bad.ckpt";
    World a = w;
    a.particles.material[7] = 99;
    EXPECT_STREQ(a.broken_invariant(), "particle material out of range");
    EXPECT_THROW(a.check_invariants(), std::logic_error);
    save_checkpoint(bad.string(), a, "");
    expect_load_error(bad, "particle material out of range");
    World b = w;
    b.pressure.nodes.push_back({uint32_t(b.particles.size()), {0, 1, 2, 3}});
    EXPECT_STREQ(b.broken_invariant(), "pressure node out of range");
    save_checkpoint(bad.string(), b, "");
    expect_load_error(bad, "pressure node out of range");
    World c = w;
    c.particles.mass.pop_back();
    EXPECT_STREQ(c.broken_invariant(), "particle arrays of different lengths");
    fs::remove_all(dir);
}

}  // namespace test_checkpoint
