// The shear spring's rotation over lanes (see dem/core/shear_spring.h). No include guard and no
// namespace: included into namespace dem by shear_spring.h and into each SIMD target's namespace
// by dem/kernels/kernels.cpp (the same reason as dem/core/lanes-inl.h).

// Carries the shear force `fs` with the contact plane: rotates it by the change of normal
// (`prev` -> `n`) and by the twist spin_n dt about n (Yade's ScGeom::rotate), projects it back
// onto the plane and keeps its length. Yade rotates to first order only; keeping |Fs| avoids
// creating energy by the rotation itself. A zero `prev` marks the first step of a contact.
template <class R>
VPPDEM_HD inline void rotate_shear_lanes(V3<R>& fs, V3<R>& prev, const V3<R>& n, const R& spin_n, const R& dt) {
    const R zero = lit(dt, 0.0);
    prev = select(both(both(prev.x == zero, prev.y == zero), prev.z == zero), n, prev);
    const R len0_2 = norm2(fs);
    V3<R> r = fs - cross(fs, cross(prev, n));
    r = r - cross(r, n * (dt * spin_n));
    r = r - n * dot(r, n);
    const R len1_2 = norm2(r);
    r = select(len1_2 > zero, r * lane_sqrt(len0_2 / len1_2), r);  // one root instead of two
    fs = select(len0_2 > zero, r, fs);
    prev = n;
}
