// The per-index bodies of the step over lanes (dem/core/lanes.h), written once: World's SIMD
// kernels (dem/kernels/kernels.cpp, R = a Highway vector, M its mask) and the batch engine's host
// and device kernels (dem/kernels/step_bodies.h and dem/batch, R = double, M = bool) call these
// same functions, so that a batch gives World's bits by construction. Each body takes what was
// loaded for its index (or lanes of indices) and gives what is to be stored; the loads, the
// stores, the masks of live slots and the energy sums stay with the callers.
// No include guard and no namespace: included into namespace dem by dem/kernels/step_bodies.h and
// into each SIMD target's namespace by dem/kernels/kernels.cpp (as dem/core/lanes-inl.h). Needs,
// included before it: dem/core/lanes-inl.h, dem/contact/linear_law-inl.h,
// dem/bonds/bond_law-inl.h.
// VPPDEM_BODY: the bodies are inlined into their kernels' loops whatever the compiler's estimate
// (World's kernels were written with every step inlined; a call per vector costs).
#ifndef VPPDEM_BODY
#if defined(__CUDACC__)
#define VPPDEM_BODY __host__ __device__ __forceinline__
#elif defined(__GNUC__)
#define VPPDEM_BODY __attribute__((always_inline)) inline
#else
#define VPPDEM_BODY inline
#endif
#endif

// One particle pair as the pair and bond kernels read it: positions, half-step velocities,
// angular velocities and radii of body 1 (i) and body 2 (j).
template <class R> struct PairLanes {
    V3<R> xi, vi, wi, xj, vj, wj;  // [m], [m/s], [rad/s]
    R ri, rj;                      // [m]
};

// What a contact body gives besides its force: the torques (frictional pairs), and with kEnergy
// the energy ledger's terms (dem/kernels/kernels.h, PairSum) and the dashpot force. All zero for a
// pair found apart, but for `release` (a loaded shear spring lost by a live pair that opened).
template <class R> struct PairLanesOut {
    V3<R> force, torque1, torque2;          // [N] on body 2 (body 1: the opposite), [N m]
    R elastic, slip, release, viscous;      // [J] (kEnergy)
    V3<R> fv;                               // [N] dashpot force on body 2 (kEnergy)
};

// The touch test of a particle pair (ContactSet::find_new, the pair kernels): the spheres
// overlap.
template <class R> VPPDEM_BODY auto spheres_touch_lanes(const V3<R>& xi, const R& ri, const V3<R>& xj, const R& rj) {
    const V3<R> dx = xj - xi;
    const R rs = ri + rj;
    return norm2(dx) < rs * rs;
}

// Velocity of body 2 relative to body 1 at the point arm1 along n from body 1's centre and arm2
// back along n from body 2's [m].
template <class R>
VPPDEM_BODY V3<R> pair_relative_velocity_at(const PairLanes<R>& q, const V3<R>& n, const R& arm1, const R& arm2) {
    return (q.vj + cross(q.wj, n * neg(arm2))) - (q.vi + cross(q.wi, n * arm1));
}
// At the contact, lever arms at the full radii along n (Yade's avoidGranularRatcheting).
template <class R> VPPDEM_BODY V3<R> pair_relative_velocity(const PairLanes<R>& q, const V3<R>& n) {
    return pair_relative_velocity_at(q, n, q.ri, q.rj);
}

// Sphere-sphere geometry (dem/detect/geometry.h, sphere_sphere), evaluated whether or not the
// spheres touch: unit normal from 1 to 2 ((0, 0, 1) for coincident centres) and overlap [m]
// (negative when apart). Returns the touch mask, `live` and the spheres overlapping.
template <class R, class M>
VPPDEM_BODY auto sphere_geometry_lanes(const PairLanes<R>& q, const M& live, V3<R>& n, R& overlap) {
    const V3<R> dx = q.xj - q.xi;
    const R d2 = norm2(dx), rs = q.ri + q.rj;
    const auto touch = both(live, d2 < rs * rs);
    const R zero = lit(rs, 0.0), one = lit(rs, 1.0);
    const R dist = lane_sqrt(d2);
    const R inv = one / dist;
    n = select(dist > zero, dx * inv, V3<R>{zero, zero, one});
    overlap = rs - dist;
    return touch;
}

// A frictional particle pair: sphere-sphere geometry, relative velocity at the contact, the
// linear law with its shear history (fs, prev: updated; zeroed when apart), torques at the
// contact point. `live`: the slot holds a contact (true for one pair). Returns the touch mask;
// a live pair that does not touch opened this step.
template <bool kEnergy, class R, class M>
VPPDEM_BODY auto frictional_pair_lanes(const PairLanes<R>& q, const M& live, const R& kn, const R& ks, const R& mu,
                                            const R& cn, const R& dt, V3<R>& fs, V3<R>& prev, PairLanesOut<R>& o) {
    V3<R> n;
    R overlap;
    const auto touch = sphere_geometry_lanes(q, live, n, overlap);
    const R zero = lit(dt, 0.0), half = lit(dt, 0.5);
    const R arm1 = q.ri - half * overlap, arm2 = q.rj - half * overlap;
    const V3<R> fs0 = fs, prev0 = prev;
    const V3<R> vrel = pair_relative_velocity(q, n);
    const R spin_n = half * dot(n, q.wi + q.wj);
    ContactEnergyLanes<R> e;
    const V3<R> f = linear_contact_force_lanes<kEnergy>(kn, ks, mu, cn, n, overlap, vrel, spin_n, dt, fs, prev, &e);
    const V3<R> nxf = cross(n, neg(f));
    const V3<R> z3{zero, zero, zero};
    // A pair found apart forgets its shear spring (Yade deletes the interaction).
    o.force = select(touch, f, z3);
    o.torque1 = select(touch, nxf * arm1, z3);
    o.torque2 = select(touch, nxf * arm2, z3);
    fs = select(touch, fs, z3);
    prev = select(touch, prev, z3);
    if constexpr (kEnergy) {
        // Opened this step: the loaded spring is lost (shear_release_energy), with the last
        // normal as lever-arm direction.
        const V3<R> vr0 = pair_relative_velocity(q, prev0);
        const R release = norm2(fs0) / (lit(dt, 2.0) * ks) - half * dot(fs0, vr0) * dt;
        o.elastic = select(touch, e.elastic, zero);
        o.slip = select(touch, e.slip, zero);
        o.release = select(touch, zero, select(both(live, ks > zero), release, zero));
        o.viscous = select(touch, e.viscous, zero);
        o.fv = select(touch, e.fv, z3);
    }
    return touch;
}

// A frictionless particle pair: the normal force only (no shear spring, no torques: o.torque1
// and o.torque2 are not written). Returns the touch mask as frictional_pair_lanes.
template <bool kEnergy, class R, class M>
VPPDEM_BODY auto smooth_pair_lanes(const PairLanes<R>& q, const M& live, const R& kn, const R& cn, const R& dt,
                                        PairLanesOut<R>& o) {
    V3<R> n;
    R overlap;
    const auto touch = sphere_geometry_lanes(q, live, n, overlap);
    const R zero = lit(dt, 0.0);
    // Only the normal relative velocity matters here: without shear there is no lever arm.
    const V3<R> vrel = q.vj - q.vi;
    ContactEnergyLanes<R> e;
    const V3<R> f = normal_contact_force_lanes<kEnergy>(kn, cn, n, overlap, vrel, dt, &e);
    const V3<R> z3{zero, zero, zero};
    o.force = select(touch, f, z3);
    if constexpr (kEnergy) {
        o.elastic = select(touch, e.elastic, zero);
        o.slip = zero;
        o.release = zero;
        o.viscous = select(touch, e.viscous, zero);
        o.fv = select(touch, e.fv, z3);
    }
    return touch;
}

// A bond's geometry: unit axis n from 1 to 2, centre distance [m], half the gap the spheres
// would close to touch (the torques' lever arms are r - half_gap: the bond point sits where the
// spheres would touch), the relative velocity that drives the shear spring and the twist rate.
// bond_point (BondArm::kBondPoint, dem/bonds/bond_list.h): that velocity at the bond point,
// with the torques' arms; otherwise at the full radii, as a contact's (the paper's convention;
// the same bits as before the choice existed).
template <class R> struct BondGeometryLanes {
    V3<R> n, vrel;
    R dist, half_gap, spin_n;
};
template <class R>
VPPDEM_BODY BondGeometryLanes<R> bond_geometry_lanes(const PairLanes<R>& q, bool bond_point = false) {
    const R half = lit(q.ri, 0.5);
    BondGeometryLanes<R> b;
    const V3<R> dx = q.xj - q.xi;
    b.dist = lane_sqrt(norm2(dx));
    b.n = dx * (lit(q.ri, 1.0) / b.dist);
    b.half_gap = half * (q.ri + q.rj - b.dist);
    // At the bond point the arms add up to dist.
    b.vrel = bond_point ? pair_relative_velocity_at(q, b.n, q.ri - b.half_gap, q.rj - b.half_gap)
                        : pair_relative_velocity(q, b.n);
    b.spin_n = half * dot(b.n, q.wi + q.wj);
    return b;
}
// The bond law on that geometry with its shear history (fs, prev: updated), and the torques.
// With kEnergy the bond's stored energy [J] goes to *elastic.
template <bool kEnergy, class R>
VPPDEM_BODY void bond_step_lanes(const PairLanes<R>& q, const BondGeometryLanes<R>& b, const R& kn, const R& ks,
                                 const R& rest, const R& dt, V3<R>& fs, V3<R>& prev, V3<R>& force, V3<R>& torque1,
                                  V3<R>& torque2, R* elastic = nullptr) {
    force = bond_force_lanes<kEnergy>(kn, ks, rest, b.n, b.dist, b.vrel, b.spin_n, dt, fs, prev, elastic);
    const V3<R> nxf = cross(b.n, neg(force));
    torque1 = nxf * (q.ri - b.half_gap);
    torque2 = nxf * (q.rj - b.half_gap);
}
// One bond's step: the two above (World's bond kernel calls them apart, loading the bond's
// coefficients and history between them).
template <bool kEnergy, class R>
VPPDEM_BODY void bond_lanes(const PairLanes<R>& q, const R& kn, const R& ks, const R& rest, const R& dt, V3<R>& fs,
                            V3<R>& prev, V3<R>& force, V3<R>& torque1, V3<R>& torque2, R* elastic = nullptr,
                            bool bond_point = false) {
    bond_step_lanes<kEnergy>(q, bond_geometry_lanes(q, bond_point), kn, ks, rest, dt, fs, prev, force, torque1,
                             torque2, elastic);
}

// 1 - lambda sign(x), sign(0) = 0 (dem/integrate/leapfrog.h).
template <class R> VPPDEM_BODY R damping_factor_lanes(const R& x, const R& lambda) {
    const R zero = lit(x, 0.0), one = lit(x, 1.0);
    return one - lambda * select(x > zero, one, select(x < zero, lit(x, -1.0), zero));
}

// One particle's state and what acts on it for its leapfrog step.
template <class R> struct AdvanceLanes {
    V3<R> x, v, w;    // [m], [m/s] and [rad/s] at t - dt/2 (v, w): updated where free
    V3<R> f, fx, t;   // [N] contact force, external force (zero when none), [N m] torque
    R m, inv_m, inv_i;  // [kg], [1/kg], [1/(kg m^2)]
};

// What the energy terms of a step read besides the particle: the velocities before and after,
// the gravity force, the total force, and the accelerations the integrator applied.
template <class R> struct AdvanceStepLanes {
    V3<R> v0, v1, w0, w1, fg, ftot, acc, al;
};

// One leapfrog step with Yade's local damping for the particles of `free` (inv_m > 0); the others
// keep their state. Total force (contact + external) + gravity, cundallDamp2nd on the translation,
// cundallDamp1st on the rotation, then v and x. lambda [-] the local damping. Returns what
// advance_terms_lanes reads.
template <class R, class M>
VPPDEM_BODY AdvanceStepLanes<R> advance_lanes(const M& free, AdvanceLanes<R>& s, const V3<R>& g, const R& dt,
                                              const R& lambda) {
    const R half_dt = lit(dt, 0.5) * dt;
    AdvanceStepLanes<R> q;
    const V3<R> x0 = s.x;
    const V3<R>& v0 = q.v0 = s.v;
    const V3<R>& w0 = q.w0 = s.w;
    q.fg = g * s.m;
    // Total force as World::total_force: contacts + external + gravity.
    q.ftot = (s.f + s.fx) + q.fg;
    // Yade's cundallDamp2nd: component k scaled by 1 - lambda sign(a_k v_k(t)),
    // v(t) = v(t - dt/2) + dt/2 a (dem/integrate/leapfrog.h, damped_acceleration).
    V3<R>& acc = q.acc = q.ftot * s.inv_m;
    acc.x = acc.x * damping_factor_lanes(acc.x * (v0.x + half_dt * acc.x), lambda);
    acc.y = acc.y * damping_factor_lanes(acc.y * (v0.y + half_dt * acc.y), lambda);
    acc.z = acc.z * damping_factor_lanes(acc.z * (v0.z + half_dt * acc.z), lambda);
    q.v1 = v0 + acc * dt;
    const V3<R> x1 = x0 + q.v1 * dt;
    // cundallDamp1st for rotations.
    V3<R>& al = q.al = s.t * s.inv_i;
    al.x = al.x * damping_factor_lanes(al.x * w0.x, lambda);
    al.y = al.y * damping_factor_lanes(al.y * w0.y, lambda);
    al.z = al.z * damping_factor_lanes(al.z * w0.z, lambda);
    q.w1 = w0 + al * dt;
    s.x = select(free, x1, x0);
    s.v = select(free, q.v1, v0);
    s.w = select(free, q.w1, w0);
    return q;
}

// The energy ledger's terms of that step (World::particle terms, docs/energy.md: trapezoid halves
// of each force's work; dem/kernels/kernels.h, ParticleTerm), zero for a particle not `free`: the
// work of each force over the back half step [J] in t[0..5), over the forward half step in
// t[5..10), the kinetic energy [J] in t[10]. s the particle as advance_lanes left it (its mass,
// inertia, external force and torque are read), fp the pressure's force [N], r the radius [m],
// `damped`: lambda != 0.
template <class R, class M>
VPPDEM_BODY void advance_terms_lanes(const M& free, const AdvanceLanes<R>& s, const AdvanceStepLanes<R>& q, const R& dt,
                                     bool damped, const V3<R>& fp, const R& r, R* t) {
    const R zero = lit(dt, 0.0), half = lit(dt, 0.5), h = half * dt;
    const R inertia = select(s.inv_i > zero, lit(dt, 0.4) * s.m * r * r, zero);
    R* const back = t;
    R* const fwd = t + 5;
    back[0] = fwd[0] = zero;  // boundary: the prescribed particles' (World's)
    back[2] = dot(q.fg, q.v0) * h;  // gravity
    fwd[2] = dot(q.fg, q.v1) * h;
    back[1] = dot(fp, q.v0) * h;  // pressure
    fwd[1] = dot(fp, q.v1) * h;
    back[3] = dot(s.fx, q.v0) * h;  // external
    fwd[3] = dot(s.fx, q.v1) * h;
    t[10] = half * s.m * dot(q.v0, q.v1) + half * inertia * dot(q.w0, q.w1);
    back[4] = fwd[4] = zero;
    if (damped) {
        // The damping force and torque the integrator removed: F - m a, T - I alpha.
        const V3<R> df = q.ftot - q.acc * s.m;
        const V3<R> dq = select(inertia > zero, s.t - q.al * inertia, V3<R>{zero, zero, zero});
        back[4] = (dot(df, q.v0) + dot(dq, q.w0)) * h;
        fwd[4] = (dot(df, q.v1) + dot(dq, q.w1)) * h;
    }
    for (int k = 0; k < 11; ++k) t[k] = select(free, t[k], zero);
}
