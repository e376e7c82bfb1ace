// The World: particles, walls, materials, bonds and contacts, advanced by step(). A step is the
// method of docs/model.md, one named phase after the other (world.cpp reads as that list):
//   forces at t (compute_forces()): prepare the step's scratch -> move the walls -> rebuild the
//     candidates if anything moved more than half the skin -> open contacts -> contact forces
//     (shear history) -> bond forces -> pressure -> gather per particle -> wall reactions ->
//     close contacts
//   motion to t + dt (integrate()): free particles (gravity, external forces, local damping,
//     leapfrog) -> clumps (rigid bodies: their members' forces summed, then the same leapfrog
//     for translation and a symplectic rotation, members placed) -> prescribed particles ->
//     clock -> energy ledger (params.track_energy).
// The phases' state and code live with their concept: the contact lifecycle in
// dem/world/contact_set, the broad phase in dem/detect/broad_phase, the work sharing in
// dem/kernels/work_share, the force and integration kernels in dem/kernels/kernels (walls:
// wall_kernel.cpp), the clumps' state and rotation in dem/clumps, the pressure in dem/core/pressure, the walls' motion and reactions in
// dem/world/wall_state, the time step estimate in dem/integrate/critical_dt, the ledger in
// dem/world/energy_book. World owns them and keeps the rules that tie them together
// (check_invariants()).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dem/bonds/bond_list.h"
#include "dem/bonds/bond_tables.h"
#include "dem/clumps/clump_shape.h"
#include "dem/clumps/clumps.h"
#include "dem/world/contact_set.h"
#include "dem/core/energy.h"
#include "dem/kernels/kernels.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/core/pressure.h"
#include "dem/core/profile.h"
#include "dem/core/thread_team.h"
#include "dem/core/vec3.h"
#include "dem/kernels/work_share.h"
#include "dem/detect/broad_phase.h"
#include "dem/detect/rebuild_rule.h"
#include "dem/integrate/step_clock.h"
#include "dem/walls/motion.h"
#include "dem/walls/wall.h"
#include "dem/world/wall_state.h"
#include "dem/world/energy_book.h"

namespace dem {

struct SimulationParams {
    double dt = 1e-7;                // [s] time step
    Vec3 gravity{0.0, 0.0, -9.81};   // [m/s^2]
    double local_damping = 0.0;      // [-] Yade's non-viscous damping coefficient lambda
    double skin = 0.0;               // [m] Verlet distance; 0 = half the smallest radius (Yade)
    int threads = 1;                 // threads of the step; results do not depend on it
    bool track_energy = false;       // keep the energy ledger (World::energy()); costs nothing when off
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
    // A rigid clump of `shape`'s members (dem/clumps/clump_shape.h) at d's pose and velocities;
    // its mass and moments from the material's density. The members are appended as particles
    // (flag kClumpMember) in shape order. Returns the clump's index.
    uint32_t add_clump(const ClumpShape& shape, const ClumpDef& d);
    const Clumps& clumps() const { return clumps_; }
    // Kinetic energy of clump c [J] at the half step (translation and rotation).
    double clump_kinetic_energy(std::size_t c) const;
    // Room for n particles in all per-particle arrays (saves the growth copies of large scenes).
    void reserve(std::size_t n);
    uint32_t add_plane(const Plane& p);
    uint32_t add_facet(const Facet& f);
    uint32_t add_motion(const Motion& m);
    // Throws std::invalid_argument "<caller>: particle i does not exist (n particles)" unless
    // particle i exists: the one check of a particle index given by a user (C++ or Python).
    void require_particle(const char* caller, uint32_t i) const;
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
    // Where every bond's shear spring is driven from (BondArm, dem/bonds/bond_list.h; saved in
    // the checkpoint). The default, kRadius, is the paper's convention.
    void set_bond_arm(BondArm arm) { bonds_.arm = arm; }
    std::size_t wall_count() const { return planes.size() + facets.size(); }

    // Contact physics depends on materials; call after changing them mid-run.
    void invalidate_contact_physics() { physics_dirty_ = true; }
    // Call after changing particles by hand between steps (positions, velocities, radii:
    // teleporting, adding) so the candidates are rebuilt and the kernels see the change.
    void invalidate_candidates() { broad_.dirty = true; packed_valid_ = false; }

    // One step: compute_forces() then integrate(). The two halves are public so that a caller
    // can read the forces at t (x(t), v(t - dt/2)) before the motion moves on.
    void step();
    void compute_forces();  // forces at the current time t (positions x(t), velocities v(t-dt/2))
    void integrate();       // advance to t + dt

    // Largest stable step [s] for a lone contact pair: min over particles of
    // sqrt(m / kn_max), kn_max the stiffest pair the particle can form with any material
    // present or with a wall. Multiply by a safety factor (< 1) for dense packings.
    double critical_dt() const;  // dem/integrate/critical_dt.h

    // Results of the last compute_forces():
    Vec3 wall_force(std::size_t w) const { return walls_now_.force[w]; }    // [N] particles on wall
    Vec3 wall_torque(std::size_t w) const { return walls_now_.torque[w]; }  // [N m] about the origin
    std::size_t contact_count() const { return contacts_.live_count(); }  // touching pairs, particle-particle and wall
    std::size_t particle_contact_count() const { return contacts_.particle_live_count(); }
    // Pairs within the skin (touching or not): what the broad phase found at the last rebuild.
    std::size_t candidate_count() const { return contacts_.pp.size() + contacts_.pw.size(); }
    // Calls f(const TouchingContact&) for every touching pair, particle pairs first, each list
    // in candidate order (particle i, then partner).
    template <class F> void for_each_touching(F&& f) const { contacts_.for_each_touching(f); }
    // v(t) = v(t-dt/2) + dt/2 a(t): synchronous velocity for output (after compute_forces()).
    Vec3 velocity_at_time(std::size_t i) const;
    Vec3 angular_velocity_at_time(std::size_t i) const;
    // Current geometry of the walls at time t.
    Vec3 plane_point(std::size_t p) const { return walls_now_.plane_point[p]; }
    const std::array<Vec3, 3>& facet_vertices(std::size_t f) const { return walls_now_.facet_now[f]; }

    uint64_t rebuild_count() const { return broad_.rebuilds; }

    // Energy ledger (docs/energy.md), updated by integrate() while params.track_energy is on.
    const EnergyLedger& energy() const { return book_.ledger; }
    // Starts the ledger afresh: its t0 is the time of the next step (works and dissipations 0,
    // stored energies then recorded as the reference). Call after switching tracking on, and
    // after changing which particles are free (set_fixed, set_prescribed) or removing walls.
    void reset_energy() { book_.ledger = EnergyLedger{}; }

    // Time per phase of step() (dem/core/profile.h); off until profile().enable(true).
    PhaseProfile& profile() { return profile_; }
    const PhaseProfile& profile() const { return profile_; }

    // The rules that tie the World's parts together (array lengths, indices in range, candidate
    // lists and contact stores pointing at each other, energy terms sized to what they sum):
    // nullptr when they hold, else what is broken. The checkpoint reader asks before it
    // rebuilds the derived tables, so a file that passed the checksum but was written
    // inconsistently cannot make the next step read out of bounds.
    const char* broken_invariant() const;
    // Throws std::logic_error naming the broken rule.
    void check_invariants() const;

    // ---- The step for an engine that runs the step's kernels in World's stead (the batch
    // engine, dem/batch, docs/gpu.md). The engine keeps the particles' state in arrays of its own
    // and calls World's serial phases around its kernels, in step()'s order, so that the contact
    // lifecycle follows World's rules (the same slots, hence the same gather order and bits):
    //   if engine_rebuild_due(): particles.pos := the engine's positions
    //   engine_begin_forces()      walls at t, candidates (rebuild or compaction), scratch lists
    //   the engine's touch test    (particle, candidate) into engine_contacts().new_pp[0], new_pw[0]
    //   engine_activate()          slots for the new contacts, in candidate order
    //   the engine's kernels       pairs, walls, bonds, pressure, gather (opened slots into opened_*[0])
    //   engine_end_forces()        wall reactions, the opened contacts' slots freed
    //   the engine's integration   of the free particles
    //   engine_follow_motions(fp)  the prescribed particles (World's arrays: the engine copies them)
    //   engine_end_step(d2)        the largest squared move since the rebuild [m^2], the clock, the ledger
    // An engine may instead place and free the contacts itself by the same rules (the device
    // backend: it hands World empty found and opened lists, and the stores whole at a rebuild or
    // a compaction and when it hands a World back, then engine_relink()).
    // With params.track_energy the engine leaves the kernels' block sums in engine_book() (as the
    // SIMD kernels do), the prescribed particles' forces in particles.force and every velocity in
    // particles.vel before engine_end_step(); fp is its pressure force per particle [N] (for the
    // prescribed particles' boundary work). Clumps are not part of it (the engine refuses them).
    bool engine_rebuild_due() { return broad_.needs_rebuild(particles.size(), planes, facets, time); }
    // engine_begin_forces() will lay the contact stores out again without a rebuild (as
    // update_candidates() decides): a device engine brings their state back first.
    bool engine_compaction_due() const { return physics_dirty_ || stores_need_compaction(contacts_.holes, contacts_.store_slots()); }
    void engine_begin_forces();
    ContactSet& engine_contacts() { return contacts_; }
    BondList& engine_bonds() { return bonds_; }
    const BroadPhase& broad_phase() const { return broad_; }
    const WallState& wall_state() const { return walls_now_; }
    // The largest gaps [m] a candidate without a contact may have closed since the rebuild: of a
    // particle pair, of a particle and a wall (the touch test skips candidates beyond them).
    std::pair<float, float> engine_reach() const;
    void engine_activate();
    EnergyBook& engine_book() { return book_; }
    void engine_end_forces();
    // The same with the walls' reactions formed by the engine (force and torque per wall, as
    // WallState::sum_reactions forms them: add_wall_reaction in slot order).
    void engine_end_forces(const Vec3* force, const Vec3* torque);
    double engine_follow_motions(const Vec3* pressure);
    void engine_end_step(double max_d2);
    // Each wall's velocity over the next step [m/s], as the ledger of engine_end_step() will
    // take it (for an engine that forms the dashpots' forward halves itself: EnergyBook).
    void engine_next_wall_velocities(std::vector<Vec3>& v) const;
    // Prescribed particle i's position [m] and velocity [m/s] after this step, as
    // engine_follow_motions() will set them (for an engine whose ledger reads them first).
    std::pair<Vec3, Vec3> engine_prescribed_next(uint32_t i) const { return prescribed_next(i); }
    // For an engine that runs the serial parts of the steps itself between events (the device
    // backend's chunks, DeviceBatch::run): what they keep from step to step, taken before the
    // engine's steps and set back after them (the ledger through engine_book()).
    struct EngineSteps {
        double time = 0;        // [s]
        uint64_t steps = 0;
        StepClock clock;
        double max_disp = 0;    // [m] the broad phase's largest move since the rebuild
        double wall_move = 0;   // [m] the walls' (its last rebuild test's)
        double skin = 0;        // [m] of the last rebuild
        double ref_round = 0;   // [m] the rounding bound of the rebuild positions
    };
    EngineSteps engine_steps() const {
        return {time, steps, clock_, broad_.max_disp, broad_.wall_move, broad_.skin, broad_.ref_round};
    }
    void engine_set_steps(const EngineSteps& e) {
        time = e.time;
        steps = e.steps;
        clock_ = e.clock;
        broad_.max_disp = e.max_disp;
        broad_.wall_move = e.wall_move;
    }
    // The engine wrote the particles back: the pair kernels' packed copy is stale.
    void engine_handback() { packed_valid_ = false; }
    // An engine that keeps the contact lifecycle itself (the device backend) wrote the stores and
    // the candidates' slots back: each particle's interaction list from them (the same content,
    // hence the same gather order, as the lists the engine kept).
    void engine_relink() { contacts_.build_interaction_lists(bond_tables_, particles.size()); }

    // Writes (Self = const World) or reads (Self = World, Archive::kLoading) the whole state,
    // section by section: the checkpoint format (dem/io/checkpoint.h) of `version`; the field
    // list is dem/world/world_io.h. After loading, ask broken_invariant(), then call
    // rebuild_derived_tables().
    template <class Archive, class Self> static void serialize(Archive& a, Self& self, uint32_t version);
    // Rebuilds what follows from the saved state (bond tables, interaction lists) after loading.
    void rebuild_derived_tables();

private:
    // ---- the phases of step(), in order (world.cpp)
    void move_walls();           // the walls at t
    void update_candidates();    // broad phase when needed, else a compaction of the stores
    void prepare_forces();       // upkeep: per-thread lists, pressure slots, owners, packed records
    void open_contacts(int tid); // candidates touching now get slots (in parallel, then serial)
    void contact_forces(int tid);
    void bond_forces(int tid);
    void pressure_forces(int tid);
    void gather_forces(int tid);
    void wall_reactions();
    void close_contacts();       // the slots of pairs found apart are freed
    void finish_forces();        // upkeep: the packed records and the energy terms are current
    bool prepare_integration();  // upkeep: energy blocks, owners, the prescribed list; true: book the ledger
    double advance_free_particles(bool track);  // returns the largest squared move since the rebuild [m^2]
    double advance_clumps(bool track);          // clumps and their members; their largest squared move [m^2]
    // Prescribed particles; their largest squared move [m^2]. `pressure`: the pressure's force per
    // particle (nullptr: pressure_forces_).
    double follow_motions(bool track, const Vec3* pressure = nullptr);
    // Prescribed particle i where its motion puts it at time + dt: position, velocity over the step.
    std::pair<Vec3, Vec3> prescribed_next(uint32_t i) const;
    void advance_clock();
    void account_energy(double t_n);
    void refresh_prescribed();  // the list of prescribed particles, when it changed

    const char* clump_rule() const;  // the clumps' part of broken_invariant()
    void assign_work();          // new slabs of work for the threads
    // With profiling on, a barrier after a phase so that its time is the slowest thread's.
    void lap(int tid, Phase phase);
    ContactPhysics contact_physics() const { return {&particles, &materials, &planes, &facets}; }
    int threads() const { return params.threads > 1 ? params.threads : 1; }
    bool pressure_on() const { return pressure.dp != 0.0 && pressure.has_nodes(); }
    double effective_skin() const;
    Vec3 total_force(std::size_t i) const;

    ContactSet contacts_;              // candidates, live contacts, interaction lists
    BroadPhase broad_;                 // rebuild test and state (positions at the last rebuild)
    WorkShare work_;                   // which thread does which blocks
    BondList bonds_;
    BondTables bond_tables_;           // each particle's bonds (from bonds_)
    bool bonds_dirty_ = false;         // bonds added since bond_tables_ was built
    bool physics_dirty_ = false;       // materials changed: contact coefficients to refresh
    WallState walls_now_;              // walls at t, their velocities and reactions
    StepClock clock_;
    EnergyBook book_;                  // the ledger and the step's energy block sums
    PressureForces pressure_forces_;   // [N] the pressure's force per particle
    std::vector<kernels::PackedParticle> packed_;  // the pair kernels' copy of the particle state
    bool packed_valid_ = false;        // packed_ holds the current state (written by integrate())
    Clumps clumps_;                    // rigid grains (their members are particles)
    std::vector<uint32_t> prescribed_; // indices of the prescribed particles
    bool prescribed_dirty_ = true;
    PhaseProfile profile_;
    TeamHandle team_;                  // the threads of the step (dem/core/thread_team.h)
    std::vector<double> thread_max_d2_;
};

}  // namespace dem
