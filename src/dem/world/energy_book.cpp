#include "dem/world/energy_book.h"

#include "dem/kernels/kernels.h"

namespace dem {

void EnergyBook::size_blocks(const ContactSet& c, std::size_t bond_count) {
    using kernels::block_count, kernels::kPairSums;
    fric.resize(std::size_t(block_count(c.fric.size()) * kPairSums));
    smooth.resize(std::size_t(block_count(c.smooth.size()) * kPairSums));
    walls.resize(std::size_t(block_count(c.walls.size()) * kPairSums));
    bonds.resize(std::size_t(block_count(bond_count)));
}

void EnergyBook::account(const Step& st) {
    using kernels::kTerms;
    const Particles& p = *st.p;
    const std::vector<Plane>& planes = *st.planes;
    const std::vector<Facet>& facets = *st.facets;
    const ContactSet& c = *st.contacts;
    const double dt = st.dt, h = 0.5 * dt, time = st.time, t_n = st.t_n;
    EnergyLedger& L = ledger;
    const bool first = L.steps == 0;

    // Walls translate: their work is the force on the particles times the wall's displacement.
    // The forward half uses the velocity the next step's move_walls() will compute.
    const std::size_t nw = planes.size() + facets.size();
    wall_vel_next.resize(nw);
    std::vector<Vec3>& v_next = wall_vel_next;
    for (std::size_t k = 0; k < planes.size(); ++k) v_next[k] = planes[k].motion.mean_velocity(time - dt, time);
    for (std::size_t k = 0; k < facets.size(); ++k)
        v_next[planes.size() + k] = facets[k].motion.mean_velocity(time - dt, time);

    double back[kTerms] = {}, fwd[kTerms] = {}, kinetic = 0;
    for (const std::vector<double>* blocks : {&particles, &clumps})
        for (std::size_t b = 0; b < blocks->size(); b += kernels::kParticleSums) {
            const double* s = &(*blocks)[b];
            for (int k = 0; k < kTerms; ++k) {
                back[k] += s[k];
                fwd[k] += s[kTerms + k];
            }
            kinetic += s[2 * kTerms];
        }
    back[kernels::kBoundary] += prescribed[0];
    fwd[kernels::kBoundary] += prescribed[1];
    for (std::size_t w = 0; w < nw; ++w) {
        back[kernels::kBoundary] -= dot(st.walls->force[w], st.walls->velocity[w]) * h;
        fwd[kernels::kBoundary] -= dot(st.walls->force[w], v_next[w]) * h;
    }
    double cs[kernels::kPairSums] = {};
    for (const std::vector<double>* blocks : {&fric, &smooth, &walls})
        for (std::size_t b = 0; b < blocks->size(); b += kernels::kPairSums)
            for (int k = 0; k < kernels::kPairSums; ++k) cs[k] += (*blocks)[b + k];
    double elastic_b = 0;
    for (double e : bonds) elastic_b += e;
    // The dashpots' forward halves need the velocities after integration: v(t_n + dt/2).
    double visc_fwd = 0;
    bool dashpots = false;
    for (const Material& m : *st.materials) dashpots |= m.restitution < 1.0;
    if (dashpots) {
        for (const ActiveContacts* a : {&c.fric, &c.smooth})
            for (std::size_t s = 0; s < a->size(); ++s)
                if (a->cand[s] != kNoSlot && a->fv[s] != Vec3{})
                    visc_fwd -= dot(a->fv[s], p.vel[a->j[s]] - p.vel[a->i[s]]) * h;
        for (std::size_t s = 0; s < c.walls.size(); ++s)
            if (c.walls.cand[s] != kNoSlot && c.walls.fv[s] != Vec3{})
                visc_fwd -= dot(c.walls.fv[s], p.vel[c.walls.i[s]] - v_next[c.walls.j[s]]) * h;
    }
    const double release = cs[kernels::kRelease] + st.contacts->dropped_shear_energy;
    st.contacts->dropped_shear_energy = 0;

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
