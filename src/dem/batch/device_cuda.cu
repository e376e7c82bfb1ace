// The batch engine's CUDA device (device_api.h): the kernels of device_kernels.inl with one thread
// block per system (body- and contact-parallel within the block: the prototype's 773,000
// system-steps/s shape, /work/shared/gpu), the memory cudaMalloc'd, the copies on one stream.
// nvcc runs with -fmad=false: the bodies give the host compiler's bits (tests/cuda).
#include <cuda_runtime.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#define VPPDEM_KFN __device__
#define VPPDEM_SYNC() __syncthreads()
namespace dem::batch::dev {
__device__ inline uint64_t vppdem_append(uint64_t* c) {
    return atomicAdd(reinterpret_cast<unsigned long long*>(c), 1ull);
}
__device__ inline void vppdem_max_bits(uint64_t* word, double d2) {
    // Non-negative doubles order as their bits.
    atomicMax(reinterpret_cast<unsigned long long*>(word), static_cast<unsigned long long>(__double_as_longlong(d2)));
}
}  // namespace dem::batch::dev
#include "dem/batch/device_kernels.inl"

namespace dem::batch::dev {
namespace {

constexpr int kThreads = 256;  // per system's block

void check(cudaError_t e, const char* what) {
    if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA: ") + what + ": " + cudaGetErrorString(e));
}

__global__ void __launch_bounds__(kThreads) k_forces(Globals g, const SysView* v) { forces_body(g, v[blockIdx.x], int(threadIdx.x), int(blockDim.x)); }
__global__ void __launch_bounds__(kThreads) k_motion(Globals g, const SysView* v) { motion_body(g, v[blockIdx.x], int(threadIdx.x), int(blockDim.x)); }

class Cuda final : public Device {
public:
    Cuda() {
        int n = 0;
        check(cudaGetDeviceCount(&n), "cudaGetDeviceCount");
        if (n == 0) throw std::runtime_error("CUDA: no device");
        check(cudaSetDevice(0), "cudaSetDevice");
        cudaDeviceProp p{};
        check(cudaGetDeviceProperties(&p, 0), "cudaGetDeviceProperties");
        std::snprintf(name_, sizeof name_, "CUDA %s", p.name);
        check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
    }
    ~Cuda() override { cudaStreamDestroy(stream_); }
    const char* name() const override { return name_; }
    void* alloc(std::size_t bytes) override {
        void* p = nullptr;
        check(cudaMalloc(&p, bytes ? bytes : 1), "cudaMalloc");
        check(cudaMemsetAsync(p, 0, bytes ? bytes : 1, stream_), "cudaMemset");
        return p;
    }
    void release(void* p) override {
        cudaStreamSynchronize(stream_);
        cudaFree(p);
    }
    // The copies are synchronous for the host (the host reads or rewrites its buffers right after).
    void put(void* dst, const void* src, std::size_t bytes) override {
        if (!bytes) return;
        check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, stream_), "copy to the device");
        check(cudaStreamSynchronize(stream_), "copy to the device");
    }
    void get(void* dst, const void* src, std::size_t bytes) override {
        if (!bytes) return;
        check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, stream_), "copy from the device");
        check(cudaStreamSynchronize(stream_), "copy from the device");
    }
    void forces(const Globals& g, const SysView* v, int B) override { launch(k_forces, g, v, B, "the force kernel"); }
    void motion(const Globals& g, const SysView* v, int B) override { launch(k_motion, g, v, B, "the motion kernel"); }

private:
    template <class K> void launch(K kernel, const Globals& g, const SysView* v, int B, const char* what) {
        if (B <= 0) return;
        kernel<<<B, kThreads, 0, stream_>>>(g, v);
        check(cudaGetLastError(), what);
    }
    cudaStream_t stream_ = nullptr;
    char name_[300] = {};
};

}  // namespace

std::unique_ptr<Device> cuda_device() {
    const char* why = nullptr;
    if (cuda_devices(&why) == 0) throw std::runtime_error(std::string("no CUDA device: ") + why);
    return std::make_unique<Cuda>();
}
bool cuda_built() { return true; }
int cuda_devices(const char** why) {
    int n = 0;
    const cudaError_t e = cudaGetDeviceCount(&n);
    if (e != cudaSuccess) {
        if (why) *why = cudaGetErrorString(e);
        return 0;
    }
    if (n == 0 && why) *why = "cudaGetDeviceCount gives 0";
    return n;
}

}  // namespace dem::batch::dev
