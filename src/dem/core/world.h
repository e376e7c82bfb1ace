// The World: particles, walls, materials and contacts, advanced by step().
// step() reads like the method (see docs/model.md):
//   move walls -> rebuild candidates if anything moved more than half the skin ->
//   contact forces (sphere-sphere, sphere-wall; history updated) -> gather per particle ->
//   wall reactions -> integrate (gravity, external forces, local damping, leapfrog) ->
//   energy ledger (only with params.track_energy; see dem/core/energy.h, docs/energy.md).
#pragma once

#include <cstdint>
#include <vector>

#include "dem/bonds/bond_list.h"
#include "dem/contact/contact_list.h"
#include "dem/core/energy.h"
#include "dem/core/material.h"
#include "dem/core/particles.h"
#include "dem/core/pressure.h"
#include "dem/core/profile.h"
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
    int threads = 1;                 // OpenMP threads; results do not depend on it
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
    // Call after moving particles by hand (teleporting, adding) so the candidates are rebuilt.
    void invalidate_candidates() { candidates_dirty_ = true; }

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
    std::size_t particle_contact_count() const { return pp_.count_touching(); }
    // v(t) = v(t-dt/2) + dt/2 a(t): synchronous velocity for output (after compute_forces()).
    Vec3 velocity_at_time(std::size_t i) const;
    Vec3 angular_velocity_at_time(std::size_t i) const;
    // Current geometry of the walls at time t.
    Vec3 plane_point(std::size_t p) const { return plane_point_[p]; }
    const std::array<Vec3, 3>& facet_vertices(std::size_t f) const { return facet_now_[f]; }

    uint64_t rebuild_count() const { return rebuilds_; }
    const ContactList& particle_contacts() const { return pp_; }
    const ContactList& wall_contacts() const { return pw_; }

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
    bool needs_rebuild() const;
    void rebuild_candidates();
    // Gather CSR tables (pp_start_, pp_entries_, pw_start_) from the current contact lists.
    void build_gather_tables();
    // Rebuilds the tables derived from the bond and contact lists (bond tables, gather
    // tables) without changing the lists. Used after restoring a checkpoint.
    void rebuild_derived_tables();
    void refresh_physics(bool all, const std::vector<uint8_t>& existed_pp,
                         const std::vector<uint8_t>& existed_pw);
    template <bool kEnergy> void particle_contact_forces();
    template <bool kEnergy> void wall_contact_forces();
    template <bool kEnergy> void bond_forces();
    // Leapfrog update of all particles; returns the largest squared move since the last
    // rebuild. With kEnergy, also each particle's energy terms of the step.
    template <bool kEnergy> double advance_particles(double t1);
    // Adds step n (forces at t_n, velocities v(t_n -/+ dt/2)) to the ledger.
    void account_energy(double t_n);
    enum EnergyTerm { kBoundary, kPressure, kGravity, kExternal, kDamping, kTerms };
    static constexpr int kParticleSums = 2 * kTerms + 1;  // back[], fwd[], kinetic
    static constexpr int64_t kEnergyBlock = 256;  // entries per energy partial sum (fixed: deterministic)
    struct ParticleEnergyStep {
        double back[kTerms] = {}, fwd[kTerms] = {};  // [J] work of each term, both half steps
        double kinetic = 0;                          // [J] 1/2 m v- . v+ + 1/2 I w- . w+
    };
    ParticleEnergyStep particle_energy(std::size_t i, const Vec3& v0, const Vec3& w0, const Vec3& v1,
                                       const Vec3& w1, const Vec3& a, const Vec3& al) const;
    void gather_forces(bool with_pressure);
    void apply_pressure();
    void sum_wall_reactions();
    double effective_skin() const;
    Vec3 total_force(std::size_t i) const;

    ContactList pp_, pw_;
    BondList bonds_;
    std::vector<uint32_t> bond_start_, bond_entries_;  // gather CSR (bit 31: body 2)
    std::vector<uint32_t> bonded_start_, bonded_with_;   // partners per particle (exclusions)
    bool bonds_dirty_ = false;
    void build_bond_tables();
    CellGrid grid_;
    // gather CSR for pp_: per particle, contact indices with bit 31 set when it is body 2
    std::vector<uint32_t> pp_start_, pp_entries_;
    std::vector<uint32_t> pw_start_;   // pw_ is sorted by particle: ranges per particle
    std::vector<Vec3> ref_pos_;        // positions at the last rebuild
    std::vector<Vec3> wall_ref_disp_;  // wall displacement at the last rebuild
    std::vector<Vec3> plane_point_, wall_vel_;
    std::vector<std::array<Vec3, 3>> facet_now_;
    std::vector<Vec3> wall_force_, wall_torque_;
    // Time is base + (steps - base_step) * dt, not a running sum, so output times stay exact
    // multiples of dt; the base moves whenever dt changes.
    double time_base_ = 0.0, dt_of_base_ = -1.0;
    uint64_t step_base_ = 0;
    double max_disp_ = 0.0;            // [m] largest particle move since the last rebuild
    bool candidates_dirty_ = true;
    bool physics_dirty_ = false;
    uint64_t rebuilds_ = 0;

    // Energy tracking (params.track_energy). The per-contact and per-bond terms are written by
    // the force kernels into their own slots and summed in index order by account_energy(),
    // so the ledger is the same for any thread count.
    EnergyLedger energy_;
    bool energy_ready_ = false;                       // compute_forces() filled the terms below
    std::vector<ContactEnergyStep> pp_energy_, pw_energy_;
    std::vector<double> bond_energy_;                 // [J] stored in each bond
    std::vector<Vec3> pressure_force_;                // [N] pressure force per particle
    std::vector<double> particle_blocks_;             // particle energy sums per block (integrate())
    std::vector<double> energy_blocks_;               // scratch of account_energy()
    std::vector<Vec3> wall_vel_next_;                 // scratch of account_energy()
    PhaseProfile profile_;
};

}  // namespace dem
