// Work splitting inside the step's parallel sections (dem/core/thread_team.h). Every split is a
// pure function of the item count and the thread count, and every sum the step forms runs over
// fixed blocks of items, never over a thread's share: results are the same for any number of
// threads.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace dem {

// The calling thread's index and the thread count inside ThreadTeam::run (0 and 1 outside).
namespace detail {
inline thread_local int tls_thread_id = 0;
inline thread_local int tls_thread_count = 1;
}  // namespace detail

inline int thread_id() { return detail::tls_thread_id; }
inline int thread_count() { return detail::tls_thread_count; }

// Thread t's contiguous share [begin, end) of n items among nt threads (a static
// schedule): shares differ by at most one item and follow the thread order.
inline std::pair<int64_t, int64_t> thread_range(int64_t n, int tid, int nt) {
    const int64_t q = n / nt, r = n % nt;
    const int64_t begin = tid * q + (tid < r ? tid : r);
    return {begin, begin + q + (tid < r ? 1 : 0)};
}

// Runs [begin, end) of blocks each thread works on: runs[t] for thread t, ascending.
using BlockRuns = std::vector<std::vector<std::pair<int64_t, int64_t>>>;

// The runs of blocks 0..nb-1 from their owners (owner(b) in [0, nt)).
template <class Owner> inline BlockRuns runs_of(int64_t nb, int nt, Owner&& owner) {
    BlockRuns runs(static_cast<std::size_t>(nt));
    for (int64_t b = 0; b < nb; ++b) {
        auto& r = runs[std::size_t(owner(b))];
        if (!r.empty() && r.back().second == b) ++r.back().second;
        else r.emplace_back(b, b + 1);
    }
    return runs;
}

}  // namespace dem
