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

// R(q) as a matrix, for turning several vectors by one orientation (a clump's members).
struct RotationMatrix {
    Vec3 c0, c1, c2;  // the columns: the body axes in the world frame
    VPPDEM_HD explicit RotationMatrix(const Quat& q) {
        const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
        const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
        const double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
        c0 = {1.0 - 2.0 * (yy + zz), 2.0 * (xy + wz), 2.0 * (xz - wy)};
        c1 = {2.0 * (xy - wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz + wx)};
        c2 = {2.0 * (xz + wy), 2.0 * (yz - wx), 1.0 - 2.0 * (xx + yy)};
    }
    VPPDEM_HD Vec3 operator*(const Vec3& v) const { return c0 * v.x + c1 * v.y + c2 * v.z; }
};

}  // namespace dem
