// The World: particles, walls, materials and contacts, advanced by step().
// step() reads like the method (see docs/model.md):
//   move walls -> rebuild candidates if anything moved more than half the skin ->
//   open and close contacts -> contact and bond forces (history updated) -> pressure ->
//   gather per particle -> wall reactions -> integrate (gravity, external forces, local
//   damping, leapfrog) -> energy ledger (only with params.track_energy; docs/energy.md).
// The phases live in their own files: the broad phase in dem/detect/broad_phase.cpp, the
// SIMD force and integration kernels in dem/core/kernels.cpp, the energy ledger's sums in
// dem/core/energy_ledger.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/bonds/bond_list.h"
#include "dem/contact/active_contacts.h"
#include "dem/contact/candidates.h"
#include "dem/contact/interaction_lists.h"
#include "dem/core/energy.h"
#include "dem/core/kernels.h"
#include "dem/core/material.h"
#include "dem/core/parallel.h"
#include "dem/core/particles.h"
#include "dem/core/pressure.h"
#include "dem/core/profile.h"
#include "dem/core/thread_team.h"
#include "dem/core/vec3.h"
#include "dem/detect/cell_grid.h"
#include "dem/walls/motion.h"
#include "dem/walls/wall.h"

namespace dem {

struct SimulationParams {
    double dt = 1e-7;                // [s] time step
    Vec3 gravity{0.0, 0.0, -9.81};   // [m/s^2]
    double local_damping = 0.0;      // [-] Yade's non-viscous damping coefficient lambda
    double skin = 0.0;               // [m] Verlet distance; 0 = half the smallest radius (Yade)
    int threads = 1;                 // threads of the step; results do not depend on it
    bool track_energy = false;       // keep the energy ledger (World::energy()); costs nothing when off
};

// A touching pair as the World reports it (World::for_each_touching).
struct TouchingContact {
    uint32_t i = 0, j = 0;  // particle i; particle j, or wall j when `wall`
    bool wall = false;
    ContactPhys phys;
    Vec3 force;             // [N] on body 2 (the wall's contact: on the particle)
    Vec3 shear;             // [N] shear spring (zero for frictionless pairs)
};

class World {
public:
    std::vector<Material> materials;
    Particles particles;
    std::vector<Plane> planes;
    std::vector<Facet> facets;
    std::vector<Motion> motions;     // motions of prescribed particles
    MembranePressure pressure;       // follower pressure on membrane nodes (empty: none)
    SimulationParams params;

    double time = 0.0;               // [s]
    uint64_t steps = 0;

    uint32_t add_material(const Material& m);
    uint32_t add_sphere(const SphereDef& d);
    // Room for n particles in all per-particle arrays (saves the growth copies of large scenes).
    void reserve(std::size_t n);
    uint32_t add_plane(const Plane& p);
    uint32_t add_facet(const Facet& f);
    uint32_t add_motion(const Motion& m);
    // Blocks all six degrees of freedom of particle i from now on.
    void set_fixed(uint32_t i);
    // Particle i follows motions[motion] from its current position (no rotation).
    void set_prescribed(uint32_t i, uint32_t motion);
    // Removes all facets (e.g. a filling funnel) and their contacts.
    void clear_facets();
    // Changes a bond's stiffness (e.g. a foil of another modulus on a prepared sample).
    void set_bond_stiffness(uint32_t b, double kn, double ks) {
        bonds_.phys[b].kn = kn;
        bonds_.phys[b].ks = ks;
    }
    // Permanent bond; rest_length < 0 takes the current centre distance.
    uint32_t add_bond(uint32_t i, uint32_t j, double kn, double ks, double rest_length = -1.0);
    const BondList& bonds() const { return bonds_; }
    std::size_t wall_count() const { return planes.size() + facets.size(); }

    // Contact physics depends on materials; call after changing them mid-run.
    void invalidate_contact_physics() { physics_dirty_ = true; }
    // Call after changing particles by hand between steps (positions, velocities, radii:
    // teleporting, adding) so the candidates are rebuilt and the kernels see the change.
    void invalidate_candidates() { candidates_dirty_ = true; packed_valid_ = false; }

    void step();            // compute_forces() then integrate()
    void compute_forces();  // forces at the current time t (positions x(t), velocities v(t-dt/2))
    void integrate();       // advance to t + dt

    // Largest stable step [s] for a lone contact pair: min over particles of
    // sqrt(m / kn_max), kn_max the stiffest pair the particle can form with any material
    // present or with a wall. Multiply by a safety factor (< 1) for dense packings.
    double critical_dt() const;

    // Results of the last compute_forces():
    Vec3 wall_force(std::size_t w) const { return wall_force_[w]; }    // [N] particles on wall
    Vec3 wall_torque(std::size_t w) const { return wall_torque_[w]; }  // [N m] about the origin
    std::size_t contact_count() const;           // touching pairs, particle-particle and wall
    std::size_t particle_contact_count() const { return fric_.live_count() + smooth_.live_count(); }
    // Pairs within the skin (touching or not): what the broad phase found at the last rebuild.
    std::size_t candidate_count() const { return pp_cand_.size() + pw_cand_.size(); }
    // Calls f(const TouchingContact&) for every touching pair, particle pairs first, each list
    // in candidate order (particle i, then partner).
    template <class F> void for_each_touching(F&& f) const;
    // v(t) = v(t-dt/2) + dt/2 a(t): synchronous velocity for output (after compute_forces()).
    Vec3 velocity_at_time(std::size_t i) const;
    Vec3 angular_velocity_at_time(std::size_t i) const;
    // Current geometry of the walls at time t.
    Vec3 plane_point(std::size_t p) const { return plane_point_[p]; }
    const std::array<Vec3, 3>& facet_vertices(std::size_t f) const { return facet_now_[f]; }

    uint64_t rebuild_count() const { return rebuilds_; }

    // Energy ledger (docs/energy.md), updated by integrate() while params.track_energy is on.
    const EnergyLedger& energy() const { return energy_; }
    // Starts the ledger afresh: its t0 is the time of the next step (works and dissipations 0,
    // stored energies then recorded as the reference). Call after switching tracking on, and
    // after changing which particles are free (set_fixed, set_prescribed) or removing walls.
    void reset_energy() { energy_ = EnergyLedger{}; }

    // Time per phase of step() (dem/core/profile.h); off until profile().enable(true).
    PhaseProfile& profile() { return profile_; }
    const PhaseProfile& profile() const { return profile_; }

private:
    friend struct WorldSerializer;  // dem/io/checkpoint.cpp: writes and restores the whole state
    void move_walls();
    bool needs_rebuild();
    // Broad phase (dem/detect/broad_phase.cpp): new candidate lists from a cell grid, live
    // contacts carried over, stores compacted into candidate order, reverse table rebuilt.
    void rebuild_candidates();
    // Moves every live contact into its store in candidate order (holes dropped); with
    // `refresh` its coefficients are recomputed from the materials first (and a pair whose
    // friction became zero or nonzero changes store).
    void compact_contacts(bool refresh);
    // The per-particle interaction lists from the bonds and the live contacts (after a
    // rebuild, a compaction or a restore).
    void build_interaction_lists();
    // Rebuilds the tables derived from the bond and contact lists without changing the lists
    // (after restoring a checkpoint).
    void rebuild_derived_tables();
    void build_bond_tables();
    ContactPhys pair_phys(uint32_t i, uint32_t j) const;   // particle pair
    ContactPhys wall_phys(uint32_t i, uint32_t w) const;   // particle i against wall w
    // Opening and closing of contacts: candidates without a slot that touch now get one
    // (in candidate order, the same for any thread count); slots whose pair opened are freed.
    void find_new_contacts();
    void activate_new_contacts();
    void release_opened_contacts();
    template <bool kEnergy> void wall_contact_forces();
    void gather_forces(bool with_pressure);

    void apply_pressure();
    void sum_wall_reactions();
    double effective_skin() const;
    Vec3 total_force(std::size_t i) const;
    // Adds step n (forces at t_n, velocities v(t_n -/+ dt/2)) to the ledger (energy_ledger.cpp).
    void account_energy(double t_n);

    // Contacts: the light candidate lists and the live contacts (dem/contact/).
    CandidateList pp_cand_, pw_cand_;
    ActiveContacts fric_, smooth_, walls_;
    // Candidates found touching this step without a slot, per thread (candidate indices).
    std::vector<std::vector<uint32_t>> new_pp_, new_pw_, open_scratch_, pair_i_, pair_j_, pair_hits_;
    // Slots whose pair opened this step, per thread, per store.
    std::vector<std::vector<uint32_t>> opened_fric_, opened_smooth_, opened_walls_;
    InteractionLists links_;           // per particle: bonds and live contacts (the gather's input)
    // Work sharing (assign_owners()): each block of kBlock particles belongs to one thread,
    // chosen by position (slabs along the longest axis, balanced by work), and every other
    // list is split by the owner of its entries' first particle. So a thread integrates, packs,
    // gathers and computes the contacts and bonds of one region: the data it reads was mostly
    // written by itself (a cache line moved between cores costs ~200 ns on a 2-socket-like VM).
    // Results never depend on it: every sum is formed per block.
    void assign_owners();
    BlockRuns store_runs(const ActiveContacts& a) const;
    std::vector<int> block_owner_;     // owner thread of each particle block
    int owners_for_ = 0;               // the thread count block_owner_ was made for
    BlockRuns particle_runs_, bond_runs_, fric_runs_, smooth_runs_, wall_runs_;
    std::vector<kernels::PackedParticle> packed_;  // the pair kernels' copy of the particle state
    bool packed_valid_ = false;        // packed_ holds the current state (written by integrate())
    std::size_t holes_ = 0;            // slots freed since the last compaction
    double dropped_shear_energy_ = 0;  // [J] shear springs dropped by a physics change (ledger)

    BondList bonds_;
    std::vector<uint32_t> bond_start_, bond_entries_;  // bonds per particle (bit 31: body 2)
    std::vector<uint32_t> bonded_with_;                // the partner of each bond_entries_ entry
    bool bonds_dirty_ = false;
    CellGrid grid_;
    // [m] positions at the last rebuild, in float (half the memory of a large scene): the
    // moves measured against them are enlarged by ref_round_, a bound of the rounding.
    std::vector<FloatVec3> ref_pos_;
    double ref_round_ = 0.0;           // [m]
    std::vector<Vec3> wall_ref_disp_;  // wall displacement at the last rebuild
    std::vector<Vec3> plane_point_, wall_vel_;
    std::vector<std::array<Vec3, 3>> facet_now_;
    std::vector<Vec3> wall_force_, wall_torque_;
    // Time is base + (steps - base_step) * dt, not a running sum, so output times stay exact
    // multiples of dt; the base moves whenever dt changes.
    double time_base_ = 0.0, dt_of_base_ = -1.0;
    uint64_t step_base_ = 0;
    double max_disp_ = 0.0;            // [m] largest particle move since the last rebuild
    double wall_move_ = 0.0;           // [m] largest wall move since the last rebuild
    double skin_ = 0.0;                // [m] the skin of the last rebuild (effective_skin() is O(n))
    bool candidates_dirty_ = true;
    bool physics_dirty_ = false;
    uint64_t rebuilds_ = 0;

    // Energy tracking (params.track_energy). The kernels sum their terms per fixed block of
    // entries (dem/core/kernels.h: the same bits for any thread count and vector width);
    // account_energy() adds the blocks in order.
    EnergyLedger energy_;
    bool energy_ready_ = false;        // compute_forces() filled the sums below
    std::vector<double> fric_energy_, smooth_energy_, wall_energy_, bond_energy_;  // block sums
    std::vector<Vec3> pressure_force_;                // [N] pressure force per particle
    std::vector<double> particle_blocks_;             // particle energy sums per block (integrate())
    double prescribed_energy_[2] = {};                // boundary work of prescribed particles: back, forward
    std::vector<uint32_t> prescribed_;                // indices of the prescribed particles
    bool prescribed_dirty_ = true;
    std::vector<PressureNode> pressure_seen_;         // node list the zeroed pressure_force_ was made for
    bool pressure_was_on_ = false;
    std::vector<Vec3> wall_vel_next_;                 // scratch of account_energy()
    PhaseProfile profile_;
    TeamHandle team_;                  // the threads of the step (dem/core/thread_team.h)
    std::vector<double> thread_max_d2_;
};

template <class F> void World::for_each_touching(F&& f) const {
    const auto visit = [&](const CandidateList& cl, bool wall) {
        for (std::size_t i = 0; i + 1 < cl.start.size(); ++i)
            for (uint32_t k = cl.start[i]; k < cl.start[i + 1]; ++k) {
                const uint32_t s = cl.slot[k];
                if (s == kNoSlot) continue;
                const bool smooth = !wall && (s & kSmoothBit);
                const ActiveContacts& a = wall ? walls_ : smooth ? smooth_ : fric_;
                const uint32_t c = s & ~kSmoothBit;
                f(TouchingContact{uint32_t(i), cl.other[k], wall, a.phys[c], a.force[c], a.shear[c]});
            }
    };
    visit(pp_cand_, false);
    visit(pw_cand_, true);
}

}  // namespace dem
