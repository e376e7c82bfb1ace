#include "dem/batch/batch_systems.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "dem/batch/bond_step.h"
#include "dem/core/lane_sums.h"
#include "dem/batch/pair_step.h"
#include "dem/batch/particle_step.h"
#include "dem/kernels/kernels.h"
#include "dem/core/parallel.h"
#include "dem/core/thread_team.h"

namespace dem::batch {

std::size_t BatchSystems::add(World& wd) {
    const Particles& p = wd.particles;
    if (!wd.clumps().empty())
        throw std::invalid_argument("batch: a system with clumps is not supported yet (docs/gpu.md)");
    const std::size_t s = systems();
    const int64_t base = int64_t(x.size());
    world.push_back(&wd);
    gravity.push_back(wd.params.gravity);
    dt.push_back(wd.params.dt);
    lambda.push_back(wd.params.local_damping);
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
        if (p.flags[i] & kPrescribed) prescribed.push_back(uint32_t(i));
    }
    first.push_back(int64_t(x.size()));
    presc_first.push_back(int64_t(prescribed.size()));
    const BondList& bl = wd.bonds();
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
    }
    bond_first.push_back(int64_t(bi.size()));
    bond_point.push_back(bl.arm == BondArm::kBondPoint ? 1 : 0);
    if (!wd.pressure.fans.empty())
        throw std::invalid_argument("batch: pressure fans (a triangulated membrane) are not supported by the batch engine");
    dp.push_back(world_underpressure(wd));
    for (const PressureNode& q : wd.pressure.nodes) {
        node.push_back(base + q.node);
        ring.push_back({base + q.ring[0], base + q.ring[1], base + q.ring[2], base + q.ring[3]});
    }
    node_first.push_back(int64_t(node.size()));
    return s;
}

void BatchSystems::store(std::size_t s) const {
    if (s >= systems()) throw std::invalid_argument("batch: no system " + std::to_string(s));
    World& wd = *world[s];
    Particles& p = wd.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = std::size_t(first[s]) + i;
        p.pos[i] = x[k];
        p.vel[i] = v[k];
        p.angvel[i] = w[k];
        p.force[i] = f[k];
        p.torque[i] = t[k];
    }
    BondList& bl = wd.engine_bonds();
    for (std::size_t k = 0; k < bl.size(); ++k) {
        const std::size_t q = std::size_t(bond_first[s]) + k;
        bl.shear[k] = shear[q];
        bl.prev_normal[k] = prev_normal[q];
        bl.force[k] = bond_force[q];
        bl.torque1[k] = torque1[q];
        bl.torque2[k] = torque2[q];
    }
    wd.engine_handback();
}

namespace {

// Runs body(q) for the entries of each block of n and flushes the block's sums into out.
template <int K, class Body> void blocks_of(std::size_t n, double* out, Body&& body) {
    const int64_t nb = kernels::block_count(n);
    for (int64_t b = 0; b < nb; ++b) {
        LaneSums<K> sums;
        for (int64_t q = b * kernels::kBlock; q < std::min(int64_t(n), (b + 1) * kernels::kBlock); ++q) body(q, sums);
        if (out) sums.flush(out + b * K);
    }
}

}  // namespace

// Forces at t of system s: World's phases (World::engine_*) around the kernel bodies, in the order
// of World::compute_forces(). The loops over slots, bonds, nodes and particles are the kernels'
// index spaces (one thread per index on a device).
void step_forces(BatchSystems& b, std::size_t sys) {
    const int64_t s = int64_t(sys);
    World& wd = *b.world[s];
    const int64_t base = b.first[s], n = b.first[s + 1] - base;
    const int64_t bb = b.bond_first[s];
    const double dt = b.dt[s];
    const auto end = [&](uint32_t i) { return PairEnd{b.x[base + i], b.v[base + i], b.w[base + i], b.r[base + i]}; };

    // Forces at t. The broad phase reads World's positions: they are handed over when it runs.
    if (wd.engine_rebuild_due())
        for (int64_t i = 0; i < n; ++i) wd.particles.pos[std::size_t(i)] = b.x[base + i];
    wd.engine_begin_forces();
    ContactSet& c = wd.engine_contacts();
    const WallState& walls = wd.wall_state();
    const auto now = [&](uint32_t k) -> const WallNow& { return walls.now[k]; };
    // Candidates without a contact that could have closed their gap since the rebuild, tested
    // (as ContactSet::find_new, with World's reach).
    const auto [pair_reach, wall_reach] = wd.engine_reach();
    if (!c.pp.other.empty())
        for (int64_t i = 0; i < n; ++i)
            for (uint32_t k = c.pp.start[i]; k < c.pp.start[i + 1]; ++k) {
                if (!open_candidate(c.pp.slot[k], c.pp.gap[k], pair_reach)) continue;
                const uint32_t j = c.pp.other[k];
                if (spheres_touch(b.x[base + i], b.r[base + i], b.x[base + j], b.r[base + j])) {
                    c.new_pp[0].push_back(uint32_t(i));
                    c.new_pp[0].push_back(k);
                }
            }
    if (!c.pw.other.empty())
        for (int64_t i = 0; i < n; ++i)
            for (uint32_t k = c.pw.start[i]; k < c.pw.start[i + 1]; ++k) {
                if (!open_candidate(c.pw.slot[k], c.pw.gap[k], wall_reach)) continue;
                ContactGeom g;
                if (wall_geometry(end(uint32_t(i)), now(c.pw.other[k]), g)) {
                    c.new_pw[0].push_back(uint32_t(i));
                    c.new_pw[0].push_back(k);
                }
            }
    wd.engine_activate();

    // The contacts of each store, slot by slot; a pair found apart is zeroed and its slot freed.
    // With the ledger, the terms of each block of slots into World's book (the wall store's in
    // slot order, as its scalar kernel).
    const bool track = wd.params.track_energy;
    EnergyBook& book = wd.engine_book();
    constexpr int P = kernels::kPairSums;
    const auto pair_terms = [](const PairEnergy& e, double* t) {
        t[kernels::kElastic] = e.elastic;
        t[kernels::kSlip] = e.slip;
        t[kernels::kRelease] = e.release;
        t[kernels::kViscous] = e.viscous;
    };
    blocks_of<P>(c.fric.size(), track ? book.fric.data() : nullptr, [&](int64_t q, LaneSums<P>& sums) {
        if (c.fric.cand[q] == kNoSlot) return;
        PairEnergy en;
        const PairOut o = track ? frictional_pair<true>(end(c.fric.i[q]), end(c.fric.j[q]), c.fric.phys[q], dt,
                                                        c.fric.shear[q], c.fric.prev_normal[q], &en)
                                : frictional_pair(end(c.fric.i[q]), end(c.fric.j[q]), c.fric.phys[q], dt, c.fric.shear[q],
                                                  c.fric.prev_normal[q]);
        c.fric.force[q] = o.force;
        c.fric.torque1[q] = o.torque1;
        c.fric.torque2[q] = o.torque2;
        if (!o.touch) c.opened_fric[0].push_back(uint32_t(q));
        if (track) {
            double t[P];
            pair_terms(en, t);
            sums.add(q, t);
            c.fric.fv[q] = en.fv;
        }
    });
    blocks_of<P>(c.smooth.size(), track ? book.smooth.data() : nullptr, [&](int64_t q, LaneSums<P>& sums) {
        if (c.smooth.cand[q] == kNoSlot) return;
        PairEnergy en;
        const PairOut o = track ? smooth_pair<true>(end(c.smooth.i[q]), end(c.smooth.j[q]), c.smooth.phys[q], dt, &en)
                                : smooth_pair(end(c.smooth.i[q]), end(c.smooth.j[q]), c.smooth.phys[q], dt);
        c.smooth.force[q] = o.force;
        if (!o.touch) c.opened_smooth[0].push_back(uint32_t(q));
        if (track) {
            double t[P];
            pair_terms(en, t);
            sums.add(q, t);
            c.smooth.fv[q] = en.fv;
        }
    });
    for (int64_t blk = 0; blk < kernels::block_count(c.walls.size()); ++blk) {
        double sum[P] = {};
        for (int64_t q = blk * kernels::kBlock; q < std::min(int64_t(c.walls.size()), (blk + 1) * kernels::kBlock); ++q) {
            if (c.walls.cand[q] == kNoSlot) continue;
            PairEnergy en;
            const WallNow& wl = now(c.walls.j[q]);
            const PairOut o = track ? wall_pair<true>(end(c.walls.i[q]), wl, c.walls.phys[q], dt, c.walls.shear[q],
                                                      c.walls.prev_normal[q], &en)
                                    : wall_pair(end(c.walls.i[q]), wl, c.walls.phys[q], dt, c.walls.shear[q],
                                                c.walls.prev_normal[q]);
            c.walls.force[q] = o.force;
            c.walls.torque2[q] = o.torque2;
            if (o.touch) {
                c.walls.point[q] = o.point;
                if (track) {
                    c.walls.fv[q] = en.fv;
                    sum[kernels::kElastic] += en.elastic;
                    sum[kernels::kSlip] += en.slip;
                    sum[kernels::kViscous] += en.viscous;
                }
            } else {
                c.walls.fv[q] = Vec3{};
                c.opened_walls[0].push_back(uint32_t(q));
                if (track) sum[kernels::kRelease] += en.release;
            }
        }
        if (track) std::copy(sum, sum + P, book.walls.data() + blk * P);
    }
    // The underpressure is World's (a driver may change it between steps: the air inside).
    b.dp[s] = world_underpressure(wd);
    const bool with_pressure = b.with_pressure(sys);
    for (int64_t k = b.node_first[s]; k < b.node_first[s + 1]; ++k) {
        const auto& q = b.ring[k];
        b.pressure_slot[b.node[k]] = pressure_force(b.x[q[0]], b.x[q[1]], b.x[q[2]], b.x[q[3]], b.dp[s]);
    }
    blocks_of<1>(std::size_t(b.bond_first[s + 1] - bb), track ? book.bonds.data() : nullptr, [&](int64_t q, LaneSums<1>& sums) {
        const int64_t k = bb + q, i = b.bi[k], j = b.bj[k];
        const BondEnd e1{b.x[i], b.v[i], b.w[i], b.r[i]}, e2{b.x[j], b.v[j], b.w[j], b.r[j]};
        double elastic = 0.0;
        const bool at_point = b.bond_point[s] != 0;
        const BondOut o = track ? bond_step<true>(e1, e2, b.kn[k], b.ks[k], b.rest[k], dt, b.shear[k], b.prev_normal[k],
                                                  &elastic, at_point)
                                : bond_step(e1, e2, b.kn[k], b.ks[k], b.rest[k], dt, b.shear[k], b.prev_normal[k],
                                            nullptr, at_point);
        b.bond_force[k] = o.force;
        b.torque1[k] = o.torque1;
        b.torque2[k] = o.torque2;
        if (track) sums.add(q, &elastic);
    });
    // The gather of World (gather_in_order): each particle's interaction list in order; the force
    // on body 1 is the opposite of that on body 2.
    const GatherTables tb{{c.fric.force.data(), c.smooth.force.data(), c.walls.force.data(), b.bond_force.data() + bb},
                          {{c.fric.torque1.data(), c.fric.torque2.data()},
                           {c.smooth.torque1.data(), c.smooth.torque2.data()},
                           {c.walls.torque2.data(), c.walls.torque2.data()},
                           {b.torque1.data() + bb, b.torque2.data() + bb}}};
    for (int64_t i = 0; i < n; ++i) {
        Vec3 fi, ti;
        gather_particle(tb, c.links.ref.data() + c.links.start[i], c.links.count[i], fi, ti);
        if (with_pressure) fi += b.pressure_slot[base + i];
        b.f[base + i] = fi;
        b.t[base + i] = ti;
    }
    wd.engine_end_forces();
    // The prescribed particles' forces are World's to read (a driver reads what they carry).
    for (int64_t q = b.presc_first[s]; q < b.presc_first[s + 1]; ++q)
        wd.particles.force[b.prescribed[q]] = b.f[base + b.prescribed[q]];
}

void step_motion(BatchSystems& b, std::size_t sys) {
    const int64_t s = int64_t(sys);
    World& wd = *b.world[s];
    const int64_t base = b.first[s], n = b.first[s + 1] - base;
    const double dt = b.dt[s];
    const bool track = wd.params.track_energy;
    EnergyBook& book = wd.engine_book();
    const BroadPhase& bp = wd.broad_phase();
    const bool with_pressure = b.with_pressure(sys);

    // Motion to t + dt: the free particles, then World's prescribed ones, then the clock (and
    // the ledger, from the block sums, the prescribed particles' forces and the new velocities).
    const std::vector<FloatVec3>& ref = bp.ref_pos;
    constexpr int Q = kernels::kParticleSums;
    if (track) book.particles.assign(std::size_t(kernels::block_count(std::size_t(n)) * Q), 0.0);
    double max_d2 = 0.0;
    blocks_of<Q>(std::size_t(n), track ? book.particles.data() : nullptr, [&](int64_t i, LaneSums<Q>& sums) {
        const int64_t k = base + i;
        ParticleState st{b.x[k], b.v[k], b.w[k]};
        if (track) {
            ParticleEnergy en;
            advance_particle<true>(st, b.f[k], b.fx[k], b.t[k], b.m[k], b.inv_m[k], b.inv_i[k], b.gravity[s], dt,
                                   b.lambda[s], &en, with_pressure ? b.pressure_slot[k] : Vec3{}, b.r[k]);
            double t[Q];
            for (int q = 0; q < kernels::kTerms; ++q) {
                t[q] = en.back[q];
                t[kernels::kTerms + q] = en.fwd[q];
            }
            t[2 * kernels::kTerms] = en.kinetic;
            sums.add(i, t);
        } else {
            advance_particle(st, b.f[k], b.fx[k], b.t[k], b.m[k], b.inv_m[k], b.inv_i[k], b.gravity[s], dt, b.lambda[s]);
        }
        if (!(b.inv_m[k] > 0.0)) return;
        b.x[k] = st.x;
        b.v[k] = st.v;
        b.w[k] = st.w;
        const FloatVec3 rf = ref[std::size_t(i)];
        max_d2 = std::max(max_d2, norm2(st.x - Vec3{rf.x, rf.y, rf.z}));
    });
    max_d2 = std::max(max_d2, wd.engine_follow_motions(b.pressure_slot.data() + base));
    for (int64_t q = b.presc_first[s]; q < b.presc_first[s + 1]; ++q) {
        const uint32_t i = b.prescribed[q];
        b.x[base + i] = wd.particles.pos[i];
        b.v[base + i] = wd.particles.vel[i];
    }
    if (track)
        for (int64_t i = 0; i < n; ++i) wd.particles.vel[std::size_t(i)] = b.v[base + i];
    wd.engine_end_step(max_d2);
}

void step_host(BatchSystems& b, int threads, uint64_t steps) {
    const int nt = threads > 1 ? threads : 1;
    ThreadTeam team;
    team.run(nt, [&](int tid) {
        const auto [s0, s1] = thread_range(int64_t(b.systems()), tid, nt);
        for (int64_t s = s0; s < s1; ++s)
            for (uint64_t k = 0; k < steps; ++k) {
                step_forces(b, std::size_t(s));
                step_motion(b, std::size_t(s));
            }
    });
}

}  // namespace dem::batch
