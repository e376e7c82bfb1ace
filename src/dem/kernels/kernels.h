// The hot loops of World::step() as free functions over arrays, vectorised with Highway and
// dispatched at run time to the widest SIMD target the processor has (AVX-512, AVX2, SSE4,
// or plain 128-bit/scalar code). Every target computes the same bits (dem/core/lanes.h), so
// results do not depend on the machine; a test runs each target and compares.
//
// Each kernel works on a range of fixed blocks of kBlock entries (slots, bonds, particles), so
// that a thread does whole blocks and the energy sums are formed per block the same way
// whatever the thread count: inside a block every term is summed in 8 "virtual lanes"
// (entry e goes to lane e % 8, in entry order), then the 8 lanes in order. An 8-lane, 4-lane,
// 2-lane or scalar target forms exactly these sums.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dem/bonds/bond_list.h"
#include "dem/contact/active_contacts.h"
#include "dem/core/ledger_step.h"
#include "dem/core/particles.h"
#include "dem/core/vec3.h"
#include "dem/walls/wall.h"
#include "dem/walls/wall_now.h"

namespace dem::kernels {

inline constexpr int64_t kBlock = 64;  // entries per block (a multiple of 8)
inline int64_t block_count(std::size_t n) { return (int64_t(n) + kBlock - 1) / kBlock; }

// Particle energy terms summed per block by advance(): the work of each force over the back
// and forward half steps, and the kinetic energy; contact energy terms summed per block by the
// pair kernels (docs/energy.md; their indices are the ledger's, dem/core/ledger_step.h).
using ledger::ParticleTerm;
using enum ledger::ParticleTerm;
using ledger::kParticleSums;
using ledger::PairSum;
using enum ledger::PairSum;

// The state the pair kernels read of each particle, packed into one cache line so that a
// vector of pairs loads its particles with a few row loads and a transpose instead of one
// gather per component (gathers were half the time of the bond kernel). Written each step by
// ContactSet::find_new() (or advance()) from the particle arrays.
struct alignas(64) PackedParticle {
    double x, y, z;     // [m] position
    double r;           // [m] radius
    double vx, vy, vz;  // [m/s] velocity (half step)
    double unused;
};

inline PackedParticle pack(const Particles& p, std::size_t i) {
    const Vec3 x = p.pos[i], v = p.vel[i];
    return {x.x, x.y, x.z, p.radius[i], v.x, v.y, v.z, 0.0};
}

struct PairArgs {
    const Particles* p = nullptr;
    const PackedParticle* packed = nullptr;
    ActiveContacts* c = nullptr;
    double dt = 0;                    // [s]
    int64_t block_begin = 0, block_end = 0;
    double* energy = nullptr;         // kPairSums per block, indexed by block; nullptr: no ledger
    std::vector<uint32_t>* opened = nullptr;  // slots of live pairs found apart, appended in order
};
// Contacts of the frictional store: geometry, linear law with shear history, torques.
void frictional_pairs(const PairArgs& a);
// Contacts of the frictionless store: geometry and normal force only.
void smooth_pairs(const PairArgs& a);

struct WallPairArgs {
    const Particles* p = nullptr;
    ActiveContacts* c = nullptr;                                  // the wall store
    const std::vector<WallNow>* now = nullptr;                    // the walls now (WallState::now)
    double dt = 0;                                                // [s]
    const std::vector<std::pair<int64_t, int64_t>>* blocks = nullptr;  // runs of blocks of slots
    double* energy = nullptr;         // kPairSums per block, indexed by block; nullptr: no ledger
    std::vector<uint32_t>* opened = nullptr;  // slots of pairs found apart (cleared first)
};
// Contacts of the wall store: geometry against planes and facets, linear law with shear history
// (frictionless pairs: normal force only), contact points for the wall torques.
void wall_pairs(const WallPairArgs& a);

struct BondArgs {
    const Particles* p = nullptr;
    const PackedParticle* packed = nullptr;
    BondList* b = nullptr;
    double dt = 0;                    // [s]
    int64_t block_begin = 0, block_end = 0;
    double* energy = nullptr;         // 1 sum (stored energy) per block; nullptr: no ledger
};
void bonds(const BondArgs& a);

struct AdvanceArgs {
    Particles* p = nullptr;
    const Vec3* ext_force = nullptr;  // [N] per particle, or nullptr for none
    const Vec3* pressure = nullptr;   // [N] pressure force per particle (energy terms only), or nullptr
    const FloatVec3* ref_pos = nullptr;  // [m] positions at the last rebuild
    PackedParticle* packed = nullptr; // also write the packed records of the new state (or nullptr)
    Vec3 gravity;                     // [m/s^2]
    double dt = 0, lambda = 0;        // [s], local damping [-]
    int64_t block_begin = 0, block_end = 0;
    double* energy = nullptr;         // kParticleSums per block; nullptr: no ledger
};
// Leapfrog with local damping for the free particles (inv_mass > 0) of the blocks; fixed and
// prescribed particles are left as they are (World moves the prescribed ones). With `packed`
// the packed records of all particles of the blocks are rewritten. Returns the
// largest squared distance of a moved particle from ref_pos [m^2].
double advance(const AdvanceArgs& a);

// Candidates in [k0, k1) of a CandidateList without a live contact (slot == kNoSlot) whose gap
// at the rebuild is below `reach` [m]: their indices are appended to `out`, ascending.
void filter_open_candidates(const uint32_t* slot, const float* gap, float reach, int64_t k0, int64_t k1,
                            std::vector<uint32_t>& out);
// Of the pairs (i[q], j[q]), q < m, those whose spheres overlap (the test of the pair kernels,
// on packed records): their q appended to `hits`, ascending.
void touching_pairs(const PackedParticle* packed, const uint32_t* i, const uint32_t* j, std::size_t m,
                    std::vector<uint32_t>& hits);
// Writes the packed records of particles [i0, i1).
void pack_particles(const Particles& p, int64_t i0, int64_t i1, PackedParticle* out);

// The SIMD targets compiled in and supported here (Highway target bits, best first), their
// names, and a switch that makes the dispatch use only `target` (0: all again). The kernels
// run on available_targets().front().
std::vector<int64_t> available_targets();
std::string target_name(int64_t target);
void restrict_to_target(int64_t target);

}  // namespace dem::kernels
