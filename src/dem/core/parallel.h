// Work splitting inside the step's OpenMP parallel regions. Every split is a pure function of
// the item count and the thread count, and every sum the step forms runs over fixed blocks of
// items, never over a thread's share: results are the same for any number of threads.
#pragma once

#include <cstdint>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace dem {

inline int thread_id() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

inline int thread_count() {
#ifdef _OPENMP
    return omp_get_num_threads();
#else
    return 1;
#endif
}

// Thread t's contiguous share [begin, end) of n items among nt threads (OpenMP's static
// schedule): shares differ by at most one item and follow the thread order.
inline std::pair<int64_t, int64_t> thread_range(int64_t n, int tid, int nt) {
    const int64_t q = n / nt, r = n % nt;
    const int64_t begin = tid * q + (tid < r ? tid : r);
    return {begin, begin + q + (tid < r ? 1 : 0)};
}

}  // namespace dem
