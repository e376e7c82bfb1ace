// Lane templates shared by the scalar code (namespace dem, via dem/core/lanes.h) and each SIMD
// target of the kernels (namespace dem::HWY_NAMESPACE, dem/kernels/kernels.cpp). No include
// guard and no namespace on purpose: it is included once into each of those namespaces, so
// that in the kernels these templates are compiled with the target's instruction set.
// Needs, declared before it: lit, neg, lane_sqrt, select, both for the lane type in use, and
// VPPDEM_HD (dem/core/hd.h).

// A 3-vector of lanes: component k of lane l is vector component k's lane l.
template <class R> struct V3 {
    R x, y, z;
};

template <class R> VPPDEM_HD inline V3<R> operator+(const V3<R>& a, const V3<R>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class R> VPPDEM_HD inline V3<R> operator-(const V3<R>& a, const V3<R>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class R> VPPDEM_HD inline V3<R> operator*(const V3<R>& a, const R& s) { return {a.x * s, a.y * s, a.z * s}; }
template <class R> VPPDEM_HD inline R dot(const V3<R>& a, const V3<R>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class R> VPPDEM_HD inline V3<R> cross(const V3<R>& a, const V3<R>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class R> VPPDEM_HD inline R norm2(const V3<R>& a) { return dot(a, a); }

// max(a, b) as (a < b ? b : a) in every lane type (std::max's rule; the x86 max instruction
// differs for signed zeros, so it is not used).
template <class R> VPPDEM_HD inline R lane_max(const R& a, const R& b) { return select(a < b, b, a); }
template <class M, class R> VPPDEM_HD inline V3<R> select(const M& m, const V3<R>& a, const V3<R>& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class R> VPPDEM_HD inline V3<R> neg(const V3<R>& a) { return {neg(a.x), neg(a.y), neg(a.z)}; }
