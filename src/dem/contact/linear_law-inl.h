// The linear contact law over lanes (see dem/contact/linear_law.h). No include guard and no
// namespace: included into namespace dem by linear_law.h and into each SIMD target's namespace
// by dem/kernels/kernels.cpp (the same reason as dem/core/lanes-inl.h).

// Energy terms of one step of a contact (docs/energy.md), in lanes.
template <class R> struct ContactEnergyLanes {
    R elastic;   // [J] stored after the step: 1/2 kn overlap^2 + |Fs|^2 / (2 ks)
    R slip;      // [J] Coulomb slip over the step
    R viscous;   // [J] dashpot work over the first half, cn vn^2 dt / 2
    V3<R> fv;    // [N] dashpot force on body 2
};

// One step of the law. `vrel` is the velocity of body 2 relative to body 1 at the contact
// [m/s]; `spin_n` = 0.5 * normal . (w1 + w2) [rad/s] is the twist rate of the contact plane.
// `fs`, `prev`: the shear history. Returns the force on body 2 [N] (body 1 gets the
// opposite). With kEnergy the step's energy terms go to *e; the force does not depend on it.
template <bool kEnergy, class R>
VPPDEM_HD inline V3<R> linear_contact_force_lanes(const R& kn, const R& ks, const R& mu, const R& cn, const V3<R>& n,
                                        const R& overlap, const V3<R>& vrel, const R& spin_n, const R& dt,
                                        V3<R>& fs, V3<R>& prev, ContactEnergyLanes<R>* e = nullptr) {
    rotate_shear_lanes(fs, prev, n, spin_n, dt);
    const V3<R> fs_prev = fs;  // the spring carried into this step's contact plane
    const R zero = lit(dt, 0.0);
    const R vn = dot(vrel, n);  // > 0 separating
    const V3<R> vt = vrel - n * vn;
    fs = fs - vt * (ks * dt);  // incremental elastic shear spring

    const R fn = kn * overlap - cn * vn;  // elastic part never pulls (overlap > 0)
    const R fs_max = mu * lane_max(fn, zero);
    const R fs2 = norm2(fs);
    const auto slip = fs2 > fs_max * fs_max;
    const V3<R> trial = fs;
    fs = select(slip, fs * (fs_max / lane_sqrt(fs2)), fs);  // Coulomb slip
    if constexpr (kEnergy) {
        // Work done on the spring over the step (trapezoid with the relative displacement
        // u = vt dt = (fs_prev - trial) / ks) minus its energy change:
        //   (trial - fs) . (fs_prev + fs) / (2 ks)   (= mu fn |slip| when sliding steadily).
        const auto has_ks = ks > zero;
        const R two_ks = lit(dt, 2.0) * ks;
        e->slip = select(both(slip, has_ks), dot(trial - fs, fs_prev + fs) / two_ks, zero);
        e->elastic = lit(dt, 0.5) * kn * overlap * overlap + select(has_ks, norm2(fs) / two_ks, zero);
        e->viscous = lit(dt, 0.5) * cn * vn * vn * dt;
        e->fv = n * neg(cn * vn);
    }
    // Force on body 1 is -(fn n) - fs (Yade); body 2 gets the opposite.
    return n * fn + fs;
}

// The law of a frictionless pair (mu = 0): the Coulomb cap is zero, so the shear spring is
// zero after every step and the law reduces to the normal spring (and dashpot): no history,
// no slip, and a force along n that exerts no torque. Kept as its own function because most
// pairs in a damper are frictionless (grain-foil, foil-foil) and skip all the shear work.
template <bool kEnergy, class R>
VPPDEM_HD inline V3<R> normal_contact_force_lanes(const R& kn, const R& cn, const V3<R>& n, const R& overlap,
                                        const V3<R>& vrel, const R& dt, ContactEnergyLanes<R>* e = nullptr) {
    const R vn = dot(vrel, n);
    const R fn = kn * overlap - cn * vn;
    if constexpr (kEnergy) {
        const R zero = lit(dt, 0.0);
        e->slip = zero;
        e->elastic = lit(dt, 0.5) * kn * overlap * overlap;
        e->viscous = lit(dt, 0.5) * cn * vn * vn * dt;
        e->fv = n * neg(cn * vn);
    }
    return n * fn;
}

