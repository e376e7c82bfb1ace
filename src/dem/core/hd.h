// VPPDEM_HD marks a function of the step's physics as callable on the host and on a CUDA device:
// `__host__ __device__` when nvcc compiles the file, nothing otherwise. The laws (contact, bond,
// integration, pressure, rigid rotation) are written once as such functions; the CPU's kernels
// (GCC, SIMD lanes) and the batch engine's kernels (nvcc, or their host backend) call the same
// source (docs/gpu.md). Every operation in them is exactly rounded IEEE arithmetic; nvcc must be
// run with -fmad=false (as GCC with -ffp-contract=off) for the bits to agree.
#pragma once

#if defined(__CUDACC__)
#define VPPDEM_HD __host__ __device__
#else
#define VPPDEM_HD
#endif
