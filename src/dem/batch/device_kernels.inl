// The device backend's kernels (docs/gpu.md), written once: included by device_cuda.cu (nvcc:
// one thread block per system, thread `tid` of `nt`) and by device_emul.cpp (the host compiler:
// one thread, tid = 0, nt = 1). The per-index work is the host backend's bodies
// (pair_step.h, bond_step.h, particle_step.h, gather_particle), in the host backend's order; what
// a kernel adds is only the loop, the barriers and the appends to the outbox. The contact
// lifecycle is here too, as ContactSet does it (the found contacts' slots in candidate order, the
// lowest holes first; the frees; each particle's sorted list), so that a step needs no round trip
// to the host between the touch test and the forces: one thread of the block decides the slots.
//
// Before including: VPPDEM_KFN (__device__ or nothing: the kernels' bodies), VPPDEM_SYNC() (a
// block barrier), vppdem_append(uint64_t* counter) (returns the old value, atomically on a
// device), vppdem_max_bits(uint64_t* word, double d2) (the largest non-negative double, by its
// bits).
#include <cstring>

#include "dem/batch/bond_step.h"
#include "dem/batch/device_api.h"
#include "dem/batch/pair_step.h"
#include "dem/batch/particle_step.h"
#include "dem/core/ledger_step.h"
#include "dem/detect/candidates.h"
#include "dem/detect/rebuild_rule.h"
#include "dem/contact/contact_physics.h"
#include "dem/contact/interaction_lists.h"
#include "dem/world/wall_state.h"

namespace dem::batch::dev {

VPPDEM_HD inline PairEnd end_of(const Globals& g, int64_t k) { return PairEnd{g.x[k], g.v[k], g.w[k], g.r[k]}; }

// nvcc unrolls the short fixed loops below so that their loads are issued together (a GPU thread
// waits at the first use of a load, not at its issue): a chain of 64 loads becomes 8 waits.
#if defined(__CUDA_ARCH__)
#define VPPDEM_UNROLL _Pragma("unroll")
#else
#define VPPDEM_UNROLL
#endif

// The lowest set bit of a nonzero word.
VPPDEM_HD inline int lowest_bit(uint64_t w) {
#if defined(__CUDA_ARCH__)
    return __ffsll(static_cast<long long>(w)) - 1;
#else
    return __builtin_ctzll(w);
#endif
}

// The double whose bits are b (the largest move's word).
VPPDEM_HD inline double double_of_bits(uint64_t b) {
#if defined(__CUDA_ARCH__)
    return __longlong_as_double(static_cast<long long>(b));
#else
    double d;
    std::memcpy(&d, &b, 8);
    return d;
#endif
}

// ---- the contact lifecycle (ContactSet's find_new, activate_new, release_opened on the device)

// The touch test of the candidates without a contact (as ContactSet::find_new): each found
// (particle, candidate) is appended to the system's records, in any order.
VPPDEM_KFN inline void touch_body(const Globals& g, const SysView& s, int tid, int nt) {
    Life& L = *s.out.life;
    for (int64_t i = tid; i < s.n; i += nt) {
        const int64_t a = s.base + i;
        if (s.pp.size)
            for (uint32_t k = s.pp.start[i]; k < s.pp.start[i + 1]; ++k) {
                if (!open_candidate(s.pp.slot[k], s.pp.gap[k], s.in->pair_reach)) continue;
                const int64_t b = s.base + s.pp.other[k];
                if (!spheres_touch(g.x[a], g.r[a], g.x[b], g.r[b])) continue;
                const uint64_t c = vppdem_append(&L.found[0]);
                s.found_pp[2 * c] = uint32_t(i);
                s.found_pp[2 * c + 1] = k;
            }
        if (s.pw.size)
            for (uint32_t k = s.pw.start[i]; k < s.pw.start[i + 1]; ++k) {
                if (!open_candidate(s.pw.slot[k], s.pw.gap[k], s.in->wall_reach)) continue;
                ContactGeom geo;
                if (!wall_geometry(end_of(g, a), s.wall_now[s.pw.other[k]], geo)) continue;
                const uint64_t c = vppdem_append(&L.found[1]);
                s.found_pw[2 * c] = uint32_t(i);
                s.found_pw[2 * c + 1] = k;
            }
    }
}

// The records (particle, candidate) in candidate order (a shell sort: one thread sorts, and a
// step finds few). Candidates are unique, so the order is World's (activate_new sorts them so).
VPPDEM_HD inline void sort_by_candidate(uint32_t* rec, uint32_t n) {
    uint32_t gap = 1;
    while (gap < n / 3) gap = 3 * gap + 1;
    for (; gap > 0; gap /= 3)
        for (uint32_t e = gap; e < n; ++e) {
            const uint32_t i = rec[2 * e], k = rec[2 * e + 1];
            uint32_t q = e;
            for (; q >= gap && rec[2 * (q - gap) + 1] > k; q -= gap) {
                rec[2 * q] = rec[2 * (q - gap)];
                rec[2 * q + 1] = rec[2 * (q - gap) + 1];
            }
            rec[2 * q] = i;
            rec[2 * q + 1] = k;
        }
}

// InteractionLists::insert and erase on the device's lists (kept sorted by reference; the room
// is never short between layouts, else the system's overflow is set).
VPPDEM_HD inline void link_insert(const SysView& s, uint32_t i, uint32_t r) {
    const uint32_t n = s.link_count[i];
    if (n >= s.link_cap[i]) {
        s.out.life->overflow = 1;
        return;
    }
    uint32_t* b = s.link_ref + s.link_start[i];
    uint32_t e = n;
    for (; e > 0 && b[e - 1] > r; --e) b[e] = b[e - 1];
    b[e] = r;
    s.link_count[i] = n + 1;
}
VPPDEM_HD inline void link_erase(const SysView& s, uint32_t i, uint32_t r) {
    uint32_t* b = s.link_ref + s.link_start[i];
    const uint32_t n = s.link_count[i];
    uint32_t e = 0;
    while (e < n && b[e] < r) ++e;
    if (e == n || b[e] != r) return;
    for (; e + 1 < n; ++e) b[e] = b[e + 1];
    s.link_count[i] = n - 1;
}

VPPDEM_HD inline const Store& store_at(const SysView& s, int k) { return k == 0 ? s.fric : k == 1 ? s.smooth : s.walls; }

// ActiveContacts::place: a new contact with zero history in the first hole at or after the
// cursor (which moves past it), or in a new slot at the end; returns the slot (kNone: no room).
VPPDEM_HD inline uint32_t place(const SysView& s, int k, uint32_t a, uint32_t b, uint32_t candidate, const ContactPhys& p,
                                uint32_t& cursor) {
    Life& L = *s.out.life;
    const Store& st = store_at(s, k);
    const uint32_t size = L.size[k];
    if (L.free[k] == 0) cursor = cursor > size ? cursor : size;  // no hole: the scan would reach the end
    // The first hole at or after the cursor, 64 slots per word of the store's hole bits (the scan
    // of cand one slot at a time was one thread's chain of dependent loads).
    while (cursor < size) {
        const uint64_t word = st.hole_bits[cursor >> 6] & (~uint64_t(0) << (cursor & 63u));
        if (word) {
            const uint32_t q = (cursor & ~63u) + uint32_t(lowest_bit(word));
            cursor = q < size ? q : size;
            break;
        }
        cursor = (cursor | 63u) + 1;
    }
    if (cursor > size) cursor = size;
    uint32_t q;
    if (cursor >= size) {
        if (size >= st.cap) {
            L.overflow = 1;
            return kNone;
        }
        q = size;
        L.size[k] = size + 1;
        cursor = size + 1;
    } else {
        q = cursor++;
        --L.free[k];
        st.hole_bits[q >> 6] &= ~(uint64_t(1) << (q & 63u));
    }
    st.i[q] = a;
    st.j[q] = b;
    st.cand[q] = candidate;
    st.phys[q] = p;
    st.shear[q] = st.prev[q] = st.force[q] = st.torque1[q] = st.torque2[q] = st.point[q] = st.fv[q] = Vec3{};
    return q;
}

// ContactPhysics::pair and ::wall from the device's copies of the materials.
VPPDEM_HD inline ContactPhys pair_phys(const Globals& g, const SysView& s, uint32_t i, uint32_t j) {
    const int64_t a = s.base + i, b = s.base + j;
    const MatCoef &ma = s.mats[g.mat[a]], &mb = s.mats[g.mat[b]];
    const double m_eff = pair_mass(g.inv_m[a] != 0.0, g.m[a], g.inv_m[b] != 0.0, g.m[b]);
    return contact_phys_of(ma.young, ma.ratio, ma.friction, g.r[a], mb.young, mb.ratio, mb.friction, g.r[b], m_eff,
                           s.zeta[g.mat[a] * s.materials + g.mat[b]]);
}
VPPDEM_HD inline ContactPhys wall_phys(const Globals& g, const SysView& s, uint32_t i, uint32_t w) {
    const int64_t a = s.base + i;
    const uint32_t wm = s.wall_mat[w];
    const MatCoef &mw = s.mats[wm], &mp = s.mats[g.mat[a]];
    return contact_phys_of(mw.young, mw.ratio, mw.friction, g.r[a], mp.young, mp.ratio, mp.friction, g.r[a], g.m[a],
                           s.zeta[wm * s.materials + g.mat[a]]);
}

// ContactSet::activate_new (one thread): the records found get slots in candidate order, the
// lowest holes first, and their entries in the lists.
VPPDEM_HD inline void place_found(const Globals& g, const SysView& s) {
    using IL = InteractionLists;
    Life& L = *s.out.life;
    const uint32_t npp = uint32_t(L.found[0]), npw = uint32_t(L.found[1]);
    sort_by_candidate(s.found_pp, npp);
    sort_by_candidate(s.found_pw, npw);
    const uint64_t before = uint64_t(L.size[0]) + L.size[1] + L.size[2];
    uint32_t cursor[3] = {0, 0, 0};
    for (uint32_t e = 0; e < npp; ++e) {
        const uint32_t i = s.found_pp[2 * e], k = s.found_pp[2 * e + 1], j = s.pp.other[k];
        const ContactPhys ph = pair_phys(g, s, i, j);
        const bool smooth = ph.mu == 0.0;
        const uint32_t q = place(s, smooth ? 1 : 0, i, j, k, ph, cursor[smooth ? 1 : 0]);
        if (q == kNone) return;
        s.pp.slot[k] = q | (smooth ? kSmooth : 0u);
        const IL::Source src = smooth ? IL::kFrictionless : IL::kFrictional;
        link_insert(s, i, IL::make(src, false, q));
        link_insert(s, j, IL::make(src, true, q));
    }
    for (uint32_t e = 0; e < npw; ++e) {
        const uint32_t i = s.found_pw[2 * e], k = s.found_pw[2 * e + 1], w = s.pw.other[k];
        const uint32_t q = place(s, 2, i, w, k, wall_phys(g, s, i, w), cursor[2]);
        if (q == kNone) return;
        s.pw.slot[k] = q;
        link_insert(s, i, IL::make(IL::kWall, true, q));
    }
    const uint64_t filled = uint64_t(npp + npw) - (uint64_t(L.size[0]) + L.size[1] + L.size[2] - before);
    L.holes = L.holes > filled ? L.holes - filled : 0;
}

// ContactSet::release_opened (one thread): the slots found apart become holes.
VPPDEM_HD inline void release_opened(const SysView& s) {
    using IL = InteractionLists;
    Life& L = *s.out.life;
    for (int k = 0; k < 3; ++k) {
        const Store& st = store_at(s, k);
        const Cands& cl = k == 2 ? s.pw : s.pp;
        const IL::Source src = k == 0 ? IL::kFrictional : k == 1 ? IL::kFrictionless : IL::kWall;
        for (uint64_t e = 0; e < L.opened[k]; ++e) {
            const uint32_t q = s.opened[k][e];
            cl.slot[st.cand[q]] = kNone;
            st.cand[q] = kNone;
            st.hole_bits[q >> 6] |= uint64_t(1) << (q & 63u);
            ++L.holes;
            ++L.free[k];
            if (k == 2) {
                link_erase(s, st.i[q], IL::make(src, true, q));
            } else {
                link_erase(s, st.i[q], IL::make(src, false, q));
                link_erase(s, st.j[q], IL::make(src, true, q));
            }
        }
    }
}

VPPDEM_HD inline void put_terms(double* t, const PairEnergy& e) {
    t[0] = e.elastic;  // kElastic, kSlip, kRelease, kViscous
    t[1] = e.slip;
    t[2] = e.release;
    t[3] = e.viscous;
}

// The ledger's block sums (lane_sums.h: LaneSums, the host backend's too) with a thread per
// (block, term) rather than per block: lane l of block b adds its entries b*64 + l + 8m in entry
// order (LaneSums::add), then the 8 lanes are added in order (LaneSums::flush): the same additions
// in the same order, so the same bits, with the 64 loads issued 8 at a time. Entries' terms lie at
// terms[e * stride + k]; entries whose terms are zero add nothing to the bits (a sum that starts
// at +0 never becomes -0), so holes may be added.
VPPDEM_HD inline double lane_job(const double* terms, int64_t stride, int64_t n, int64_t b, int k) {
    double lane[8];
    const int64_t e0 = b * kBlock;
    VPPDEM_UNROLL
    for (int l = 0; l < 8; ++l) {
        double acc = 0.0;
        VPPDEM_UNROLL
        for (int m = 0; m < 8; ++m) {
            const int64_t e = e0 + l + 8 * m;
            if (e < n) acc += terms[e * stride + k];
        }
        lane[l] = acc;
    }
    double sum = 0.0;
    VPPDEM_UNROLL
    for (int l = 0; l < 8; ++l) sum += lane[l];
    return sum;
}
// EnergyBook::account's running sum (from +0, in order) of count values a[e * stride], added or
// (subtract) taken away, the loads issued 8 at a time.
VPPDEM_HD inline double chain_sum(double acc, const double* a, int64_t count, int64_t stride, bool subtract) {
    for (int64_t c = 0; c < count; c += 8) {
        double t[8];
        VPPDEM_UNROLL
        for (int m = 0; m < 8; ++m) t[m] = c + m < count ? a[(c + m) * stride] : 0.0;
        VPPDEM_UNROLL
        for (int m = 0; m < 8; ++m)
            if (c + m < count) acc = subtract ? acc - t[m] : acc + t[m];
    }
    return acc;
}
// The wall store's sums: one running sum per block in slot order (the scalar wall kernel).
VPPDEM_HD inline double running_job(const double* terms, int64_t stride, int64_t n, int64_t b, int k) {
    const int64_t e0 = b * kBlock, e1 = e0 + kBlock < n ? e0 + kBlock : n;
    return chain_sum(0.0, terms + e0 * stride + k, e1 - e0, stride, false);
}

// Several arrays' block sums as one list of jobs (a job: one block's one term), shared by the
// block's threads, so that the arrays' sums run side by side.
struct SumArray {
    const double* terms = nullptr;
    int64_t n = 0;      // entries
    int k = 1;          // terms per entry (the stride)
    bool running = false;  // the wall store's running sums
    double* out = nullptr;  // out[b * k + term]
};
template <int A> VPPDEM_HD inline void block_sums(const SumArray (&arr)[A], int tid, int nt) {
    int64_t jobs[A + 1];
    jobs[0] = 0;
    for (int a = 0; a < A; ++a) jobs[a + 1] = jobs[a] + (arr[a].terms ? blocks(arr[a].n) * arr[a].k : 0);
    for (int64_t u = tid; u < jobs[A]; u += nt) {
        int a = 0;
        while (u >= jobs[a + 1]) ++a;
        const SumArray& r = arr[a];
        const int64_t v = u - jobs[a], b = v / r.k;
        const int k = int(v % r.k);
        r.out[b * r.k + k] = r.running ? running_job(r.terms, r.k, r.n, b, k) : lane_job(r.terms, r.k, r.n, b, k);
    }
}

// Forces at t of one system (World::step_forces' order) in five phases, each a kernel on the
// device (a system's threads may span several blocks: a phase ends where every thread of the
// system must have finished the one before) and forces_body() on the emulated device (the phases
// with barriers between them):
//   1. the touch test (its counters zeroed by the last forces' phase 5, or by the layout);
//   2. the new contacts' slots in candidate order, and their entries in the lists (one thread);
//   3. the three stores' contacts, the pressure, the bonds;
//   4. the ledger's block sums, the walls' reactions, the gather;
//   5. the prescribed particles' forces into the outbox, the slots found apart freed (after the
//      gather, as World's engine_end_forces), the counters zeroed for the next step.
// Into the outbox: the lifecycle's counts, the walls' reactions, the prescribed particles' forces
// (and with the ledger the block sums). A system whose store or list ran out of room (overflow)
// stops after phase 2: the host throws.
VPPDEM_KFN inline void forces_touch(const Globals& g, const SysView& s, int tid, int nt) {
    if (!idle(s)) touch_body(g, s, tid, nt);
}
VPPDEM_KFN inline void forces_place(const Globals& g, const SysView& s, int tid, int) {
    if (!idle(s) && tid == 0) place_found(g, s);
}
VPPDEM_KFN inline void forces_pairs(const Globals& g, const SysView& s, int tid, int nt) {
    if (idle(s) || s.out.life->overflow) return;
    const double dt = s.dt;
    const bool track = s.track != 0;
    Life& L = *s.out.life;
    const uint32_t size[3] = {L.size[0], L.size[1], L.size[2]};
    const auto pair = [&](const Store& st, int kind) {
        const bool smooth = kind == 1;
        for (int64_t q = tid; q < int64_t(size[kind]); q += nt) {
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
            if (!o.touch) s.opened[kind][vppdem_append(&L.opened[kind])] = uint32_t(q);
            if (track) {
                put_terms(t, en);
                st.fv[q] = en.fv;
            }
        }
    };
    pair(s.fric, 0);
    pair(s.smooth, 1);
    const Store& wl = s.walls;
    for (int64_t q = tid; q < int64_t(size[2]); q += nt) {
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
            s.opened[2][vppdem_append(&L.opened[2])] = uint32_t(q);
        }
        if (track) put_terms(t, en);
    }
    for (int64_t k = s.node0 + tid; k < s.node1; k += nt) {
        const int64_t* q = g.ring + 4 * k;
        g.pressure_slot[g.node[k]] = pressure_force(g.x[q[0]], g.x[q[1]], g.x[q[2]], g.x[q[3]], s.in->dp);
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
}
VPPDEM_KFN inline void forces_gather(const Globals& g, const SysView& s, int tid, int nt) {
    const Life& L = *s.out.life;
    if (idle(s) || L.overflow) return;
    const bool track = s.track != 0;
    const uint32_t size[3] = {L.size[0], L.size[1], L.size[2]};
    const Store& wl = s.walls;
    if (track) {
        const SumArray arr[4] = {{s.fric.terms, int64_t(size[0]), kPairSums, false, s.out.sum_fric},
                                 {s.smooth.terms, int64_t(size[1]), kPairSums, false, s.out.sum_smooth},
                                 {s.bterms, s.bond1 - s.bond0, 1, false, s.out.sum_bonds},
                                 {wl.terms, int64_t(size[2]), kPairSums, true, s.out.sum_walls}};
        block_sums(arr, tid, nt);
    }
    // The walls' reactions (WallState::sum_reactions: each wall's live contacts in slot order),
    // a wall per thread, the slots' owners read 8 at a time.
    for (int64_t w = tid; w < int64_t(s.walls_n); w += nt) {
        Vec3 force, torque;
        for (uint32_t q0 = 0; q0 < size[2]; q0 += 8) {
            uint32_t owner[8];
            VPPDEM_UNROLL
            for (uint32_t m = 0; m < 8; ++m) owner[m] = q0 + m < size[2] && wl.cand[q0 + m] != kNone ? wl.j[q0 + m] : kNone;
            for (uint32_t m = 0; m < 8; ++m)
                if (owner[m] == uint32_t(w)) add_wall_reaction(force, torque, wl.force[q0 + m], wl.point[q0 + m]);
        }
        s.out.reactions[w] = force;
        s.out.reactions[s.walls_n + w] = torque;
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
}
VPPDEM_KFN inline void forces_release(const Globals& g, const SysView& s, int tid, int nt) {
    Life& L = *s.out.life;
    if (idle(s) || L.overflow) return;
    for (int64_t q = s.presc0 + tid; q < s.presc1; q += nt) {
        const int64_t k = s.base + g.prescribed[q];
        s.out.presc[2 * (q - s.presc0)] = g.f[k];
        s.out.presc[2 * (q - s.presc0) + 1] = g.pressure_slot[k];
    }
    // The totals of the forces' block sums (threads 1.., or thread 0 alone), as account() forms
    // them: each pair term over the frictional, frictionless and wall blocks in turn; the bonds'.
    if (s.track && s.out.ftotals) {
        const int first = nt > 1 ? 1 : 0;
        for (int j = tid - first; j < kForceTotals; j += nt) {
            if (j < 0) continue;
            double t = 0.0;
            if (j < kPairSums) {
                t = chain_sum(t, s.out.sum_fric + j, blocks(L.size[0]), kPairSums, false);
                t = chain_sum(t, s.out.sum_smooth + j, blocks(L.size[1]), kPairSums, false);
                t = chain_sum(t, s.out.sum_walls + j, blocks(L.size[2]), kPairSums, false);
            } else {
                t = chain_sum(t, s.out.sum_bonds, blocks(s.bond1 - s.bond0), 1, false);
            }
            s.out.ftotals[j] = t;
        }
    }
    if (tid != 0) return;
    release_opened(s);
    // The next step's counters, and the largest move that the motion half forms.
    L.found[0] = L.found[1] = L.opened[0] = L.opened[1] = L.opened[2] = 0;
    *s.out.max_d2 = 0;
}
VPPDEM_KFN inline void forces_body(const Globals& g, const SysView& s, int tid, int nt) {
    forces_touch(g, s, tid, nt);
    VPPDEM_SYNC();
    forces_place(g, s, tid, nt);
    VPPDEM_SYNC();
    forces_pairs(g, s, tid, nt);
    VPPDEM_SYNC();
    forces_gather(g, s, tid, nt);
    VPPDEM_SYNC();
    forces_release(g, s, tid, nt);
}

// Motion to t + dt in three phases (four with the ledger's totals; as the forces'): 1. the free
// particles (advance_particle) and the prescribed ones (from the host), the largest squared move
// of the free ones since the rebuild (its word zeroed by the forces' phase 5); with the ledger
// 2. the dashpots' forward halves, which need the new velocities, a slot per thread, and 3. the
// block sums (the particles', the dashpots').
VPPDEM_KFN inline void motion_advance(const Globals& g, const SysView& s, int tid, int nt) {
    if (idle(s)) return;
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
    // The prescribed particles where their motions put them (World::follow_motions; the host
    // counts their moves): the ledger's dashpots read their velocities.
    for (int64_t q = s.presc0 + tid; q < s.presc1; q += nt) {
        const int64_t k = s.base + g.prescribed[q];
        g.x[k] = s.presc_in[2 * (q - s.presc0)];
        g.v[k] = s.presc_in[2 * (q - s.presc0) + 1];
    }
}
// The dashpots' forward halves with the velocities at t + dt/2 (EnergyBook::account) into the
// stores' scratch.
VPPDEM_KFN inline void motion_dashpots(const Globals& g, const SysView& s, int tid, int nt) {
    if (idle(s) || !s.track) return;
    const Life& L = *s.out.life;
    const double h = 0.5 * s.dt;
    for (int k = 0; k < 3; ++k) {
        const Store& st = store_at(s, k);
        for (int64_t q = tid; q < int64_t(L.size[k]); q += nt) {
            // Body 2 against body 1: a wall contact's particle is its body 2.
            const bool live = st.cand[q] != kNone;
            double work = 0.0;
            if (live) {
                const Vec3 vi = g.v[s.base + st.i[q]];
                const Vec3 v1 = k == 2 ? s.wall_vnext[st.j[q]] : vi;
                const Vec3 v2 = k == 2 ? vi : g.v[s.base + st.j[q]];
                work = dashpot_forward_work(true, st.fv[q], v1, v2, h);
            }
            st.dterms[q] = work;
        }
    }
}
VPPDEM_KFN inline void motion_sums(const Globals&, const SysView& s, int tid, int nt) {
    if (idle(s) || !s.track) return;
    const Life& L = *s.out.life;
    double* const d = s.out.sum_dashpots;
    const SumArray arr[4] = {{s.pterms, s.n, kParticleSums, false, s.out.sum_particles},
                             {s.fric.dterms, int64_t(L.size[0]), 1, false, d},
                             {s.smooth.dterms, int64_t(L.size[1]), 1, false, d + blocks(s.fric.cap)},
                             {s.walls.dterms, int64_t(L.size[2]), 1, false, d + blocks(s.fric.cap) + blocks(s.smooth.cap)}};
    block_sums(arr, tid, nt);
}
// 4. With the totals: account()'s sums of the motion's blocks (each particle term over the
// blocks; the dashpots' forward halves taken away in turn over the three stores' blocks, negated
// so that account(), taking the one value away from +0, gets them back).
VPPDEM_KFN inline void motion_totals(const Globals&, const SysView& s, int tid, int nt) {
    if (idle(s) || !s.track || !s.out.mtotals) return;
    const Life& L = *s.out.life;
    for (int j = tid; j < kMotionTotals; j += nt) {
        if (j < kParticleSums) {
            s.out.mtotals[j] = chain_sum(0.0, s.out.sum_particles + j, blocks(s.n), kParticleSums, false);
            continue;
        }
        const double* d = s.out.sum_dashpots;
        double v = chain_sum(0.0, d, blocks(L.size[0]), 1, true);
        d += blocks(s.fric.cap);
        v = chain_sum(v, d, blocks(L.size[1]), 1, true);
        d += blocks(s.smooth.cap);
        v = chain_sum(v, d, blocks(L.size[2]), 1, true);
        s.out.mtotals[j] = -v;
    }
}
VPPDEM_KFN inline void motion_body(const Globals& g, const SysView& s, int tid, int nt) {
    motion_advance(g, s, tid, nt);
    VPPDEM_SYNC();
    motion_dashpots(g, s, tid, nt);
    VPPDEM_SYNC();
    motion_sums(g, s, tid, nt);
    VPPDEM_SYNC();
    motion_totals(g, s, tid, nt);
}

// ---- Chunks: World's serial parts of a step on the device (one thread of the system), around
// the forces and the motion, in World::step()'s order, with World's functions.

// Before the forces at t: the system stops at its event, or where World would find the candidates
// again or lay the stores out (World::update_candidates: the host does those); otherwise the walls
// at t (WallState::move), the touch test's reaches (World::engine_reach), with the ledger the
// walls' next velocities (EnergyBook::next_wall_velocities), and the prescribed particles' places
// after the step (World::prescribed_next), their velocities before it kept for the ledger.
VPPDEM_HD inline void step_begin(const Globals& g, const SysView& s) {
    if (idle(s)) return;
    Chunk& c = *s.ck;
    if (c.steps >= c.stop_at) {
        c.stop = kEvent;
        return;
    }
    if (particles_past_skin(c.max_disp, c.skin)) {
        c.stop = kRebuild;
        return;
    }
    double move = 0.0;
    for (uint32_t k = 0; k < s.walls_n; ++k) {
        const double d = norm(motion_displacement(s.wall_ref[k].motion, c.time) - s.wall_ref_disp[k]);
        move = move < d ? d : move;  // std::max(move, d)
    }
    c.wall_move = move;
    if (walls_past_skin(c.max_disp, move, c.skin)) {
        c.stop = kRebuild;
        return;
    }
    const Life& L = *s.out.life;
    if (stores_need_compaction(L.holes, uint64_t(L.size[0]) + L.size[1] + L.size[2])) {
        c.stop = kCompaction;
        return;
    }
    const double t0 = c.time - s.dt;
    StepClock next = c.clock;  // the time the step's end moves the clock to
    double t1 = c.time;
    uint64_t n1 = c.steps;
    next.advance(t1, n1, s.dt);
    for (uint32_t k = 0; k < s.walls_n; ++k) {
        const WallRef& r = s.wall_ref[k];
        const Vec3 d = motion_displacement(r.motion, c.time);
        WallNow w;
        w.plane = r.plane != 0;
        w.one_sided = r.one_sided != 0;
        if (w.plane) {
            w.point = r.point + d;
            w.normal = r.normal;
        } else {
            w.v0 = r.v0 + d;
            w.v1 = r.v1 + d;
            w.v2 = r.v2 + d;
        }
        w.velocity = motion_mean_velocity(r.motion, t0, c.time);
        s.wall_now_w[k] = w;
        if (s.track) s.wall_vnext_w[k] = motion_mean_velocity(r.motion, t1 - s.dt, t1);
    }
    const Reaches reach = touch_reaches(c.max_disp, move, c.skin);
    s.in_w->pair_reach = reach.pair;
    s.in_w->wall_reach = reach.wall;
    for (int64_t q = s.presc0; q < s.presc1; ++q) {
        const int64_t e = q - s.presc0, k = s.base + g.prescribed[q];
        s.presc_v0[e] = g.v[k];
        const PrescRef& p = s.presc_ref[e];
        const Placement at = placement_after_step(p.motion, p.ref, c.time, s.dt);
        s.presc_in_w[2 * e] = at.pos;
        s.presc_in_w[2 * e + 1] = at.vel;
    }
}

// After the motion: the prescribed particles' moves and boundary work (World::follow_motions),
// the largest move (BroadPhase::record_moves), the clock, the ledger's booking of the step
// (EnergyBook::account from the device's totals, as the host adds them: from +0, in its order).
VPPDEM_HD inline void step_end(const Globals& g, const SysView& s) {
    if (idle(s)) return;
    Chunk& c = *s.ck;
    double max_d2 = double_of_bits(*s.out.max_d2);
    const bool track = s.track != 0;
    const double h = 0.5 * s.dt;
    double presc_max = 0.0, presc_back = 0.0, presc_fwd = 0.0;
    for (int64_t q = s.presc0; q < s.presc1; ++q) {
        const int64_t e = q - s.presc0, i = g.prescribed[q], k = s.base + i;
        const FloatVec3 r = s.ref_pos[i];
        const double d2 = norm2(g.x[k] - Vec3{r.x, r.y, r.z});
        presc_max = presc_max < d2 ? d2 : presc_max;
        if (track) ledger::add_boundary_work(presc_back, presc_fwd, g.f[k] - g.pressure_slot[k], s.presc_v0[e], g.v[k], h);
        s.out.pstate[2 * e] = g.x[k];
        s.out.pstate[2 * e + 1] = g.v[k];
    }
    max_d2 = max_d2 < presc_max ? presc_max : max_d2;
    const double t_n = c.time;
    // The caller's window: the forces at t_n (the walls' reactions, the gather's forces).
    probe_step(c.probe, t_n, c.probe.wall < s.walls_n ? s.out.reactions + c.probe.wall : nullptr, g.f, s.probe_particles,
               s.probe_n, s.base);
    c.max_disp = max_disp_after(max_d2, c.ref_round);
    c.clock.advance(c.time, c.steps, s.dt);
    if (!track) return;
    using namespace ledger;
    const double* mt = s.out.mtotals;
    const double* ft = s.out.ftotals;
    double back[kTerms], fwd[kTerms], cs[kPairSums];
    for (int k = 0; k < kTerms; ++k) {
        back[k] = 0.0 + mt[k];
        fwd[k] = 0.0 + mt[kTerms + k];
    }
    const double kinetic = 0.0 + mt[2 * kTerms];
    back[kBoundary] += presc_back;
    fwd[kBoundary] += presc_fwd;
    for (uint32_t w = 0; w < s.walls_n; ++w)
        add_boundary_work(back[kBoundary], fwd[kBoundary], s.out.reactions[w], s.wall_now[w].velocity, s.wall_vnext[w], h);
    for (int k = 0; k < kPairSums; ++k) cs[k] = 0.0 + ft[k];
    const double elastic_bonds = 0.0 + ft[kPairSums];
    const double visc_fwd = c.dashpots ? 0.0 - mt[kParticleSums] : 0.0;
    const double release = cs[kRelease] + c.dropped;
    c.dropped = 0.0;
    book_step(c.ledger, back, fwd, cs, elastic_bonds, visc_fwd, release, kinetic, t_n);
}

// Up to K steps of one system (the emulated device's chunk: its threads meet at the barriers).
VPPDEM_KFN inline void chunk_body(const Globals& g, const SysView& s, int tid, int nt, int K) {
    for (int k = 0; k < K; ++k) {
        if (tid == 0) step_begin(g, s);
        VPPDEM_SYNC();
        if (idle(s)) return;  // every thread reads the stop after the barrier
        forces_body(g, s, tid, nt);
        VPPDEM_SYNC();
        motion_body(g, s, tid, nt);
        VPPDEM_SYNC();
        if (tid == 0) step_end(g, s);
        VPPDEM_SYNC();
    }
}

}  // namespace dem::batch::dev
