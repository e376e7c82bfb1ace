// The laws written once (dem/core/hd.h), compiled by nvcc: on the host here (every machine with
// nvcc, in CI), and on the device when a GPU is present. Both must give the GCC build's bits:
// the same IEEE operations in the same order, no fused multiply-add (-fmad=false here,
// -ffp-contract=off there), correctly rounded division and square root (nvcc's defaults).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include <cuda_runtime.h>

#include "laws_eval.h"

using namespace cuda_test;

namespace {

__global__ void evaluate_all(const LawCase* in, LawResult* out, int n) {
    const int i = int(blockIdx.x * blockDim.x + threadIdx.x);
    if (i < n) out[i] = evaluate(in[i]);
}

bool same_bits(const LawResult& a, const LawResult& b) { return std::memcmp(&a, &b, sizeof(LawResult)) == 0; }

bool have_gpu() {
    int n = 0;
    return cudaGetDeviceCount(&n) == cudaSuccess && n > 0;
}

}  // namespace

TEST(CudaLaws, NvccHostCodeGivesTheBitsOfTheGccBuild) {
    const std::vector<LawCase> cases = make_cases(4096);
    std::size_t differ = 0;
    for (const LawCase& c : cases) differ += !same_bits(evaluate(c), reference(c));
    EXPECT_EQ(differ, 0u) << "of " << cases.size() << " cases";
}

TEST(CudaLaws, DeviceGivesTheBitsOfTheGccBuild) {
    if (!have_gpu()) GTEST_SKIP() << "no CUDA device here: the device half runs where one is lent";
    const std::vector<LawCase> cases = make_cases(4096);
    const int n = int(cases.size());
    LawCase* din = nullptr;
    LawResult* dout = nullptr;
    ASSERT_EQ(cudaMalloc(&din, sizeof(LawCase) * n), cudaSuccess);
    ASSERT_EQ(cudaMalloc(&dout, sizeof(LawResult) * n), cudaSuccess);
    ASSERT_EQ(cudaMemcpy(din, cases.data(), sizeof(LawCase) * n, cudaMemcpyHostToDevice), cudaSuccess);
    evaluate_all<<<(n + 127) / 128, 128>>>(din, dout, n);
    ASSERT_EQ(cudaDeviceSynchronize(), cudaSuccess);
    std::vector<LawResult> got(cases.size());
    ASSERT_EQ(cudaMemcpy(got.data(), dout, sizeof(LawResult) * n, cudaMemcpyDeviceToHost), cudaSuccess);
    cudaFree(din);
    cudaFree(dout);
    std::size_t differ = 0;
    for (int i = 0; i < n; ++i) differ += !same_bits(got[std::size_t(i)], reference(cases[std::size_t(i)]));
    EXPECT_EQ(differ, 0u) << "of " << n << " cases";
}
