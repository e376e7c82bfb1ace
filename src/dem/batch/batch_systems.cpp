#include "dem/batch/batch_systems.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "dem/batch/bond_step.h"
#include "dem/batch/particle_step.h"
#include "dem/core/parallel.h"
#include "dem/core/thread_team.h"

namespace dem::batch {

std::size_t BatchSystems::add(const World& world) {
    const Particles& p = world.particles;
    if (!world.clumps().empty())
        throw std::invalid_argument("batch: a system with clumps is not supported yet (docs/gpu.md)");
    if (!world.planes.empty() || !world.facets.empty() || world.contact_count() != 0)
        throw std::invalid_argument("batch: walls and contacts are not supported yet (docs/gpu.md)");
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.flags[i] & kPrescribed) throw std::invalid_argument("batch: prescribed particles are not supported yet");
    const std::size_t s = systems();
    const int64_t base = int64_t(x.size()), bond_base = int64_t(bi.size());
    gravity.push_back(world.params.gravity);
    dt.push_back(world.params.dt);
    lambda.push_back(world.params.local_damping);
    for (std::size_t i = 0; i < p.size(); ++i) {
        x.push_back(p.pos[i]);
        v.push_back(p.vel[i]);
        w.push_back(p.angvel[i]);
        f.push_back(p.force[i]);
        fx.push_back(p.ext_force.empty() ? Vec3{} : p.ext_force[i]);
        t.push_back(p.torque[i]);
        m.push_back(p.mass[i]);
        inv_m.push_back(p.inv_mass[i]);
        inv_i.push_back(p.inv_inertia[i]);
        r.push_back(p.radius[i]);
        pressure_slot.emplace_back();
    }
    first.push_back(int64_t(x.size()));
    const BondList& bl = world.bonds();
    std::vector<std::vector<int64_t>> per(p.size());
    for (std::size_t k = 0; k < bl.size(); ++k) {
        bi.push_back(base + bl.i[k]);
        bj.push_back(base + bl.j[k]);
        kn.push_back(bl.phys[k].kn);
        ks.push_back(bl.phys[k].ks);
        rest.push_back(bl.phys[k].rest_length);
        shear.push_back(bl.shear[k]);
        prev_normal.push_back(bl.prev_normal[k]);
        bond_force.push_back(bl.force[k]);
        torque1.push_back(bl.torque1[k]);
        torque2.push_back(bl.torque2[k]);
        per[bl.i[k]].push_back(2 * (bond_base + int64_t(k)));
        per[bl.j[k]].push_back(2 * (bond_base + int64_t(k)) + 1);
    }
    // World's order: by reference value, all of a particle's bonds as body 1 first, then as body 2.
    for (auto& l : per) {
        std::stable_sort(l.begin(), l.end(), [](int64_t a, int64_t c) { return (a & 1) != (c & 1) ? (a & 1) < (c & 1) : a < c; });
        links.insert(links.end(), l.begin(), l.end());
        link_start.push_back(int64_t(links.size()));
    }
    bond_first.push_back(int64_t(bi.size()));
    dp.push_back(world.pressure.nodes.empty() ? 0.0 : world.pressure.dp);
    for (const PressureNode& q : world.pressure.nodes) {
        node.push_back(base + q.node);
        ring.push_back({base + q.ring[0], base + q.ring[1], base + q.ring[2], base + q.ring[3]});
    }
    node_first.push_back(int64_t(node.size()));
    return s;
}

void BatchSystems::store(std::size_t s, World& world) const {
    Particles& p = world.particles;
    if (s >= systems() || std::size_t(first[s + 1] - first[s]) != p.size())
        throw std::invalid_argument("batch: system " + std::to_string(s) + " does not match the world");
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = std::size_t(first[s]) + i;
        p.pos[i] = x[k];
        p.vel[i] = v[k];
        p.angvel[i] = w[k];
    }
    world.invalidate_candidates();
}

namespace {

// System s's particles by advance_particle.
void advance_system(BatchSystems& b, int64_t s) {
    for (int64_t k = b.first[s]; k < b.first[s + 1]; ++k) {
        ParticleState st{b.x[k], b.v[k], b.w[k]};
        advance_particle(st, b.f[k], b.fx[k], b.t[k], b.m[k], b.inv_m[k], b.inv_i[k], b.gravity[s], b.dt[s], b.lambda[s]);
        b.x[k] = st.x;
        b.v[k] = st.v;
        b.w[k] = st.w;
    }
}

}  // namespace

void step_host(BatchSystems& b, int threads) {
    const int nt = threads > 1 ? threads : 1;
    ThreadTeam team;
    team.run(nt, [&](int tid) {
        const auto [s0, s1] = thread_range(int64_t(b.systems()), tid, nt);
        for (int64_t s = s0; s < s1; ++s) {
            const bool with_pressure = b.dp[s] != 0.0 && b.node_first[s + 1] > b.node_first[s];
            for (int64_t k = b.node_first[s]; k < b.node_first[s + 1]; ++k) {
                const auto& q = b.ring[k];
                b.pressure_slot[b.node[k]] = pressure_force(b.x[q[0]], b.x[q[1]], b.x[q[2]], b.x[q[3]], b.dp[s]);
            }
            for (int64_t k = b.bond_first[s]; k < b.bond_first[s + 1]; ++k) {
                const int64_t i = b.bi[k], j = b.bj[k];
                const BondOut o = bond_step({b.x[i], b.v[i], b.w[i], b.r[i]}, {b.x[j], b.v[j], b.w[j], b.r[j]}, b.kn[k],
                                            b.ks[k], b.rest[k], b.dt[s], b.shear[k], b.prev_normal[k]);
                b.bond_force[k] = o.force;
                b.torque1[k] = o.torque1;
                b.torque2[k] = o.torque2;
            }
            // The gather of World: in list order, alternating two partial sums.
            for (int64_t i = b.first[s]; i < b.first[s + 1]; ++i) {
                Vec3 fa, ta, fb, tb;
                const auto add = [&](int64_t ref, Vec3& f, Vec3& t) {
                    const int64_t k = ref >> 1;
                    const bool second = ref & 1;
                    f += b.bond_force[k] * (second ? 1.0 : -1.0);
                    t += second ? b.torque2[k] : b.torque1[k];
                };
                const int64_t e0 = b.link_start[i], m = b.link_start[i + 1] - e0;
                int64_t e = 0;
                for (; e + 1 < m; e += 2) {
                    add(b.links[e0 + e], fa, ta);
                    add(b.links[e0 + e + 1], fb, tb);
                }
                if (e < m) add(b.links[e0 + e], fa, ta);
                Vec3 fi = fa + fb;
                if (with_pressure) fi += b.pressure_slot[i];
                b.f[i] = fi;
                b.t[i] = ta + tb;
            }
            advance_system(b, s);
        }
    });
}

void advance_host(BatchSystems& b, int threads) {
    const int nt = threads > 1 ? threads : 1;
    ThreadTeam team;
    team.run(nt, [&](int tid) {
        const auto [s0, s1] = thread_range(int64_t(b.systems()), tid, nt);
        for (int64_t s = s0; s < s1; ++s) advance_system(b, s);
    });
}

}  // namespace dem::batch
