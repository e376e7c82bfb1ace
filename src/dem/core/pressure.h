// Follower pressure on a bonded membrane through tributary-area vectors.
// A loaded node S with four chain neighbours P1..P4 in a fixed cyclic order gets
//   A = sum_i (P_i - S) x (P_{i%4+1} - S) = (P1 - P3) x (P2 - P4),   F = -dp A,
// recomputed from the current positions every step. On a flat square grid of spacing h this is
// |A| = 4 h^2, the area the node stands for when loaded nodes sit every 2h both ways.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/core/hd.h"

namespace dem {

struct PressureNode {
    uint32_t node;                    // the loaded particle S
    std::array<uint32_t, 4> ring;     // P1..P4, cyclic; A points to the side dp pushes from
};

// The tributary-area vector of a node from its ring P1..P4 [m^2].
VPPDEM_HD inline Vec3 tributary_area(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
    return cross(p1 - p3, p2 - p4);
}
inline Vec3 tributary_area(const std::vector<Vec3>& pos, const PressureNode& q) {
    return tributary_area(pos[q.ring[0]], pos[q.ring[1]], pos[q.ring[2]], pos[q.ring[3]]);
}
// The follower pressure's force on a node [N]: -(A dp), A its ring's tributary area (World's
// PressureForces::apply and the batch engine's kernels).
VPPDEM_HD inline Vec3 pressure_force(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double dp) {
    return -(tributary_area(p1, p2, p3, p4) * dp);
}

// Follower pressure on a triangulated membrane (dem/mesh, vpp/membrane): a loaded node S with
// its one-ring P_1..P_n, counter-clockwise seen from the side A points to, stands for a third
// of each triangle (S, P_i, P_i+1) around it:
//   A = sum_i (P_i - S) x (P_{i+1} - S) / 6,   F = -dp A.
// Summed over the nodes of a closed triangulation every triangle's area vector is counted
// once, so a uniform dp gives zero net force (to round-off) in any shape. The quad rule of
// PressureNode is the special case of a square grid whose loaded nodes stand for (2h)^2 each;
// fans carry any valence, hence a CSR ring rather than a fixed array.
struct PressureFans {
    std::vector<uint32_t> node;   // the loaded particles S
    std::vector<uint32_t> start;  // CSR: node k's ring is ring[start[k] .. start[k+1]); size node.size()+1
    std::vector<uint32_t> ring;   // one-ring particles, cyclic
    bool empty() const { return node.empty(); }
};

// The tributary-area vector of fan k [m^2].
inline Vec3 fan_area(const std::vector<Vec3>& pos, const PressureFans& f, std::size_t k) {
    const Vec3& s = pos[f.node[k]];
    const uint32_t b = f.start[k], e = f.start[k + 1];
    Vec3 a;
    for (uint32_t i = b; i < e; ++i) a += cross(pos[f.ring[i]] - s, pos[f.ring[i + 1 < e ? i + 1 : b]] - s);
    return a / 6.0;
}

struct MembranePressure {
    std::vector<PressureNode> nodes;
    PressureFans fans;  // triangulated membranes; not in checkpoints yet (the writer refuses them)
    double dp = 0.0;  // [Pa] outside minus inside; > 0 pushes against A (underpressure)
    bool has_nodes() const { return !nodes.empty() || !fans.empty(); }
};

// The pressure's force on each particle in one slot per particle, which the gather adds (and the
// energy ledger reads). Only the nodes' slots are written each step, the others stay zero; so
// the slots are zeroed whenever the node list changes or the pressure is switched on or off.
class PressureForces {
public:
    std::vector<Vec3> force;  // [N] per particle

    // Before a step with n particles: `on` when the pressure acts, `needed` when the slots are
    // read at all (the pressure acts, or the ledger reads the zero slots).
    void prepare(const MembranePressure& mp, std::size_t n, bool on, bool needed);
    // Inside the step's parallel region: this thread's share of the nodes, F = -dp A.
    void apply(const MembranePressure& mp, const std::vector<Vec3>& pos);

private:
    std::vector<PressureNode> seen_;  // the node list the zeroed slots were made for
    std::vector<uint32_t> seen_fans_;  // the fans' loaded nodes the zeroed slots were made for
    bool was_on_ = false;
};

}  // namespace dem
