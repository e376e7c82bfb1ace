// The bond law over lanes (see dem/bonds/bond_law.h). No include guard and no namespace:
// included into namespace dem by bond_law.h and into each SIMD target's namespace by
// dem/kernels/kernels.cpp (the same reason as dem/core/lanes-inl.h).

// `n` unit vector from 1 to 2, `dist` [m] centre distance, `vrel` velocity of 2 relative to 1
// at the bond point [m/s], `fs`, `prev` the shear history. Returns the force on body 2 [N];
// body 1 gets the opposite. With kEnergy the stored energy 1/2 kn (L - L0)^2 + |Fs|^2 / (2 ks)
// [J] after the step goes to *elastic; the force does not depend on it.
template <bool kEnergy, class R>
VPPDEM_HD inline V3<R> bond_force_lanes(const R& kn, const R& ks, const R& rest_length, const V3<R>& n, const R& dist,
                              const V3<R>& vrel, const R& spin_n, const R& dt, V3<R>& fs, V3<R>& prev,
                              R* elastic = nullptr) {
    rotate_shear_lanes(fs, prev, n, spin_n, dt);
    const V3<R> vt = vrel - n * dot(vrel, n);
    fs = fs - vt * (ks * dt);
    if constexpr (kEnergy) {
        const R zero = lit(dt, 0.0);
        const R stretch = dist - rest_length;
        *elastic = lit(dt, 0.5) * kn * stretch * stretch + select(ks > zero, norm2(fs) / (lit(dt, 2.0) * ks), zero);
    }
    return n * (kn * (rest_length - dist)) + fs;
}

