// The energy ledger's bookkeeping (World::account_energy; docs/energy.md): the kernels and the
// integrator leave their terms summed per fixed block; here the blocks are added in order and
// booked, back halves and the contacts' terms on [t_n - dt, t_n], forward halves pending until
// the next step. Everything is summed in a fixed order: the same numbers for any thread count.
#include "dem/core/kernels.h"
#include "dem/core/world.h"

namespace dem {

void World::account_energy(double t_n) {
    using kernels::kTerms;
    const Particles& p = particles;
    const double dt = params.dt, h = 0.5 * dt;
    EnergyLedger& L = energy_;
    const bool first = L.steps == 0;

    // Walls translate: their work is the force on the particles times the wall's displacement.
    // The forward half uses the velocity the next step's move_walls() will compute.
    const std::size_t nw = wall_count();
    wall_vel_next_.resize(nw);
    std::vector<Vec3>& v_next = wall_vel_next_;
    for (std::size_t k = 0; k < planes.size(); ++k) v_next[k] = planes[k].motion.mean_velocity(time - dt, time);
    for (std::size_t k = 0; k < facets.size(); ++k)
        v_next[planes.size() + k] = facets[k].motion.mean_velocity(time - dt, time);

    double back[kTerms] = {}, fwd[kTerms] = {}, kinetic = 0;
    for (std::size_t b = 0; b < particle_blocks_.size(); b += kernels::kParticleSums) {
        const double* s = &particle_blocks_[b];
        for (int k = 0; k < kTerms; ++k) {
            back[k] += s[k];
            fwd[k] += s[kTerms + k];
        }
        kinetic += s[2 * kTerms];
    }
    back[kernels::kBoundary] += prescribed_energy_[0];
    fwd[kernels::kBoundary] += prescribed_energy_[1];
    for (std::size_t w = 0; w < nw; ++w) {
        back[kernels::kBoundary] -= dot(wall_force_[w], wall_vel_[w]) * h;
        fwd[kernels::kBoundary] -= dot(wall_force_[w], v_next[w]) * h;
    }
    double cs[kernels::kPairSums] = {};
    for (const std::vector<double>* blocks : {&fric_energy_, &smooth_energy_, &wall_energy_})
        for (std::size_t b = 0; b < blocks->size(); b += kernels::kPairSums)
            for (int k = 0; k < kernels::kPairSums; ++k) cs[k] += (*blocks)[b + k];
    double elastic_b = 0;
    for (double e : bond_energy_) elastic_b += e;
    // The dashpots' forward halves need the velocities after integration: v(t_n + dt/2).
    double visc_fwd = 0;
    bool dashpots = false;
    for (const Material& m : materials) dashpots |= m.restitution < 1.0;
    if (dashpots) {
        for (const ActiveContacts* a : {&fric_, &smooth_})
            for (std::size_t s = 0; s < a->size(); ++s)
                if (a->cand[s] != kNoSlot && a->fv[s] != Vec3{})
                    visc_fwd -= dot(a->fv[s], p.vel[a->j[s]] - p.vel[a->i[s]]) * h;
        for (std::size_t s = 0; s < walls_.size(); ++s)
            if (walls_.cand[s] != kNoSlot && walls_.fv[s] != Vec3{})
                visc_fwd -= dot(walls_.fv[s], p.vel[walls_.i[s]] - v_next[walls_.j[s]]) * h;
    }
    const double release = cs[kernels::kRelease] + dropped_shear_energy_;
    dropped_shear_energy_ = 0;

    if (!first) {  // the back halves and the kernels' terms belong to [t_n - dt, t_n]
        L.boundary_work += L.pending_boundary + back[kernels::kBoundary];
        L.pressure_work += L.pending_pressure + back[kernels::kPressure];
        L.gravity_work += L.pending_gravity + back[kernels::kGravity];
        L.external_work += L.pending_external + back[kernels::kExternal];
        L.damping_dissipation += L.pending_damping + back[kernels::kDamping];
        L.viscous_dissipation += L.pending_viscous + cs[kernels::kViscous];
        L.friction_slip += cs[kernels::kSlip];
        L.shear_release += release;
    }
    L.pending_boundary = fwd[kernels::kBoundary];
    L.pending_pressure = fwd[kernels::kPressure];
    L.pending_gravity = fwd[kernels::kGravity];
    L.pending_external = fwd[kernels::kExternal];
    L.pending_damping = fwd[kernels::kDamping];
    L.pending_viscous = visc_fwd;
    L.kinetic = kinetic;
    L.elastic_contacts = cs[kernels::kElastic];
    L.elastic_bonds = elastic_b;
    L.time = t_n;
    if (first) {
        L.t0 = t_n;
        L.stored0 = L.stored();
    }
    ++L.steps;
}

}  // namespace dem
