// SIMD kernels of the step (dem/core/kernels.h). Compiled once per Highway target through
// foreach_target.h; the physics comes from the lane templates of the laws
// (dem/contact/linear_law.h, dem/bonds/bond_law.h), so this file only loads, stores and masks.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "dem/core/kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "dem/core/kernels.h"

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
#include "dem/contact/linear_law-inl.h"
#include "dem/bonds/bond_law-inl.h"

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

// The bodies and velocities of a particle pair, gathered.
template <class D> struct PairState {
    V3D<D> xi, xj, vi, vj, wi, wj;
    VecD<D> ri, rj;
};
template <class D> HWY_INLINE PairState<D> gather_pair(D d, const Particles& p, const uint32_t* i, const uint32_t* j) {
    const auto I = load_index(d, i), J = load_index(d, j);
    const auto I3 = times3(I), J3 = times3(J);
    PairState<D> q;
    q.xi = gather3(d, p.pos.data(), I3);
    q.xj = gather3(d, p.pos.data(), J3);
    q.vi = gather3(d, p.vel.data(), I3);
    q.vj = gather3(d, p.vel.data(), J3);
    q.wi = gather3(d, p.angvel.data(), I3);
    q.wj = gather3(d, p.angvel.data(), J3);
    q.ri = hn::GatherIndex(d, p.radius.data(), I);
    q.rj = hn::GatherIndex(d, p.radius.data(), J);
    return q;
}
// Velocity of body 2 relative to body 1 at the contact, lever arms at the full radii along n
// (Yade's avoidGranularRatcheting).
template <class D> HWY_INLINE V3D<D> relative_velocity(const PairState<D>& q, const V3D<D>& n) {
    return (q.vj + cross(q.wj, n * neg(q.rj))) - (q.vi + cross(q.wi, n * q.ri));
}
// A slot holds a live contact unless it is a hole (cand = kNoSlot, -1 as int32).
template <class D> HWY_INLINE auto live_mask(D d, const uint32_t* cand) {
    const hn::RebindToSigned<D> di;
    return hn::RebindMask(d, hn::Ne(load_index(d, cand), hn::Set(di, -1)));
}

template <bool kEnergy, class D>
HWY_INLINE void frictional_body(D d, const kernels::PairArgs& a, int64_t s, VecD<D>* terms) {
    ActiveContacts& c = *a.c;
    const PairState<D> q = gather_pair(d, *a.p, &c.i[s], &c.j[s]);
    const auto live = live_mask(d, &c.cand[s]);
    const VecD<D> zero = hn::Zero(d), dt = hn::Set(d, a.dt), half = hn::Set(d, 0.5);
    // Sphere-sphere geometry (dem/detect/geometry.h, sphere_sphere).
    const V3D<D> dx = q.xj - q.xi;
    const VecD<D> d2 = norm2(dx), rs = q.ri + q.rj;
    const auto touch = hn::And(live, d2 < rs * rs);
    const VecD<D> dist = hn::Sqrt(d2);
    const VecD<D> inv = hn::Set(d, 1.0) / dist;
    const V3D<D> n = select(dist > zero, dx * inv, V3D<D>{zero, zero, hn::Set(d, 1.0)});
    const VecD<D> overlap = rs - dist;
    const VecD<D> arm1 = q.ri - half * overlap, arm2 = q.rj - half * overlap;

    VecD<D> kn, ks, mu, cn;
    hn::LoadInterleaved4(d, &c.phys[s].kn, kn, ks, mu, cn);
    const V3D<D> fs0 = load3(d, &c.shear[s]), prev0 = load3(d, &c.prev_normal[s]);
    V3D<D> fs = fs0, prev = prev0;
    const V3D<D> vrel = relative_velocity(q, n);
    const VecD<D> spin_n = half * dot(n, q.wi + q.wj);
    ContactEnergyLanes<VecD<D>> e;
    const V3D<D> f = linear_contact_force_lanes<kEnergy>(kn, ks, mu, cn, n, overlap, vrel, spin_n, dt, fs, prev, &e);
    const V3D<D> nxf = cross(n, neg(f));
    const V3D<D> z3 = zero3(d);
    // A pair found apart forgets its shear spring (Yade deletes the interaction).
    store3(d, select(touch, f, z3), &c.force[s]);
    store3(d, select(touch, nxf * arm1, z3), &c.torque1[s]);
    store3(d, select(touch, nxf * arm2, z3), &c.torque2[s]);
    store3(d, select(touch, fs, z3), &c.shear[s]);
    store3(d, select(touch, prev, z3), &c.prev_normal[s]);
    const auto opened = hn::AndNot(touch, live);
    if constexpr (kEnergy) {
        // Opened this step: the loaded spring is lost (shear_release_energy), with the last
        // normal as lever-arm direction.
        const V3D<D> vr0 = relative_velocity(q, prev0);
        const VecD<D> release = norm2(fs0) / (hn::Set(d, 2.0) * ks) - half * dot(fs0, vr0) * dt;
        terms[kernels::kElastic] = select(touch, e.elastic, zero);
        terms[kernels::kSlip] = select(touch, e.slip, zero);
        terms[kernels::kRelease] = select(both(opened, ks > zero), release, zero);
        terms[kernels::kViscous] = select(touch, e.viscous, zero);
        store3(d, select(touch, e.fv, z3), &c.fv[s]);
    }
    append_lanes(d, opened, s, a.opened);
}

template <bool kEnergy, class D>
HWY_INLINE void smooth_body(D d, const kernels::PairArgs& a, int64_t s, VecD<D>* terms) {
    ActiveContacts& c = *a.c;
    const auto I = load_index(d, &c.i[s]), J = load_index(d, &c.j[s]);
    const auto I3 = times3(I), J3 = times3(J);
    const Particles& p = *a.p;
    const V3D<D> xi = gather3(d, p.pos.data(), I3), xj = gather3(d, p.pos.data(), J3);
    const VecD<D> ri = hn::GatherIndex(d, p.radius.data(), I), rj = hn::GatherIndex(d, p.radius.data(), J);
    const auto live = live_mask(d, &c.cand[s]);
    const VecD<D> zero = hn::Zero(d), dt = hn::Set(d, a.dt);
    const V3D<D> dx = xj - xi;
    const VecD<D> d2 = norm2(dx), rs = ri + rj;
    const auto touch = hn::And(live, d2 < rs * rs);
    const VecD<D> dist = hn::Sqrt(d2);
    const VecD<D> inv = hn::Set(d, 1.0) / dist;
    const V3D<D> n = select(dist > zero, dx * inv, V3D<D>{zero, zero, hn::Set(d, 1.0)});
    const VecD<D> overlap = rs - dist;
    VecD<D> kn, ks, mu, cn;
    hn::LoadInterleaved4(d, &c.phys[s].kn, kn, ks, mu, cn);
    // Only the normal relative velocity matters here: without shear there is no lever arm.
    const V3D<D> vrel = gather3(d, p.vel.data(), J3) - gather3(d, p.vel.data(), I3);
    ContactEnergyLanes<VecD<D>> e;
    const V3D<D> f = normal_contact_force_lanes<kEnergy>(kn, cn, n, overlap, vrel, dt, &e);
    const V3D<D> z3 = zero3(d);
    store3(d, select(touch, f, z3), &c.force[s]);
    if constexpr (kEnergy) {
        terms[kernels::kElastic] = select(touch, e.elastic, zero);
        terms[kernels::kSlip] = zero;
        terms[kernels::kRelease] = zero;
        terms[kernels::kViscous] = select(touch, e.viscous, zero);
        store3(d, select(touch, e.fv, z3), &c.fv[s]);
    }
    append_lanes(d, hn::AndNot(touch, live), s, a.opened);
}

template <bool kEnergy, class D>
HWY_INLINE void bond_body(D d, const kernels::BondArgs& a, int64_t s, VecD<D>* terms) {
    BondList& b = *a.b;
    const PairState<D> q = gather_pair(d, *a.p, &b.i[s], &b.j[s]);
    const VecD<D> dt = hn::Set(d, a.dt), half = hn::Set(d, 0.5);
    const V3D<D> dx = q.xj - q.xi;
    const VecD<D> dist = hn::Sqrt(norm2(dx));
    const V3D<D> n = dx * (hn::Set(d, 1.0) / dist);
    // Lever arms as for a contact: the bond point sits where the spheres would touch.
    const VecD<D> half_gap = half * (q.ri + q.rj - dist);
    const V3D<D> vrel = relative_velocity(q, n);
    const VecD<D> spin_n = half * dot(n, q.wi + q.wj);
    VecD<D> kn, ks, l0;
    hn::LoadInterleaved3(d, &b.phys[s].kn, kn, ks, l0);
    V3D<D> fs = load3(d, &b.shear[s]), prev = load3(d, &b.prev_normal[s]);
    VecD<D> elastic;
    const V3D<D> f = bond_force_lanes<kEnergy>(kn, ks, l0, n, dist, vrel, spin_n, dt, fs, prev, &elastic);
    const V3D<D> nxf = cross(n, neg(f));
    store3(d, f, &b.force[s]);
    store3(d, nxf * (q.ri - half_gap), &b.torque1[s]);
    store3(d, nxf * (q.rj - half_gap), &b.torque2[s]);
    store3(d, fs, &b.shear[s]);
    store3(d, prev, &b.prev_normal[s]);
    if constexpr (kEnergy) terms[0] = elastic;
}

// sign(x) * lambda as in dem/integrate/leapfrog.h: 1 - lambda sign(x), sign(0) = 0.
template <class D> HWY_INLINE VecD<D> damping_factor(D d, VecD<D> x, VecD<D> lambda) {
    const VecD<D> zero = hn::Zero(d), one = hn::Set(d, 1.0);
    const VecD<D> sgn = hn::IfThenElse(x > zero, one, hn::IfThenElse(x < zero, hn::Set(d, -1.0), zero));
    return one - lambda * sgn;
}

template <bool kEnergy, class D>
HWY_INLINE void advance_body(D d, const kernels::AdvanceArgs& a, int64_t s, VecD<D>* terms, VecD<D>& max_d2) {
    Particles& p = *a.p;
    const VecD<D> zero = hn::Zero(d), dt = hn::Set(d, a.dt), lambda = hn::Set(d, a.lambda);
    const VecD<D> half = hn::Set(d, 0.5), half_dt = hn::Set(d, 0.5 * a.dt);
    const VecD<D> inv_m = hn::LoadU(d, &p.inv_mass[s]), m = hn::LoadU(d, &p.mass[s]);
    const VecD<D> inv_i = hn::LoadU(d, &p.inv_inertia[s]);
    const auto free = inv_m > zero;
    const V3D<D> x0 = load3(d, &p.pos[s]), v0 = load3(d, &p.vel[s]), w0 = load3(d, &p.angvel[s]);
    const V3D<D> fc = load3(d, &p.force[s]), tq = load3(d, &p.torque[s]);
    const V3D<D> g{hn::Set(d, a.gravity.x), hn::Set(d, a.gravity.y), hn::Set(d, a.gravity.z)};
    const V3D<D> fx = a.ext_force ? load3(d, &a.ext_force[s]) : zero3(d);
    const V3D<D> fg = g * m;
    // Total force as World::total_force: contacts + external + gravity.
    const V3D<D> ftot = (fc + fx) + fg;
    // Yade's cundallDamp2nd: component k scaled by 1 - lambda sign(a_k v_k(t)),
    // v(t) = v(t - dt/2) + dt/2 a (dem/integrate/leapfrog.h, damped_acceleration).
    V3D<D> acc = ftot * inv_m;
    acc.x = acc.x * damping_factor(d, acc.x * (v0.x + half_dt * acc.x), lambda);
    acc.y = acc.y * damping_factor(d, acc.y * (v0.y + half_dt * acc.y), lambda);
    acc.z = acc.z * damping_factor(d, acc.z * (v0.z + half_dt * acc.z), lambda);
    const V3D<D> v1 = v0 + acc * dt;
    const V3D<D> x1 = x0 + v1 * dt;
    // cundallDamp1st for rotations.
    V3D<D> al = tq * inv_i;
    al.x = al.x * damping_factor(d, al.x * w0.x, lambda);
    al.y = al.y * damping_factor(d, al.y * w0.y, lambda);
    al.z = al.z * damping_factor(d, al.z * w0.z, lambda);
    const V3D<D> w1 = w0 + al * dt;
    store3(d, select(free, v1, v0), &p.vel[s]);
    store3(d, select(free, x1, x0), &p.pos[s]);
    store3(d, select(free, w1, w0), &p.angvel[s]);
    const V3D<D> moved = x1 - load3(d, &a.ref_pos[s]);
    max_d2 = hn::Max(max_d2, hn::IfThenElseZero(free, norm2(moved)));
    if constexpr (kEnergy) {
        // World::particle terms (docs/energy.md): trapezoid halves of each force's work.
        const VecD<D> h = half_dt;
        const V3D<D> fp = a.pressure ? load3(d, &a.pressure[s]) : zero3(d);
        const VecD<D> r = hn::LoadU(d, &p.radius[s]);
        const VecD<D> inertia = select(inv_i > zero, hn::Set(d, 0.4) * m * r * r, zero);
        using kernels::kTerms;
        for (int k = 0; k < kernels::kParticleSums; ++k) terms[k] = zero;
        terms[kernels::kGravity] = dot(fg, v0) * h;
        terms[kTerms + kernels::kGravity] = dot(fg, v1) * h;
        terms[kernels::kPressure] = dot(fp, v0) * h;
        terms[kTerms + kernels::kPressure] = dot(fp, v1) * h;
        terms[kernels::kExternal] = dot(fx, v0) * h;
        terms[kTerms + kernels::kExternal] = dot(fx, v1) * h;
        terms[2 * kTerms] = half * m * dot(v0, v1) + half * inertia * dot(w0, w1);
        if (a.lambda != 0.0) {
            // The damping force and torque the integrator removed: F - m a, T - I alpha.
            const V3D<D> df = ftot - acc * m;
            const V3D<D> dq = select(inertia > zero, tq - al * inertia, zero3(d));
            terms[kernels::kDamping] = (dot(df, v0) + dot(dq, w0)) * h;
            terms[kTerms + kernels::kDamping] = (dot(df, v1) + dot(dq, w1)) * h;
        }
        for (int k = 0; k < kernels::kParticleSums; ++k) terms[k] = hn::IfThenElseZero(free, terms[k]);
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
        d, int64_t(a.p->size()), a.block_begin, a.block_end, a.energy, [&](auto dd, int64_t s, auto* t) {
            if constexpr (hn::MaxLanes(decltype(dd)()) == 1 && hn::MaxLanes(decltype(d)()) != 1)
                advance_body<kEnergy>(dd, a, s, t, max_1);
            else
                advance_body<kEnergy>(dd, a, s, t, max_v);
        });
    return std::max(hn::GetLane(hn::MaxOfLanes(d, max_v)), hn::GetLane(max_1));
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

namespace kernels {

void frictional_pairs(const PairArgs& a) { HWY_DYNAMIC_DISPATCH(FrictionalPairs)(a); }
void smooth_pairs(const PairArgs& a) { HWY_DYNAMIC_DISPATCH(SmoothPairs)(a); }
void bonds(const BondArgs& a) { HWY_DYNAMIC_DISPATCH(Bonds)(a); }
double advance(const AdvanceArgs& a) { return HWY_DYNAMIC_DISPATCH(Advance)(a); }

std::vector<int64_t> available_targets() { return hwy::SupportedAndGeneratedTargets(); }
std::string target_name(int64_t target) { return hwy::TargetName(target); }
void restrict_to_target(int64_t target) { hwy::SetSupportedTargetsForTest(target); }

}  // namespace kernels
}  // namespace dem
#endif  // HWY_ONCE
