// Unit quaternions for the orientation of rigid bodies (clumps): q = (w, x, y, z), R(q) turns
// body-frame vectors into world-frame ones, and R(a * b) = R(a) R(b) (Hamilton product).
// Only +, *, sqrt: the same bits on every IEEE machine (no sin or cos, see rigid_rotation.h).
#pragma once

#include <cmath>

#include "dem/core/vec3.h"
#include "dem/core/hd.h"

namespace dem {

struct Quat {
    double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
    constexpr bool operator==(const Quat&) const = default;
};

constexpr Quat operator*(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

constexpr Quat conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }

VPPDEM_HD inline Quat normalized(const Quat& q) {
    const double s = 1.0 / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w * s, q.x * s, q.y * s, q.z * s};
}

// R(q) v: body frame -> world frame (v + 2 u x (u x v + w v), u = (x, y, z)).
constexpr Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 u{q.x, q.y, q.z};
    const Vec3 t = cross(u, v) * 2.0;
    return v + t * q.w + cross(u, t);
}

// R(q)^T v: world frame -> body frame.
constexpr Vec3 rotate_back(const Quat& q, const Vec3& v) { return rotate(conjugate(q), v); }

// The rotation matrix's columns (the body axes in the world frame).
constexpr Vec3 body_axis(const Quat& q, int k) {
    Vec3 e;
    e[k] = 1.0;
    return rotate(q, e);
}

}  // namespace dem
