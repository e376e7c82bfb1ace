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

namespace dem {

struct PressureNode {
    uint32_t node;                    // the loaded particle S
    std::array<uint32_t, 4> ring;     // P1..P4, cyclic; A points to the side dp pushes from
};

inline Vec3 tributary_area(const std::vector<Vec3>& pos, const PressureNode& q) {
    return cross(pos[q.ring[0]] - pos[q.ring[2]], pos[q.ring[1]] - pos[q.ring[3]]);
}

struct MembranePressure {
    std::vector<PressureNode> nodes;
    double dp = 0.0;  // [Pa] outside minus inside; > 0 pushes against A (underpressure)
};

}  // namespace dem
