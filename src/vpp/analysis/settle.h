// Stationary loops: has W stopped changing from cycle to cycle? (docs/damper.md, "Stationary
// loops"). The first cycles of a damper compact the packing and their loops shrink (the main
// job's damper: W 2608, 2164, 1649 J/m^2, then a band of +-4% around 1538 J/m^2 for cycles 4-8);
// a study that compares designs should compare loops that no longer drift, not whatever cycle the
// run happened to stop at.
//
// A stationary W still scatters from cycle to cycle (the packing rearranges differently each
// time: 2.7% sample sd over cycles 4-8 of that run), so a rule "each change below x%" is either
// never met (x below the scatter) or blind to drift (x above it). The criterion instead asks
// whether the last cycles show a trend or a jump beyond that scatter. With s = tol |m| the
// expected scatter of one cycle's W (tol = analysis.settle_tolerance, m a mean of W), the
// stationary part is the longest tail of consecutive complete cycles a..N (N the last one) grown
// backwards from N, cycle by cycle, while the cycle a that joins passes both tests:
//   level: |W_a - m'| <= z s' sqrt(1 + 1/n'), m' the mean of the n' cycles after a, s' = tol |m'|
//          (a's W lies in the 95% prediction interval of a new cycle drawn like those);
//   trend: over the tail a..N (from 3 cycles on) the least-squares slope b of W against the cycle
//          number satisfies |b| <= z s / sqrt(S_xx), S_xx = sum (k - kbar)^2, m the tail's mean
//          (the slope's 95% interval, for that scatter, contains zero);
// z = 1.96. W is stationary when the tail has at least 3 cycles; W_settled is its mean and the
// settled cycles are the tail. A tail of 3 detects a drift of more than 1.39 tol per cycle (4.2%
// at 3%); longer tails resolve smaller drifts (S_xx grows as n^3).
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "vpp/analysis/analysis.h"

namespace vpp {

// Cycles the stationary tail needs at least (the trend of fewer is not defined).
inline constexpr std::size_t kSettleMinCycles = 3;
// Two-sided 95% normal quantile of the level and trend tests.
inline constexpr double kSettleZ = 1.959963984540054;

struct Settling {
    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    double tolerance = 0.03;     // [-] the tol above: relative scatter of one cycle's W
    std::vector<bool> settled;   // per entry of the cycles given
    int first = 0;               // first settled cycle (its number); 0: none
    std::size_t count = 0;       // settled cycles (the tail's length; 0 when shorter than kSettleMinCycles)
    double W_mean = kNaN;        // [J/m^2] mean W of the settled cycles
    // The longest tail that passed, even when it is too short to count (for the messages):
    int tail_first = 0, tail_last = 0;  // cycle numbers; 0: no complete cycle
    double slope = kNaN;         // [J/m^2 per cycle] least-squares slope of W over the settled tail
    double slope_limit = kNaN;   // [J/m^2 per cycle] z s / sqrt(S_xx) for that tail
};

// Evaluates the criterion over `cycles` in order (a cycle counts as following the previous
// entry only when its number is one more and both are complete; the tail ends at the last
// complete cycle). Throws std::invalid_argument unless 0 < tolerance < 1.
Settling settle_cycles(const std::vector<CycleResult>& cycles, double tolerance);

// The same, and writes each cycle's flag into it (has_settled, settled): cycles.csv then has a
// `settled` column.
Settling mark_settled(std::vector<CycleResult>& cycles, double tolerance);

}  // namespace vpp
