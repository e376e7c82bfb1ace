// Stationary loops: has W stopped changing from cycle to cycle? (docs/damper.md, "Stationary
// loops"). The first cycles of a damper compact the packing and their loops shrink (W 1275,
// 1066, 1076, 1088 J/m^2 at 0.06 MPa); a study that compares designs should compare loops that
// no longer drift, not whatever cycle the run happened to stop at.
//
// Criterion: with the relative change r_k = |W_k - W_{k-1}| / |W_{k-1}| of cycle k from the one
// before, cycle k is settled when r_k <= tol and r_{k-1} <= tol: three cycles in a row within the
// tolerance of their predecessors (so at the earliest cycle 3). One change below the tolerance
// is not enough: a drifting sequence passes through small steps by chance (1275, 1066, 1076 J/m^2:
// r_3 = 0.9% between two larger steps). A later cycle that jumps again is not settled; W_settled
// is the mean over the settled cycles, wherever they are.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "vpp/analysis.h"

namespace vpp {

struct Settling {
    double tolerance = 0.03;                                     // [-] the tol above
    std::vector<bool> settled;                                   // per entry of the cycles given
    int first = 0;                                               // first settled cycle (its number); 0: none
    std::size_t count = 0;                                       // settled cycles
    double W_mean = std::numeric_limits<double>::quiet_NaN();   // [J/m^2] mean W of the settled cycles
};

// Evaluates the criterion over `cycles` in order (a cycle counts as following the previous
// entry only when its number is one more and both are complete). Throws std::invalid_argument
// unless 0 < tolerance < 1.
Settling settle_cycles(const std::vector<CycleResult>& cycles, double tolerance);

// The same, and writes each cycle's flag into it (has_settled, settled): cycles.csv then has a
// `settled` column.
Settling mark_settled(std::vector<CycleResult>& cycles, double tolerance);

}  // namespace vpp
