// The device backend's kernels (docs/gpu.md), written once: included by device_cuda.cu (nvcc:
// one thread block per system, thread `tid` of `nt`) and by device_emul.cpp (the host compiler:
// one thread, tid = 0, nt = 1). The per-index work is the host backend's bodies
// (pair_step.h, bond_step.h, particle_step.h, gather_particle), in the host backend's order; what
// a kernel adds is only the loop, the barriers and the appends to the outbox.
//
// Before including: VPPDEM_KFN (__device__ or nothing: the kernels' bodies), VPPDEM_SYNC() (a block barrier), vppdem_append(uint64_t* counter) (returns
// the old value, atomically on a device), vppdem_max_bits(uint64_t* word, double d2) (the largest
// non-negative double, by its bits).
#include "dem/batch/bond_step.h"
#include "dem/batch/device_api.h"
#include "dem/batch/lane_sums.h"
#include "dem/batch/pair_step.h"
#include "dem/batch/particle_step.h"
#include "dem/detect/candidates.h"
#include "dem/contact/interaction_lists.h"

namespace dem::batch::dev {

// Appends a record to the outbox's stream.
VPPDEM_KFN inline void emit(const Outbox& o, uint32_t kind, uint32_t a, uint32_t b) {
    const uint64_t c = vppdem_append(&o.count[0]);
    if (c < o.cap) {
        uint32_t* r = o.stream + 4 * c;
        r[0] = o.sys;
        r[1] = kind;
        r[2] = a;
        r[3] = b;
    } else {
        o.count[1] = 1;
    }
}

VPPDEM_HD inline PairEnd end_of(const Globals& g, int64_t k) { return PairEnd{g.x[k], g.v[k], g.w[k], g.r[k]}; }

// The touch test of the candidates without a contact (as step_forces, ContactSet::find_new).
VPPDEM_KFN inline void touch_body(const Globals& g, const SysView& s, int tid, int nt) {
    if (!s.active) return;
    for (int64_t i = tid; i < s.n; i += nt) {
        const int64_t a = s.base + i;
        if (s.pp.size)
            for (uint32_t k = s.pp.start[i]; k < s.pp.start[i + 1]; ++k) {
                if (!open_candidate(s.pp.slot[k], s.pp.gap[k], s.pair_reach)) continue;
                const int64_t b = s.base + s.pp.other[k];
                if (!spheres_touch(g.x[a], g.r[a], g.x[b], g.r[b])) continue;
                emit(s.out, kFoundPP, uint32_t(i), k);
            }
        if (s.pw.size)
            for (uint32_t k = s.pw.start[i]; k < s.pw.start[i + 1]; ++k) {
                if (!open_candidate(s.pw.slot[k], s.pw.gap[k], s.wall_reach)) continue;
                ContactGeom geo;
                if (!wall_geometry(end_of(g, a), s.wall_now[s.pw.other[k]], geo)) continue;
                emit(s.out, kFoundPW, uint32_t(i), k);
            }
    }
}

VPPDEM_HD inline void put_terms(double* t, const PairEnergy& e) {
    t[0] = e.elastic;  // kElastic, kSlip, kRelease, kViscous
    t[1] = e.slip;
    t[2] = e.release;
    t[3] = e.viscous;
}

// The ledger's block sums of K terms per entry (lane_sums.h, LaneSums, the host backend's too).
// Entries whose terms are zero add nothing to the bits (a sum that starts at +0 never becomes -0),
// so holes may be added.
template <int K> VPPDEM_HD inline void lane_sums(const double* terms, int64_t n, double* out, int tid, int nt) {
    for (int64_t b = tid; b < blocks(n); b += nt) {
        LaneSums<K> sums;
        const int64_t e1 = (b + 1) * kBlock < n ? (b + 1) * kBlock : n;
        for (int64_t e = b * kBlock; e < e1; ++e) sums.add(e, terms + e * K);
        sums.flush(out + b * K);
    }
}

// Forces at t of one system: the three stores' contacts, the pressure, the bonds, the ledger's
// block sums, the gather; into the outbox: the slots found apart, the wall store, the prescribed
// particles' forces (and with the ledger the dashpot forces).
VPPDEM_KFN inline void forces_body(const Globals& g, const SysView& s, int tid, int nt) {
    if (!s.active) return;
    const double dt = s.dt;
    const bool track = s.track != 0;
    const auto pair = [&](const Store& st, bool smooth, uint32_t kind) {
        for (int64_t q = tid; q < int64_t(st.size); q += nt) {
            double* t = st.terms ? st.terms + q * kPairSums : nullptr;
            if (st.cand[q] == kNone) {
                if (track) t[0] = t[1] = t[2] = t[3] = 0.0;
                continue;
            }
            PairEnergy en;
            const PairEnd a = end_of(g, s.base + st.i[q]), b = end_of(g, s.base + st.j[q]);
            PairOut o;
            if (smooth) o = track ? smooth_pair<true>(a, b, st.phys[q], dt, &en) : smooth_pair(a, b, st.phys[q], dt);
            else
                o = track ? frictional_pair<true>(a, b, st.phys[q], dt, st.shear[q], st.prev[q], &en)
                          : frictional_pair(a, b, st.phys[q], dt, st.shear[q], st.prev[q]);
            st.force[q] = o.force;
            if (!smooth) {
                st.torque1[q] = o.torque1;
                st.torque2[q] = o.torque2;
            }
            if (!o.touch) emit(s.out, kind, uint32_t(q), 0);
            if (track) {
                put_terms(t, en);
                st.fv[q] = en.fv;
            }
        }
    };
    pair(s.fric, false, kOpenFric);
    pair(s.smooth, true, kOpenSmooth);
    const Store& wl = s.walls;
    for (int64_t q = tid; q < int64_t(wl.size); q += nt) {
        double* t = wl.terms ? wl.terms + q * kPairSums : nullptr;
        if (wl.cand[q] == kNone) {
            if (track) t[0] = t[1] = t[2] = t[3] = 0.0;
            continue;
        }
        PairEnergy en;
        const PairEnd a = end_of(g, s.base + wl.i[q]);
        const WallNow& w = s.wall_now[wl.j[q]];
        const PairOut o = track ? wall_pair<true>(a, w, wl.phys[q], dt, wl.shear[q], wl.prev[q], &en)
                                : wall_pair(a, w, wl.phys[q], dt, wl.shear[q], wl.prev[q]);
        wl.force[q] = o.force;
        wl.torque2[q] = o.torque2;
        if (o.touch) {
            wl.point[q] = o.point;
            if (track) wl.fv[q] = en.fv;
        } else {
            wl.fv[q] = Vec3{};
            emit(s.out, kOpenWalls, uint32_t(q), 0);
        }
        if (track) put_terms(t, en);
    }
    for (int64_t k = s.node0 + tid; k < s.node1; k += nt) {
        const int64_t* q = g.ring + 4 * k;
        g.pressure_slot[g.node[k]] = pressure_force(g.x[q[0]], g.x[q[1]], g.x[q[2]], g.x[q[3]], s.dp);
    }
    for (int64_t k = s.bond0 + tid; k < s.bond1; k += nt) {
        const int64_t i = g.bi[k], j = g.bj[k];
        const BondEnd e1{g.x[i], g.v[i], g.w[i], g.r[i]}, e2{g.x[j], g.v[j], g.w[j], g.r[j]};
        double elastic = 0.0;
        const bool at_point = s.bond_point != 0;
        const BondOut o = track ? bond_step<true>(e1, e2, g.kn[k], g.ks[k], g.rest[k], dt, g.bshear[k], g.bprev[k],
                                                  &elastic, at_point)
                                : bond_step(e1, e2, g.kn[k], g.ks[k], g.rest[k], dt, g.bshear[k], g.bprev[k], nullptr,
                                            at_point);
        g.bforce[k] = o.force;
        g.btorque1[k] = o.torque1;
        g.btorque2[k] = o.torque2;
        if (track) s.bterms[k - s.bond0] = elastic;
    }
    VPPDEM_SYNC();
    if (track) {
        lane_sums<kPairSums>(s.fric.terms, s.fric.size, s.out.sum_fric, tid, nt);
        lane_sums<kPairSums>(s.smooth.terms, s.smooth.size, s.out.sum_smooth, tid, nt);
        lane_sums<1>(s.bterms, s.bond1 - s.bond0, s.out.sum_bonds, tid, nt);
        // The wall store: one running sum per block, in slot order (the scalar wall kernel).
        for (int64_t b = tid; b < blocks(wl.size); b += nt) {
            double sum[kPairSums] = {0.0, 0.0, 0.0, 0.0};
            const int64_t e1 = (b + 1) * kBlock < int64_t(wl.size) ? (b + 1) * kBlock : int64_t(wl.size);
            for (int64_t e = b * kBlock; e < e1; ++e)
                for (int k = 0; k < kPairSums; ++k) sum[k] += wl.terms[e * kPairSums + k];
            for (int k = 0; k < kPairSums; ++k) s.out.sum_walls[b * kPairSums + k] = sum[k];
        }
        for (int64_t q = tid; q < int64_t(s.fric.size); q += nt) s.out.fv_fric[q] = s.fric.fv[q];
        for (int64_t q = tid; q < int64_t(s.smooth.size); q += nt) s.out.fv_smooth[q] = s.smooth.fv[q];
    }
    for (int64_t q = tid; q < int64_t(wl.size); q += nt) {
        s.out.walls[4 * q] = wl.force[q];
        s.out.walls[4 * q + 1] = wl.torque2[q];
        s.out.walls[4 * q + 2] = wl.point[q];
        s.out.walls[4 * q + 3] = wl.fv[q];
    }
    // The gather of World (gather_in_order): each particle's interaction list in order.
    const GatherTables tb{{s.fric.force, s.smooth.force, s.walls.force, g.bforce + s.bond0},
                          {{s.fric.torque1, s.fric.torque2},
                           {s.smooth.torque1, s.smooth.torque2},
                           {s.walls.torque2, s.walls.torque2},
                           {g.btorque1 + s.bond0, g.btorque2 + s.bond0}}};
    for (int64_t i = tid; i < s.n; i += nt) {
        Vec3 fi, ti;
        gather_particle(tb, s.link_ref + s.link_start[i], s.link_count[i], fi, ti);
        if (s.with_pressure) fi += g.pressure_slot[s.base + i];
        g.f[s.base + i] = fi;
        g.t[s.base + i] = ti;
    }
    VPPDEM_SYNC();
    for (int64_t q = s.presc0 + tid; q < s.presc1; q += nt) {
        const int64_t k = s.base + g.prescribed[q];
        s.out.presc[2 * (q - s.presc0)] = g.f[k];
        s.out.presc[2 * (q - s.presc0) + 1] = g.pressure_slot[k];
    }
}

// Motion to t + dt of the free particles (advance_particle), the largest squared move since the
// rebuild, the ledger's block sums (and the velocities, which the ledger reads).
VPPDEM_KFN inline void motion_body(const Globals& g, const SysView& s, int tid, int nt) {
    if (!s.active) return;
    const bool track = s.track != 0;
    double max_d2 = 0.0;
    for (int64_t i = tid; i < s.n; i += nt) {
        const int64_t k = s.base + i;
        ParticleState st{g.x[k], g.v[k], g.w[k]};
        const Vec3 fp = s.with_pressure ? g.pressure_slot[k] : Vec3{};
        if (track) {
            ParticleEnergy en;
            advance_particle<true>(st, g.f[k], g.fx[k], g.t[k], g.m[k], g.inv_m[k], g.inv_i[k], s.gravity, s.dt, s.lambda,
                                   &en, fp, g.r[k]);
            double* t = s.pterms + i * kParticleSums;
            for (int q = 0; q < 5; ++q) {
                t[q] = en.back[q];
                t[5 + q] = en.fwd[q];
            }
            t[10] = en.kinetic;
        } else {
            advance_particle(st, g.f[k], g.fx[k], g.t[k], g.m[k], g.inv_m[k], g.inv_i[k], s.gravity, s.dt, s.lambda);
        }
        if (!(g.inv_m[k] > 0.0)) continue;
        g.x[k] = st.x;
        g.v[k] = st.v;
        g.w[k] = st.w;
        const FloatVec3 rf = s.ref_pos[i];
        const double d2 = norm2(st.x - Vec3{rf.x, rf.y, rf.z});
        max_d2 = d2 > max_d2 ? d2 : max_d2;
    }
    vppdem_max_bits(s.out.max_d2, max_d2);
    VPPDEM_SYNC();
    if (track) {
        lane_sums<kParticleSums>(s.pterms, s.n, s.out.sum_particles, tid, nt);
        for (int64_t i = tid; i < s.n; i += nt) s.out.v[i] = g.v[s.base + i];
    }
}

// The patches (device_api.h), one per index.
VPPDEM_HD inline void apply_patch(const Patch* p, const uint32_t* payload, uint32_t q) {
    uint32_t* dst = reinterpret_cast<uint32_t*>(p[q].dst);
    for (uint32_t e = 0; e < p[q].words; ++e) dst[e] = payload[p[q].from + e];
}

}  // namespace dem::batch::dev
