#include "dem/clumps/clump_shape.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>


namespace dem {

namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

// Integrals over a body per unit density: volume, first moment, second moments sum x_a x_b.
struct Moments {
    double v = 0.0;
    Vec3 first;
    Mat3 second{};
};

// A ball's closed forms: V, V c, V (c c^T + r^2 / 5 Id).
Moments ball(const ClumpMember& m) {
    Moments s;
    const double r = m.radius;
    s.v = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    s.first = m.center * s.v;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) s.second[a][b] = s.v * (m.center[a] * m.center[b] + (a == b ? r * r / 5.0 : 0.0));
    return s;
}

// Members that touch form one body: breadth-first over pairs closer than the radii's sum.
bool connected(const std::vector<ClumpMember>& m) {
    std::vector<char> seen(m.size(), 0);
    std::vector<std::size_t> queue{0};
    seen[0] = 1;
    for (std::size_t q = 0; q < queue.size(); ++q)
        for (std::size_t j = 0; j < m.size(); ++j) {
            const double reach = m[queue[q]].radius + m[j].radius;
            if (!seen[j] && norm2(m[j].center - m[queue[q]].center) < reach * reach) {
                seen[j] = 1;
                queue.push_back(j);
            }
        }
    return queue.size() == m.size();
}

void add(Moments& a, const Moments& b, double sign = 1.0) {
    a.v += sign * b.v;
    a.first += b.first * sign;
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y) a.second[x][y] += sign * b.second[x][y];
}

// The cap of the ball (c, R) beyond the plane at distance s from c along the unit vector u
// (s clamped to [-R, R]: the whole ball, nothing). In the cap's frame (z along u) the
// integrals are polynomials of the bounds: V = pi int (R^2 - z^2), int z dV, int z^2 dV, and
// int x^2 dV = (pi / 4) int (R^2 - z^2)^2 (a disk's second moment); then moved to c.
Moments cap(const Vec3& c, double R, const Vec3& u, double s) {
    Moments m;
    s = std::clamp(s, -R, R);
    const double r2 = R * R, pi = std::numbers::pi;
    const auto between = [&](auto f) { return f(R) - f(s); };
    const double v = pi * between([&](double z) { return r2 * z - z * z * z / 3.0; });
    const double m1 = pi * between([&](double z) { return r2 * z * z / 2.0 - z * z * z * z / 4.0; });
    const double szz = pi * between([&](double z) { return r2 * z * z * z / 3.0 - std::pow(z, 5) / 5.0; });
    const double sxx = pi / 4.0 * between([&](double z) { return r2 * r2 * z - 2.0 * r2 * z * z * z / 3.0 + std::pow(z, 5) / 5.0; });
    m.v = v;
    m.first = c * v + u * m1;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            m.second[a][b] = v * c[a] * c[b] + m1 * (c[a] * u[b] + u[a] * c[b]) + sxx * ((a == b ? 1.0 : 0.0) - u[a] * u[b]) +
                             szz * u[a] * u[b];
    return m;
}

// The intersection of two balls (a lens, or the smaller ball): on each side of the radical
// plane it is the cap of one ball (beyond the plane, a point of ball i lies in ball j too).
Moments lens(const ClumpMember& a, const ClumpMember& b) {
    const Vec3 d = b.center - a.center;
    const double dist = norm(d);
    Moments m;
    if (dist == 0.0) return ball(a.radius <= b.radius ? a : b);
    const Vec3 u = d / dist;
    const double s = (dist * dist + a.radius * a.radius - b.radius * b.radius) / (2.0 * dist);
    add(m, cap(a.center, a.radius, u, s));
    add(m, cap(b.center, b.radius, -u, dist - s));
    return m;
}

bool overlap(const ClumpMember& a, const ClumpMember& b) {
    const double reach = a.radius + b.radius;
    return norm2(b.center - a.center) < reach * reach;
}

// What the overlaps count twice, integral of (n(x) - 1)+ {1, x, x x^T}: the pairs' lenses in
// closed form (a point in n balls lies in n(n - 1)/2 of them), less (n - 1)(n - 2)/2 where
// three or more balls overlap, by the midpoint rule in the boxes of those triples.
Moments overlap_excess(const std::vector<ClumpMember>& m, int cells_per_radius) {
    Moments s;
    for (std::size_t i = 0; i < m.size(); ++i)
        for (std::size_t j = i + 1; j < m.size(); ++j)
            if (overlap(m[i], m[j])) add(s, lens(m[i], m[j]));
    double rmin = m[0].radius;
    for (const ClumpMember& c : m) rmin = std::min(rmin, c.radius);
    const double h = rmin / cells_per_radius;
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    bool any = false;
    for (std::size_t i = 0; i < m.size(); ++i)
        for (std::size_t j = i + 1; j < m.size(); ++j)
            for (std::size_t k = j + 1; k < m.size(); ++k) {
                if (!overlap(m[i], m[j]) || !overlap(m[i], m[k]) || !overlap(m[j], m[k])) continue;
                any = true;
                for (int a = 0; a < 3; ++a) {
                    // The triple's region lies inside the three balls' boxes.
                    lo[a] = std::min(lo[a], std::max({m[i].center[a] - m[i].radius, m[j].center[a] - m[j].radius,
                                                       m[k].center[a] - m[k].radius}));
                    hi[a] = std::max(hi[a], std::min({m[i].center[a] + m[i].radius, m[j].center[a] + m[j].radius,
                                                       m[k].center[a] + m[k].radius}));
                }
            }
    if (!any) return s;
    int64_t n[3];
    for (int a = 0; a < 3; ++a) n[a] = std::max<int64_t>(1, int64_t(std::ceil((hi[a] - lo[a]) / h)));
    const double dv = h * h * h;
    Moments t;
    for (int64_t k = 0; k < n[2]; ++k)
        for (int64_t j = 0; j < n[1]; ++j)
            for (int64_t i = 0; i < n[0]; ++i) {
                const Vec3 x{lo.x + (double(i) + 0.5) * h, lo.y + (double(j) + 0.5) * h, lo.z + (double(k) + 0.5) * h};
                int count = 0;
                for (const ClumpMember& c : m) count += norm2(x - c.center) < c.radius * c.radius;
                if (count < 3) continue;
                const double w = 0.5 * double((count - 1) * (count - 2)) * dv;
                t.v += w;
                t.first += x * w;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) t.second[a][b] += w * x[a] * x[b];
            }
    add(s, t, -1.0);
    return s;
}

Vec3 column(const Mat3& r, int k) { return {r[0][k], r[1][k], r[2][k]}; }

// The quaternion of a rotation matrix (columns: the rotated axes), Shepperd's method.
Quat from_matrix(const Mat3& r) {
    const double tr = r[0][0] + r[1][1] + r[2][2];
    Quat q;
    if (tr > 0.0) {
        const double s = 2.0 * std::sqrt(1.0 + tr);
        q = {0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s};
    } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
        const double s = 2.0 * std::sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
        q = {(r[2][1] - r[1][2]) / s, 0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s};
    } else if (r[1][1] > r[2][2]) {
        const double s = 2.0 * std::sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
        q = {(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s};
    } else {
        const double s = 2.0 * std::sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
        q = {(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s};
    }
    return normalized(q);
}

}  // namespace

SymmetricEigen3 symmetric_eigen(const Mat3& in) {
    Mat3 a = in;
    Mat3 v{};
    for (int k = 0; k < 3; ++k) v[k][k] = 1.0;
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-32 * diag || off == 0.0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                // The rotation in the (p, q) plane that zeroes a[p][q] (Numerical Recipes' form).
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // a <- a J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {  // a <- J^T a
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {  // v <- v J
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int x, int y) { return a[x][x] < a[y][y]; });
    SymmetricEigen3 e;
    for (int k = 0; k < 3; ++k) {
        e.values[k] = a[order[k]][order[k]];
        e.vectors[k] = column(v, order[k]);
    }
    // Right-handed: the third axis is the cross product of the first two.
    if (dot(cross(e.vectors[0], e.vectors[1]), e.vectors[2]) < 0.0) e.vectors[2] = -e.vectors[2];
    return e;
}

ClumpShape make_clump_shape(const std::vector<ClumpMember>& members, int cells_per_radius) {
    if (members.empty()) throw std::invalid_argument("clump template: no members");
    if (cells_per_radius < 1) throw std::invalid_argument("clump template: cells_per_radius must be >= 1");
    for (std::size_t k = 0; k < members.size(); ++k) {
        const ClumpMember& m = members[k];
        if (!std::isfinite(m.center.x) || !std::isfinite(m.center.y) || !std::isfinite(m.center.z) ||
            !std::isfinite(m.radius))
            throw std::invalid_argument("clump template: member " + std::to_string(k + 1) + " has a non-finite number");
        if (!(m.radius > 0.0))
            throw std::invalid_argument("clump template: member " + std::to_string(k + 1) + " has radius " +
                                        std::to_string(m.radius) + " (must be > 0)");
    }
    if (!connected(members))
        throw std::invalid_argument("clump template: the members do not all touch one another (a clump is one body)");

    Moments total;
    for (const ClumpMember& m : members) add(total, ball(m));
    add(total, overlap_excess(members, cells_per_radius), -1.0);

    ClumpShape s;
    s.volume = total.v;
    const Vec3 com = total.first / total.v;
    s.template_center = com;
    // Second moments about the centre of mass, then the inertia tensor tr(S) Id - S.
    Mat3 sc, j;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) sc[a][c] = total.second[a][c] - total.v * com[a] * com[c];
    const double tr = sc[0][0] + sc[1][1] + sc[2][2];
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) j[a][c] = (a == c ? tr : 0.0) - sc[a][c];
    const SymmetricEigen3 e = symmetric_eigen(j);
    s.inertia_per_density = {e.values[0], e.values[1], e.values[2]};
    // Principal frame: x' = E^T (x - com), E's columns the principal axes in the template frame.
    Mat3 et;  // rows: the principal axes
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) et[k][a] = e.vectors[k][a];
    s.template_to_principal = from_matrix(et);
    s.min_radius = members[0].radius;
    for (const ClumpMember& m : members) {
        const Vec3 d = m.center - com;
        ClumpMember p{{dot(e.vectors[0], d), dot(e.vectors[1], d), dot(e.vectors[2], d)}, m.radius};
        s.members.push_back(p);
        s.bounding_radius = std::max(s.bounding_radius, norm(p.center) + m.radius);
        s.min_radius = std::min(s.min_radius, m.radius);
    }
    return s;
}

ClumpShape scaled(const ClumpShape& shape, double f) {
    if (!(f > 0.0) || !std::isfinite(f)) throw std::invalid_argument("clump shape: scale must be finite and > 0");
    ClumpShape s = shape;
    for (ClumpMember& m : s.members) {
        m.center = m.center * f;
        m.radius *= f;
    }
    s.volume *= f * f * f;
    s.inertia_per_density = s.inertia_per_density * (f * f * f * f * f);
    s.bounding_radius *= f;
    s.min_radius *= f;
    s.template_center = s.template_center * f;
    return s;
}

const std::vector<std::string>& builtin_clump_shapes() {
    static const std::vector<std::string> names{"sphere", "dimer", "trimer", "tetrahedron", "pellet"};
    return names;
}

ClumpShape builtin_clump_shape(const std::string& name, double r_equivalent) {
    if (!(r_equivalent > 0.0) || !std::isfinite(r_equivalent))
        throw std::invalid_argument("clump shape '" + name + "': equivalent radius must be finite and > 0");
    std::vector<ClumpMember> t;
    if (name == "sphere") {
        t = {{{0, 0, 0}, 1.0}};
    } else if (name == "dimer") {
        t = {{{-0.5, 0, 0}, 1.0}, {{0.5, 0, 0}, 1.0}};
    } else if (name == "trimer") {
        t = {{{-1.0, 0, 0}, 1.0}, {{0, 0, 0}, 1.0}, {{1.0, 0, 0}, 1.0}};
    } else if (name == "tetrahedron") {
        // Corners of a regular tetrahedron of edge 1.5 (alternate corners of a cube of side a).
        const double a = 1.5 / std::sqrt(2.0) / 2.0;
        t = {{{a, a, a}, 1.0}, {{a, -a, -a}, 1.0}, {{-a, a, -a}, 1.0}, {{-a, -a, a}, 1.0}};
    } else if (name == "pellet") {
        t = {{{0, 0, 0}, 1.0}};
        for (int k = 0; k < 6; ++k) {
            // The ring at angles k * 60 degrees: cos and sin of multiples of 60 as exact-form constants.
            static const double c[6] = {1.0, 0.5, -0.5, -1.0, -0.5, 0.5};
            static const double s3 = std::sqrt(3.0) / 2.0;
            const double sn[6] = {0.0, s3, s3, 0.0, -s3, -s3};
            t.push_back({{c[k], sn[k], 0.0}, 1.0});
        }
    } else {
        std::string list;
        for (const std::string& n : builtin_clump_shapes()) list += (list.empty() ? "" : ", ") + n;
        throw std::invalid_argument("clump shape '" + name + "' is not built in (built-in: " + list + ")");
    }
    return scaled_to_radius(make_clump_shape(t), r_equivalent);
}

ClumpShape scaled_to_radius(const ClumpShape& shape, double r) {
    const double target = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    return scaled(shape, std::cbrt(target / shape.volume));
}

}  // namespace dem
