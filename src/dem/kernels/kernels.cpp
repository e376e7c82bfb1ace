// SIMD kernels of the step (dem/kernels/kernels.h). Compiled once per Highway target through
// foreach_target.h; the physics comes from the lane templates of the bodies
// (dem/kernels/step_bodies-inl.h, the batch engine's too) and of the laws they call
// (dem/contact/linear_law.h, dem/bonds/bond_law.h), so this file only loads, stores and masks.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "dem/kernels/kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "dem/kernels/kernels.h"

// Lane functions of dem/core/lanes.h for Highway vectors. They live in Highway's namespace
// because the law templates find them by argument-dependent lookup.
HWY_BEFORE_NAMESPACE();
namespace hwy {
namespace HWY_NAMESPACE {

template <class V> HWY_INLINE V lit(V, double v) { return Set(DFromV<V>(), v); }
template <class V> HWY_INLINE V neg(V a) { return Neg(a); }
template <class V> HWY_INLINE V lane_sqrt(V a) { return Sqrt(a); }
template <class M, class V> HWY_INLINE V select(M m, V a, V b) { return IfThenElse(m, a, b); }
template <class M> HWY_INLINE M both(M a, M b) { return And(a, b); }

}  // namespace HWY_NAMESPACE
}  // namespace hwy
HWY_AFTER_NAMESPACE();

HWY_BEFORE_NAMESPACE();
namespace dem {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using kernels::kBlock;

// The laws, compiled for this target.
#include "dem/core/lanes-inl.h"
#include "dem/core/shear_spring-inl.h"
#include "dem/contact/linear_law-inl.h"
#include "dem/bonds/bond_law-inl.h"
#include "dem/kernels/step_bodies-inl.h"

template <class D> using VecD = hn::Vec<D>;
template <class D> using V3D = V3<VecD<D>>;

// Particle indices as 64-bit lane indices (particle counts stay below 2^31).
template <class D> HWY_INLINE auto load_index(D, const uint32_t* p) {
    const hn::Rebind<int32_t, D> d32;
    const hn::RebindToSigned<D> di;
    return hn::PromoteTo(di, hn::LoadU(d32, reinterpret_cast<const int32_t*>(p)));
}
template <class VI> HWY_INLINE VI times3(VI i) { return i + i + i; }
template <class D, class VI> HWY_INLINE V3D<D> gather3(D d, const Vec3* base, VI idx3) {
    const double* b = &base[0].x;
    return {hn::GatherIndex(d, b, idx3), hn::GatherIndex(d, b + 1, idx3), hn::GatherIndex(d, b + 2, idx3)};
}
template <class D> HWY_INLINE V3D<D> load3(D d, const Vec3* p) {
    V3D<D> v;
    hn::LoadInterleaved3(d, &p->x, v.x, v.y, v.z);
    return v;
}
template <class D> HWY_INLINE void store3(D d, const V3D<D>& v, Vec3* p) {
    hn::StoreInterleaved3(v.x, v.y, v.z, d, &p->x);
}
template <class D> HWY_INLINE V3D<D> zero3(D d) { return {hn::Zero(d), hn::Zero(d), hn::Zero(d)}; }

// Runs body(d, first_entry, terms) over the entries of blocks [b0, b1) of an n-entry list,
// full vectors first and the last few entries of a short final block one lane at a time, and
// sums each of the K energy terms per block in 8 virtual lanes (see kernels.h) into
// energy[block * K + k]. With energy == nullptr the terms are ignored.
template <int K, class D, class Body>
HWY_INLINE void for_blocks(D d, int64_t n, int64_t b0, int64_t b1, double* energy, Body&& body) {
    constexpr int64_t N = int64_t(hn::MaxLanes(D()));
    static_assert(8 % N == 0, "a vector holds 1, 2, 4 or 8 doubles");
    constexpr int64_t G = 8 / N;  // vectors per group of 8 virtual lanes
    const hn::CappedTag<double, 1> d1;
    for (int64_t b = b0; b < b1; ++b) {
        const int64_t e0 = b * kBlock, e1 = std::min(n, e0 + kBlock);
        const int64_t full_end = e0 + (e1 - e0) / N * N;
        std::array<VecD<D>, std::size_t(K * G)> acc;
        for (auto& a : acc) a = hn::Zero(d);
        std::array<VecD<D>, std::size_t(K)> t;
        int64_t g = 0;
        for (int64_t s = e0; s < full_end; s += N) {
            body(d, s, t.data());
            if (energy)
                for (int k = 0; k < K; ++k) acc[k * G + g] = acc[k * G + g] + t[k];
            g = g + 1 == G ? 0 : g + 1;
        }
        std::array<VecD<decltype(d1)>, std::size_t(K)> t1;
        alignas(64) double lanes[K > 0 ? K : 1][8] = {};
        if (energy)
            for (int k = 0; k < K; ++k)
                for (int64_t q = 0; q < G; ++q) hn::StoreU(acc[k * G + q], d, &lanes[k][q * N]);
        for (int64_t s = full_end; s < e1; ++s) {
            body(d1, s, t1.data());
            if (energy)
                for (int k = 0; k < K; ++k) lanes[k][s % 8] += hn::GetLane(t1[k]);
        }
        if (energy)
            for (int k = 0; k < K; ++k) {
                double sum = 0.0;
                for (int l = 0; l < 8; ++l) sum += lanes[k][l];
                energy[b * K + k] = sum;
            }
    }
}

// Appends the entries s + l whose lane l is set in m.
template <class D, class M> HWY_INLINE void append_lanes(D d, M m, int64_t s, std::vector<uint32_t>* out) {
    if (hn::AllFalse(d, m)) return;
    uint8_t bits[8] = {};
    hn::StoreMaskBits(d, m, bits);
    for (std::size_t l = 0; l < hn::Lanes(d); ++l)
        if (bits[l / 8] & (1u << (l % 8))) out->push_back(uint32_t(s + int64_t(l)));
}

// In-register transpose of N rows of 8 doubles (N = lanes): on return v[k] lane l holds what
// row l held at column k, for k < 8 (rows given as the first 8/N... see load/store below).
// Only data moves, so every target gives the same values.
#if HWY_TARGET <= HWY_AVX3
HWY_INLINE void transpose8x8(__m512d (&r)[8]) {
    __m512d t[8], u[8];
    for (int l = 0; l < 4; ++l) {
        t[2 * l] = _mm512_unpacklo_pd(r[2 * l], r[2 * l + 1]);      // a0 b0 a2 b2 a4 b4 a6 b6
        t[2 * l + 1] = _mm512_unpackhi_pd(r[2 * l], r[2 * l + 1]);  // a1 b1 a3 b3 a5 b5 a7 b7
    }
    for (int h = 0; h < 2; ++h)      // rows 0-3, rows 4-7
        for (int o = 0; o < 2; ++o) {  // even, odd columns
            const __m512d lo = t[4 * h + o], hi = t[4 * h + 2 + o];
            u[4 * h + o] = _mm512_shuffle_f64x2(lo, hi, 0x88);      // columns o, o+4 of the 4 rows
            u[4 * h + 2 + o] = _mm512_shuffle_f64x2(lo, hi, 0xdd);  // columns o+2, o+6
        }
    for (int f = 0; f < 4; ++f) {  // u[f]: columns f, f+4 of rows 0-3; u[4+f]: the same of rows 4-7
        r[f] = _mm512_shuffle_f64x2(u[f], u[4 + f], 0x88);
        r[f + 4] = _mm512_shuffle_f64x2(u[f], u[4 + f], 0xdd);
    }
}
#endif

// Rows: `row(l)` is the address of row l's 8 doubles (64-byte aligned). Fields -> lanes.
template <class D, class Row> HWY_INLINE void rows_to_lanes(D d, Row&& row, VecD<D> (&out)[8]) {
    constexpr std::size_t N = hn::MaxLanes(D());
    if constexpr (N == 1) {
        for (int k = 0; k < 8; ++k) out[k] = hn::LoadU(d, row(0) + k);
    }
#if HWY_TARGET != HWY_SCALAR
    else if constexpr (N == 2) {
        const double *a = row(0), *b = row(1);
        for (int c = 0; c < 4; ++c) {
            const VecD<D> ra = hn::LoadU(d, a + 2 * c), rb = hn::LoadU(d, b + 2 * c);
            out[2 * c] = hn::InterleaveLower(d, ra, rb);
            out[2 * c + 1] = hn::InterleaveUpper(d, ra, rb);
        }
    } else if constexpr (N == 4) {
        for (int h = 0; h < 2; ++h) {
            const VecD<D> r0 = hn::LoadU(d, row(0) + 4 * h), r1 = hn::LoadU(d, row(1) + 4 * h);
            const VecD<D> r2 = hn::LoadU(d, row(2) + 4 * h), r3 = hn::LoadU(d, row(3) + 4 * h);
            const VecD<D> t0 = hn::InterleaveLower(d, r0, r1), t1 = hn::InterleaveUpper(d, r0, r1);
            const VecD<D> t2 = hn::InterleaveLower(d, r2, r3), t3 = hn::InterleaveUpper(d, r2, r3);
            out[4 * h] = hn::ConcatLowerLower(d, t2, t0);
            out[4 * h + 1] = hn::ConcatLowerLower(d, t3, t1);
            out[4 * h + 2] = hn::ConcatUpperUpper(d, t2, t0);
            out[4 * h + 3] = hn::ConcatUpperUpper(d, t3, t1);
        }
    }
#endif
    else {
#if HWY_TARGET <= HWY_AVX3
        static_assert(N == 8);
        __m512d r[8];
        for (int l = 0; l < 8; ++l) r[l] = _mm512_load_pd(row(l));
        transpose8x8(r);
        for (int k = 0; k < 8; ++k) out[k].raw = r[k];
#endif
    }
}

// The inverse: lanes -> fields of N consecutive 64-byte aligned rows starting at `rows`.
template <class D> HWY_INLINE void lanes_to_rows(D d, const VecD<D> (&in)[8], double* rows) {
    constexpr std::size_t N = hn::MaxLanes(D());
    if constexpr (N == 1) {
        for (int k = 0; k < 8; ++k) hn::StoreU(in[k], d, rows + k);
    }
#if HWY_TARGET != HWY_SCALAR
    else if constexpr (N == 2) {
        for (int c = 0; c < 4; ++c) {
            hn::StoreU(hn::InterleaveLower(d, in[2 * c], in[2 * c + 1]), d, rows + 2 * c);
            hn::StoreU(hn::InterleaveUpper(d, in[2 * c], in[2 * c + 1]), d, rows + 8 + 2 * c);
        }
    } else if constexpr (N == 4) {
        for (int h = 0; h < 2; ++h) {
            const VecD<D> t0 = hn::InterleaveLower(d, in[4 * h], in[4 * h + 1]);
            const VecD<D> t1 = hn::InterleaveUpper(d, in[4 * h], in[4 * h + 1]);
            const VecD<D> t2 = hn::InterleaveLower(d, in[4 * h + 2], in[4 * h + 3]);
            const VecD<D> t3 = hn::InterleaveUpper(d, in[4 * h + 2], in[4 * h + 3]);
            hn::StoreU(hn::ConcatLowerLower(d, t2, t0), d, rows + 4 * h);
            hn::StoreU(hn::ConcatLowerLower(d, t3, t1), d, rows + 8 + 4 * h);
            hn::StoreU(hn::ConcatUpperUpper(d, t2, t0), d, rows + 16 + 4 * h);
            hn::StoreU(hn::ConcatUpperUpper(d, t3, t1), d, rows + 24 + 4 * h);
        }
    }
#endif
    else {
#if HWY_TARGET <= HWY_AVX3
        static_assert(N == 8);
        __m512d r[8];
        for (int k = 0; k < 8; ++k) r[k] = in[k].raw;
        transpose8x8(r);
        for (int l = 0; l < 8; ++l) _mm512_store_pd(rows + 8 * l, r[l]);
#endif
    }
}

// The 8 doubles of the packed records of the particles idx[0..N), as lanes: out[k] holds
// field k (x y z r vx vy vz unused) of every lane's particle.
template <class D>
HWY_INLINE void load_packed(D d, const kernels::PackedParticle* P, const uint32_t* idx, VecD<D> (&out)[8]) {
    rows_to_lanes(d, [&](int l) { return &P[idx[l]].x; }, out);
}

// The bodies and velocities of a particle pair, gathered.
template <class D> using PairState = PairLanes<VecD<D>>;
template <class D>
HWY_INLINE PairState<D> gather_pair(D d, const Particles& p, const kernels::PackedParticle* packed, const uint32_t* i,
                                    const uint32_t* j) {
    VecD<D> a[8], b[8];
    load_packed(d, packed, i, a);
    load_packed(d, packed, j, b);
    PairState<D> q;
    q.xi = {a[0], a[1], a[2]};
    q.ri = a[3];
    q.vi = {a[4], a[5], a[6]};
    q.xj = {b[0], b[1], b[2]};
    q.rj = b[3];
    q.vj = {b[4], b[5], b[6]};
    q.wi = gather3(d, p.angvel.data(), times3(load_index(d, i)));
    q.wj = gather3(d, p.angvel.data(), times3(load_index(d, j)));
    return q;
}
// A slot holds a live contact unless it is a hole (cand = kNoSlot, -1 as int32).
template <class D> HWY_INLINE auto live_mask(D d, const uint32_t* cand) {
    const hn::RebindToSigned<D> di;
    return hn::RebindMask(d, hn::Ne(load_index(d, cand), hn::Set(di, -1)));
}

// The pair kernels: loads, the body of dem/kernels/step_bodies-inl.h (the batch engine's too), stores.
template <bool kEnergy, class D>
HWY_INLINE void store_pair_terms(D d, const PairLanesOut<VecD<D>>& o, VecD<D>* terms, Vec3* fv) {
    if constexpr (kEnergy) {
        terms[kernels::kElastic] = o.elastic;
        terms[kernels::kSlip] = o.slip;
        terms[kernels::kRelease] = o.release;
        terms[kernels::kViscous] = o.viscous;
        store3(d, o.fv, fv);
    }
}

template <bool kEnergy, class D>
HWY_INLINE void frictional_body(D d, const kernels::PairArgs& a, int64_t s, VecD<D>* terms) {
    ActiveContacts& c = *a.c;
    const PairState<D> q = gather_pair(d, *a.p, a.packed, &c.i[s], &c.j[s]);
    const auto live = live_mask(d, &c.cand[s]);
    VecD<D> kn, ks, mu, cn;
    hn::LoadInterleaved4(d, &c.phys[s].kn, kn, ks, mu, cn);
    V3D<D> fs = load3(d, &c.shear[s]), prev = load3(d, &c.prev_normal[s]);
    PairLanesOut<VecD<D>> o;
    const auto touch = frictional_pair_lanes<kEnergy>(q, live, kn, ks, mu, cn, hn::Set(d, a.dt), fs, prev, o);
    store3(d, o.force, &c.force[s]);
    store3(d, o.torque1, &c.torque1[s]);
    store3(d, o.torque2, &c.torque2[s]);
    store3(d, fs, &c.shear[s]);
    store3(d, prev, &c.prev_normal[s]);
    store_pair_terms<kEnergy>(d, o, terms, &c.fv[s]);
    append_lanes(d, hn::AndNot(touch, live), s, a.opened);
}

template <bool kEnergy, class D>
HWY_INLINE void smooth_body(D d, const kernels::PairArgs& a, int64_t s, VecD<D>* terms) {
    ActiveContacts& c = *a.c;
    VecD<D> pi[8], pj[8];
    load_packed(d, a.packed, &c.i[s], pi);
    load_packed(d, a.packed, &c.j[s], pj);
    PairState<D> q;  // no angular velocities: a frictionless pair has no lever arm
    q.wi = q.wj = zero3(d);
    q.xi = {pi[0], pi[1], pi[2]};
    q.ri = pi[3];
    q.vi = {pi[4], pi[5], pi[6]};
    q.xj = {pj[0], pj[1], pj[2]};
    q.rj = pj[3];
    q.vj = {pj[4], pj[5], pj[6]};
    const auto live = live_mask(d, &c.cand[s]);
    VecD<D> kn, ks, mu, cn;
    hn::LoadInterleaved4(d, &c.phys[s].kn, kn, ks, mu, cn);
    PairLanesOut<VecD<D>> o;
    const auto touch = smooth_pair_lanes<kEnergy>(q, live, kn, cn, hn::Set(d, a.dt), o);
    store3(d, o.force, &c.force[s]);
    store_pair_terms<kEnergy>(d, o, terms, &c.fv[s]);
    append_lanes(d, hn::AndNot(touch, live), s, a.opened);
}

template <bool kEnergy, class D>
HWY_INLINE void bond_body(D d, const kernels::BondArgs& a, int64_t s, VecD<D>* terms) {
    BondList& b = *a.b;
    const PairState<D> q = gather_pair(d, *a.p, a.packed, &b.i[s], &b.j[s]);
    const BondGeometryLanes<VecD<D>> geo = bond_geometry_lanes(q, b.arm == BondArm::kBondPoint);
    VecD<D> kn, ks, l0;
    hn::LoadInterleaved3(d, &b.phys[s].kn, kn, ks, l0);
    V3D<D> fs = load3(d, &b.shear[s]), prev = load3(d, &b.prev_normal[s]);
    V3D<D> f, t1, t2;
    bond_step_lanes<kEnergy>(q, geo, kn, ks, l0, hn::Set(d, a.dt), fs, prev, f, t1, t2, terms);
    store3(d, f, &b.force[s]);
    store3(d, t1, &b.torque1[s]);
    store3(d, t2, &b.torque2[s]);
    store3(d, fs, &b.shear[s]);
    store3(d, prev, &b.prev_normal[s]);
}

template <bool kEnergy, class D>
HWY_INLINE void advance_body(D d, const kernels::AdvanceArgs& a, int64_t s, VecD<D>* terms, VecD<D>& max_d2) {
    Particles& p = *a.p;
    const VecD<D> zero = hn::Zero(d);
    AdvanceLanes<VecD<D>> st;
    st.m = hn::LoadU(d, &p.mass[s]);
    st.inv_m = hn::LoadU(d, &p.inv_mass[s]);
    st.inv_i = hn::LoadU(d, &p.inv_inertia[s]);
    const auto free = st.inv_m > zero;
    st.x = load3(d, &p.pos[s]);
    st.v = load3(d, &p.vel[s]);
    st.w = load3(d, &p.angvel[s]);
    st.f = load3(d, &p.force[s]);
    st.t = load3(d, &p.torque[s]);
    st.fx = a.ext_force ? load3(d, &a.ext_force[s]) : zero3(d);
    const V3D<D> g{hn::Set(d, a.gravity.x), hn::Set(d, a.gravity.y), hn::Set(d, a.gravity.z)};
    const VecD<D> dt = hn::Set(d, a.dt), lambda = hn::Set(d, a.lambda);
    const AdvanceStepLanes<VecD<D>> step = advance_lanes(free, st, g, dt, lambda);
    store3(d, st.v, &p.vel[s]);
    store3(d, st.x, &p.pos[s]);
    store3(d, st.w, &p.angvel[s]);
    if (a.packed) {  // the pair kernels' copy for the next step
        const VecD<D> rows[8] = {st.x.x, st.x.y, st.x.z, hn::LoadU(d, &p.radius[s]), st.v.x, st.v.y, st.v.z, zero};
        lanes_to_rows(d, rows, &a.packed[s].x);
    }
    const hn::Rebind<float, D> df;
    hn::Vec<decltype(df)> rx, ry, rz;
    hn::LoadInterleaved3(df, &a.ref_pos[s].x, rx, ry, rz);
    const V3D<D> moved = st.x - V3D<D>{hn::PromoteTo(d, rx), hn::PromoteTo(d, ry), hn::PromoteTo(d, rz)};
    max_d2 = hn::Max(max_d2, hn::IfThenElseZero(free, norm2(moved)));
    if constexpr (kEnergy) {
        static_assert(kernels::kTerms == 5 && kernels::kParticleSums == 11 && kernels::kGravity == 2 &&
                      kernels::kPressure == 1 && kernels::kExternal == 3 && kernels::kDamping == 4);
        const V3D<D> fp = a.pressure ? load3(d, &a.pressure[s]) : zero3(d);
        advance_terms_lanes(free, st, step, dt, a.lambda != 0.0, fp, hn::LoadU(d, &p.radius[s]), terms);
    }
}

template <bool kEnergy>
void FrictionalPairsT(const kernels::PairArgs& a) {
    const hn::ScalableTag<double> d;
    for_blocks<kEnergy ? kernels::kPairSums : 0>(
        d, int64_t(a.c->size()), a.block_begin, a.block_end, a.energy,
        [&](auto dd, int64_t s, auto* t) { frictional_body<kEnergy>(dd, a, s, t); });
}
template <bool kEnergy>
void SmoothPairsT(const kernels::PairArgs& a) {
    const hn::ScalableTag<double> d;
    for_blocks<kEnergy ? kernels::kPairSums : 0>(
        d, int64_t(a.c->size()), a.block_begin, a.block_end, a.energy,
        [&](auto dd, int64_t s, auto* t) { smooth_body<kEnergy>(dd, a, s, t); });
}
template <bool kEnergy>
void BondsT(const kernels::BondArgs& a) {
    const hn::ScalableTag<double> d;
    for_blocks<kEnergy ? 1 : 0>(d, int64_t(a.b->size()), a.block_begin, a.block_end, a.energy,
                                [&](auto dd, int64_t s, auto* t) { bond_body<kEnergy>(dd, a, s, t); });
}
template <bool kEnergy>
double AdvanceT(const kernels::AdvanceArgs& a) {
    const hn::ScalableTag<double> d;
    const hn::CappedTag<double, 1> d1;
    auto max_v = hn::Zero(d);
    auto max_1 = hn::Zero(d1);
    for_blocks<kEnergy ? kernels::kParticleSums : 0>(
        d, int64_t(a.p->size()), a.block_begin, a.block_end, a.energy,
        [&](auto dd, int64_t s, auto* t) __attribute__((always_inline)) {
            if constexpr (hn::MaxLanes(decltype(dd)()) == 1 && hn::MaxLanes(decltype(d)()) != 1)
                advance_body<kEnergy>(dd, a, s, t, max_1);
            else
                advance_body<kEnergy>(dd, a, s, t, max_v);
        });
    return std::max(hn::GetLane(hn::MaxOfLanes(d, max_v)), hn::GetLane(max_1));
}

void FilterOpenCandidates(const uint32_t* slot, const float* gap, float reach, int64_t k0, int64_t k1,
                          std::vector<uint32_t>& out) {
    const hn::ScalableTag<uint32_t> du;
    const hn::RebindToFloat<decltype(du)> df;
    const int64_t N = int64_t(hn::Lanes(du));
    const std::size_t old = out.size();
    out.resize(old + std::size_t(k1 - k0) + std::size_t(N));  // CompressStore may write a whole vector
    uint32_t* dst = out.data() + old;
    std::size_t cnt = 0;
    const auto none = hn::Set(du, kNoSlot);
    const auto limit = hn::Set(df, reach);
    const auto iota = hn::Iota(du, 0);
    int64_t k = k0;
    for (; k + N <= k1; k += N) {
        const auto m = hn::And(hn::RebindMask(du, hn::Lt(hn::LoadU(df, gap + k), limit)),
                               hn::Eq(hn::LoadU(du, slot + k), none));
        cnt += hn::CompressStore(hn::Add(iota, hn::Set(du, uint32_t(k))), m, du, dst + cnt);
    }
    for (; k < k1; ++k)
        if (open_candidate(slot[k], gap[k], reach)) dst[cnt++] = uint32_t(k);
    out.resize(old + cnt);
}

void TouchingPairs(const kernels::PackedParticle* P, const uint32_t* I, const uint32_t* J, std::size_t m,
                   std::vector<uint32_t>& hits) {
    const hn::ScalableTag<double> d;
    const std::size_t N = hn::Lanes(d);
    const auto test = [&](auto dd, std::size_t q) {
        VecD<decltype(dd)> a[8], b[8];
        load_packed(dd, P, I + q, a);
        load_packed(dd, P, J + q, b);
        using R = VecD<decltype(dd)>;
        const auto touch = spheres_touch_lanes(V3<R>{a[0], a[1], a[2]}, a[3], V3<R>{b[0], b[1], b[2]}, b[3]);
        if (hn::AllFalse(dd, touch)) return;
        uint8_t bits[8] = {};
        hn::StoreMaskBits(dd, touch, bits);
        for (std::size_t l = 0; l < hn::Lanes(dd); ++l)
            if (bits[l / 8] & (1u << (l % 8))) hits.push_back(uint32_t(q + l));
    };
    std::size_t q = 0;
    for (; q + N <= m; q += N) test(d, q);
    for (; q < m; ++q) test(hn::CappedTag<double, 1>(), q);
}

void PackParticles(const Particles& p, int64_t i0, int64_t i1, kernels::PackedParticle* out) {
    for (int64_t i = i0; i < i1; ++i) out[i] = kernels::pack(p, i);
}

void FrictionalPairs(const kernels::PairArgs& a) { a.energy ? FrictionalPairsT<true>(a) : FrictionalPairsT<false>(a); }
void SmoothPairs(const kernels::PairArgs& a) { a.energy ? SmoothPairsT<true>(a) : SmoothPairsT<false>(a); }
void Bonds(const kernels::BondArgs& a) { a.energy ? BondsT<true>(a) : BondsT<false>(a); }
double Advance(const kernels::AdvanceArgs& a) { return a.energy ? AdvanceT<true>(a) : AdvanceT<false>(a); }

}  // namespace HWY_NAMESPACE
}  // namespace dem
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace dem {
HWY_EXPORT(FrictionalPairs);
HWY_EXPORT(SmoothPairs);
HWY_EXPORT(Bonds);
HWY_EXPORT(Advance);
HWY_EXPORT(FilterOpenCandidates);
HWY_EXPORT(PackParticles);
HWY_EXPORT(TouchingPairs);

namespace kernels {

void frictional_pairs(const PairArgs& a) { HWY_DYNAMIC_DISPATCH(FrictionalPairs)(a); }
void smooth_pairs(const PairArgs& a) { HWY_DYNAMIC_DISPATCH(SmoothPairs)(a); }
void bonds(const BondArgs& a) { HWY_DYNAMIC_DISPATCH(Bonds)(a); }
double advance(const AdvanceArgs& a) { return HWY_DYNAMIC_DISPATCH(Advance)(a); }
void filter_open_candidates(const uint32_t* slot, const float* gap, float reach, int64_t k0, int64_t k1,
                            std::vector<uint32_t>& out) {
    HWY_DYNAMIC_DISPATCH(FilterOpenCandidates)(slot, gap, reach, k0, k1, out);
}
void touching_pairs(const PackedParticle* packed, const uint32_t* i, const uint32_t* j, std::size_t m,
                    std::vector<uint32_t>& hits) {
    HWY_DYNAMIC_DISPATCH(TouchingPairs)(packed, i, j, m, hits);
}
void pack_particles(const Particles& p, int64_t i0, int64_t i1, PackedParticle* out) {
    HWY_DYNAMIC_DISPATCH(PackParticles)(p, i0, i1, out);
}

std::vector<int64_t> available_targets() { return hwy::SupportedAndGeneratedTargets(); }
std::string target_name(int64_t target) { return hwy::TargetName(target); }
void restrict_to_target(int64_t target) { hwy::SetSupportedTargetsForTest(target); }

}  // namespace kernels
}  // namespace dem
#endif  // HWY_ONCE
