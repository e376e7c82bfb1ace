// The energy ledger's block sums as World's SIMD kernels form them (dem/kernels/kernels.h, for_blocks):
// within a block of kernels::kBlock entries, entry e adds its K terms to virtual lane e % 8 in entry
// order, then the 8 lanes are added in order. One source for the batch engine's host backend
// (batch_systems.cpp) and the ledger's own sums that the device forms too (EnergyBook: the
// dashpots' forward halves); the device kernels form the same sums a thread per (block, term)
// (device_kernels.inl: lane_job), and the tests hold them to these bits.
#pragma once

#include <cstdint>

#include "dem/core/hd.h"

namespace dem {

template <int K> struct LaneSums {
    double lane[K][8];
    VPPDEM_HD LaneSums() {
        for (int k = 0; k < K; ++k)
            for (int l = 0; l < 8; ++l) lane[k][l] = 0.0;
    }
    // Entry e's K terms t[0..K).
    VPPDEM_HD void add(int64_t e, const double* t) {
        for (int k = 0; k < K; ++k) lane[k][e % 8] += t[k];
    }
    // The block's K sums into out (each block starts with a fresh LaneSums).
    VPPDEM_HD void flush(double* out) const {
        for (int k = 0; k < K; ++k) {
            double sum = 0.0;
            for (int l = 0; l < 8; ++l) sum += lane[k][l];
            out[k] = sum;
        }
    }
};

// The sum of term(e) over the entries e0 .. e1 of one block (e0 a multiple of 8), as LaneSums
// forms it.
template <class Term> VPPDEM_HD inline double lane_block_sum(int64_t e0, int64_t e1, Term&& term) {
    LaneSums<1> sums;
    for (int64_t e = e0; e < e1; ++e) {
        const double t = term(e);
        sums.add(e, &t);
    }
    double out;
    sums.flush(&out);
    return out;
}

}  // namespace dem
