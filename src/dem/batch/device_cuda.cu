// The batch engine's CUDA device (device_api.h): the phases of device_kernels.inl as kernels over
// the batch (each system one or more thread blocks: the prototype's shape, /work/shared/gpu,
// split further when the batch is small), the memory cudaMalloc'd, the copies and launches on one
// stream. nvcc runs with -fmad=false: the bodies give the host compiler's bits (tests/cuda).
#include <cuda_runtime.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
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

// The phases of device_kernels.inl, each a kernel over B systems of `split` blocks each: block
// b serves system b / split, its threads numbered on from the system's earlier blocks (a system
// of 4,000 particles and contacts is too small for one block to keep an SM busy: split by
// split()). A block has 256 threads unless VPPDEM_CUDA_BLOCK names 128 or 512; the bits do
// not depend on either.
enum Phase { kTouch, kPlace, kPairs, kGather, kRelease, kAdvance, kDashpots, kSums, kTotals, kBegin, kEnd };
template <int T, int P> __global__ void __launch_bounds__(T) k_phase(Globals g, const SysView* v, int split) {
    const SysView& s = v[blockIdx.x / split];
    const int tid = int(blockIdx.x % unsigned(split)) * T + int(threadIdx.x), nt = split * T;
    switch (P) {
        case kTouch: forces_touch(g, s, tid, nt); break;
        case kPlace: forces_place(g, s, tid, nt); break;
        case kPairs: forces_pairs(g, s, tid, nt); break;
        case kGather: forces_gather(g, s, tid, nt); break;
        case kRelease: forces_release(g, s, tid, nt); break;
        case kAdvance: motion_advance(g, s, tid, nt); break;
        case kDashpots: motion_dashpots(g, s, tid, nt); break;
        case kSums: motion_sums(g, s, tid, nt); break;
        case kTotals: motion_totals(g, s, tid, nt); break;
        case kBegin: if (tid == 0) step_begin(g, s); break;
        default: if (tid == 0) step_end(g, s); break;
    }
}
// A chunk in one launch where each system is one block (chunk_body: its K steps with the block's
// barriers between the phases): no launch per phase and per step.
template <int T> __global__ void __launch_bounds__(T) k_chunk(Globals g, const SysView* v, int K) {
    chunk_body(g, v[blockIdx.x], int(threadIdx.x), T, K);
}
int block_threads() {
    const char* e = std::getenv("VPPDEM_CUDA_BLOCK");
    if (!e || !*e) return 256;
    const int t = std::atoi(e);
    if (t != 128 && t != 256 && t != 512)
        throw std::invalid_argument(std::string("VPPDEM_CUDA_BLOCK = ") + e + ": allowed 128, 256 or 512");
    return t;
}
// Blocks per system: VPPDEM_CUDA_SPLIT when set (1 to 64), else enough for about two blocks per
// multiprocessor over the batch, at most 32.
int split_setting() {
    const char* e = std::getenv("VPPDEM_CUDA_SPLIT");
    if (!e || !*e) return 0;
    const int k = std::atoi(e);
    if (k < 1 || k > 64) throw std::invalid_argument(std::string("VPPDEM_CUDA_SPLIT = ") + e + ": allowed 1 to 64");
    return k;
}

void check(cudaError_t e, const char* what) {
    if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA: ") + what + ": " + cudaGetErrorString(e));
}


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
        threads_ = block_threads();
        split_ = split_setting();
        if (const char* c = std::getenv("VPPDEM_CUDA_CHUNK"); c && *c) {
            if (std::string(c) != "phases" && std::string(c) != "kernel")
                throw std::invalid_argument(std::string("VPPDEM_CUDA_CHUNK = ") + c + ": allowed phases or kernel");
            one_launch_ = std::string(c) == "kernel";
        }
        sms_ = p.multiProcessorCount;
        check(cudaEventCreate(&start_), "cudaEventCreate");
        check(cudaEventCreate(&stop_), "cudaEventCreate");
        if (threads_ != 256) {
            const std::size_t len = std::strlen(name_);
            std::snprintf(name_ + len, sizeof name_ - len, " (%d threads per block)", threads_);
        }
    }
    ~Cuda() override {
        cudaEventDestroy(start_);
        cudaEventDestroy(stop_);
        cudaStreamDestroy(stream_);
    }
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
    // The host reads or rewrites its buffers right after a copy. From pageable memory (ours) to
    // the device, cudaMemcpyAsync returns once the source is staged, so the host may rewrite it at
    // once and no wait is needed (the stream keeps the copy before the next launch); from the
    // device the host waits for the data.
    void put(void* dst, const void* src, std::size_t bytes) override {
        if (!bytes) return;
        check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, stream_), "copy to the device");
    }
    void get(void* dst, const void* src, std::size_t bytes) override {
        get_async(dst, src, bytes);
        wait();
    }
    void* host_alloc(std::size_t bytes) override {
        void* p = nullptr;
        check(cudaMallocHost(&p, bytes ? bytes : 1), "cudaMallocHost");
        return p;
    }
    void host_release(void* p) override {
        cudaStreamSynchronize(stream_);
        cudaFreeHost(p);
    }
    void get_async(void* dst, const void* src, std::size_t bytes) override {
        if (!bytes) return;
        check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, stream_), "copy from the device");
    }
    void wait() override {
        check(cudaStreamSynchronize(stream_), "the copies from the device");
        take_kernel_time();
    }
    double kernel_seconds() override {
        check(cudaStreamSynchronize(stream_), "the kernels' time");
        take_kernel_time();
        return kernel_s_;
    }
    void forces(const Globals& g, const SysView* v, int B) override {
        if (B <= 0) return;
        begin();
        const int k = split(B);
        phase<kTouch>(g, v, B, k);
        phase<kPlace>(g, v, B, 1);  // one thread per system
        phase<kPairs>(g, v, B, k);
        phase<kGather>(g, v, B, k);
        phase<kRelease>(g, v, B, k);
        end("the force kernels");
    }
    void motion(const Globals& g, const SysView* v, int B) override {
        if (B <= 0) return;
        begin();
        const int k = split(B);
        phase<kAdvance>(g, v, B, k);
        phase<kDashpots>(g, v, B, k);
        phase<kSums>(g, v, B, k);
        phase<kTotals>(g, v, B, 1);  // (returns at once where a view has no totals)
        end("the motion kernels");
    }

    // A chunk: K steps' launches queued on the stream, no copy and no wait between them (a
    // stopped system's kernels return at once).
    void chunk(const Globals& g, const SysView* v, int B, int K) override {
        if (B <= 0) return;
        begin();
        const int k = split(B);
        // A batch that fills the multiprocessors with a block per system runs the chunk as one
        // launch (VPPDEM_CUDA_CHUNK=phases: a launch per phase and step, for measurements).
        if (one_launch_ && (split_ == 1 || (split_ == 0 && B >= sms_))) {
            const dim3 grid{unsigned(B)};
            if (threads_ == 128) k_chunk<128><<<grid, 128, 0, stream_>>>(g, v, K);
            else if (threads_ == 512) k_chunk<512><<<grid, 512, 0, stream_>>>(g, v, K);
            else k_chunk<256><<<grid, 256, 0, stream_>>>(g, v, K);
            end("the chunk kernel");
            return;
        }
        for (int step = 0; step < K; ++step) {
            phase<kBegin>(g, v, B, 1);
            phase<kTouch>(g, v, B, k);
            phase<kPlace>(g, v, B, 1);
            phase<kPairs>(g, v, B, k);
            phase<kGather>(g, v, B, k);
            phase<kRelease>(g, v, B, k);
            phase<kAdvance>(g, v, B, k);
            phase<kDashpots>(g, v, B, k);
            phase<kSums>(g, v, B, k);
            phase<kTotals>(g, v, B, 1);
            phase<kEnd>(g, v, B, 1);
        }
        end("the chunk's kernels");
    }

private:
    int split(int B) const {
        if (split_) return split_;
        const int k = (2 * sms_ + B - 1) / B;
        return k < 1 ? 1 : k > 32 ? 32 : k;
    }
    template <int P> void phase(const Globals& g, const SysView* v, int B, int k) {
        const dim3 grid(unsigned(B) * unsigned(k));
        if (threads_ == 128) k_phase<128, P><<<grid, 128, 0, stream_>>>(g, v, k);
        else if (threads_ == 512) k_phase<512, P><<<grid, 512, 0, stream_>>>(g, v, k);
        else k_phase<256, P><<<grid, 256, 0, stream_>>>(g, v, k);
    }
    void begin() { check(cudaEventRecord(start_, stream_), "cudaEventRecord"); }
    void end(const char* what) {
        check(cudaGetLastError(), what);
        check(cudaEventRecord(stop_, stream_), "cudaEventRecord");
        timed_ = true;
    }
    // The last launch's time, once the stream has passed it.
    void take_kernel_time() {
        if (!timed_) return;
        float ms = 0;
        check(cudaEventElapsedTime(&ms, start_, stop_), "cudaEventElapsedTime");
        kernel_s_ += 1e-3 * double(ms);
        timed_ = false;
    }
    cudaStream_t stream_ = nullptr;
    int threads_ = 256;
    int split_ = 0;  // blocks per system (0: split()'s choice)
    bool one_launch_ = true;  // a chunk of one block per system as one launch (k_chunk)
    int sms_ = 1;    // the device's multiprocessors
    cudaEvent_t start_ = nullptr, stop_ = nullptr;  // around the last launch
    bool timed_ = false;                           // its time not yet taken
    double kernel_s_ = 0;                          // [s]
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
