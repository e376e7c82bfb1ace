#include "dem/world/energy_book.h"

#include <algorithm>

#include "dem/core/lane_sums.h"
#include "dem/kernels/kernels.h"

namespace dem {

void EnergyBook::size_blocks(const ContactSet& c, std::size_t bond_count) {
    using kernels::block_count, kernels::kPairSums;
    fric.resize(std::size_t(block_count(c.fric.size()) * kPairSums));
    smooth.resize(std::size_t(block_count(c.smooth.size()) * kPairSums));
    walls.resize(std::size_t(block_count(c.walls.size()) * kPairSums));
    bonds.resize(std::size_t(block_count(bond_count)));
}

void EnergyBook::next_wall_velocities(const std::vector<Plane>& planes, const std::vector<Facet>& facets, double time,
                                      double dt, std::vector<Vec3>& v_next) {
    v_next.resize(planes.size() + facets.size());
    for (std::size_t k = 0; k < planes.size(); ++k) v_next[k] = planes[k].motion.mean_velocity(time - dt, time);
    for (std::size_t k = 0; k < facets.size(); ++k)
        v_next[planes.size() + k] = facets[k].motion.mean_velocity(time - dt, time);
}

void EnergyBook::account(const Step& st) {
    using kernels::kTerms;
    const Particles& p = *st.p;
    const std::vector<Plane>& planes = *st.planes;
    const std::vector<Facet>& facets = *st.facets;
    const ContactSet& c = *st.contacts;
    const double dt = st.dt, h = 0.5 * dt, time = st.time, t_n = st.t_n;
    EnergyLedger& L = ledger;

    // Walls translate: their work is the force on the particles times the wall's displacement.
    // The forward half uses the velocity the next step's move_walls() will compute.
    const std::size_t nw = planes.size() + facets.size();
    std::vector<Vec3>& v_next = wall_vel_next;
    next_wall_velocities(planes, facets, time, dt, v_next);

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
    for (std::size_t w = 0; w < nw; ++w)
        ledger::add_boundary_work(back[kernels::kBoundary], fwd[kernels::kBoundary], st.walls->force[w],
                                  st.walls->velocity[w], v_next[w], h);
    double cs[kernels::kPairSums] = {};
    for (const std::vector<double>* blocks : {&fric, &smooth, &walls})
        for (std::size_t b = 0; b < blocks->size(); b += kernels::kPairSums)
            for (int k = 0; k < kernels::kPairSums; ++k) cs[k] += (*blocks)[b + k];
    double elastic_b = 0;
    for (double e : bonds) elastic_b += e;
    // The dashpots' forward halves need the velocities after integration: v(t_n + dt/2). They
    // are summed per block of each store as the kernels sum their terms, so that an engine that
    // keeps the stores elsewhere (the batch engine's device) forms the same sums.
    double visc_fwd = 0;
    bool dashpots = false;
    for (const Material& m : *st.materials) dashpots |= m.restitution < 1.0;
    if (dashpots && dashpot_blocks_given) {
        for (double b : dashpot_blocks) visc_fwd -= b;
    } else if (dashpots) {
        // Body 2 against body 1: a particle pair's j against i, a wall contact's particle (its
        // body 2) against the wall.
        const auto blocks = [&](const ActiveContacts& a, auto&& v1, auto&& v2) {
            const int64_t n = int64_t(a.size());
            for (int64_t e0 = 0; e0 < n; e0 += kernels::kBlock)
                visc_fwd -= lane_block_sum(e0, std::min(n, e0 + kernels::kBlock), [&](int64_t s) {
                    return dashpot_forward_work(a.cand[s] != kNoSlot, a.fv[s], v1(s), v2(s), h);
                });
        };
        const auto vi = [&](const ActiveContacts& a) { return [&](int64_t s) { return p.vel[a.i[s]]; }; };
        const auto vj = [&](const ActiveContacts& a) { return [&](int64_t s) { return p.vel[a.j[s]]; }; };
        blocks(c.fric, vi(c.fric), vj(c.fric));
        blocks(c.smooth, vi(c.smooth), vj(c.smooth));
        blocks(c.walls, [&](int64_t s) { return v_next[c.walls.j[s]]; }, vi(c.walls));
    }
    dashpot_blocks_given = false;
    const double release = cs[kernels::kRelease] + st.contacts->dropped_shear_energy;
    st.contacts->dropped_shear_energy = 0;

    ledger::book_step(L, back, fwd, cs, elastic_b, visc_fwd, release, kinetic, t_n);
}

}  // namespace dem
