// The emulated device (device_api.h): the device backend's kernels compiled by the host compiler,
// its memory host memory. It runs everything of the device backend but the CUDA launches, so that
// every machine tests the backend's exchange with World and the kernels' bodies
// (tests/physics/test_batch_damper.cpp) before a GPU runs them. With threads_per_block = 1 a
// block is one thread; with more, each system's block is that many threads meeting at the
// kernels' barriers (std::barrier) and appending with atomics, as a GPU's block does: the
// kernels' split of the work among a block's threads and their barriers are tested too.
#include <atomic>
#include <barrier>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>
#include <thread>
#include <vector>

#include "dem/batch/device_api.h"

namespace dem::batch::dev {
namespace {
thread_local std::barrier<>* block_barrier = nullptr;  // the block's barrier (nullptr: one thread)
}  // namespace
inline void vppdem_sync() {
    if (block_barrier) block_barrier->arrive_and_wait();
}
inline uint64_t vppdem_append(uint64_t* c) { return std::atomic_ref<uint64_t>(*c).fetch_add(1); }
inline void vppdem_max_bits(uint64_t* word, double d2) {
    uint64_t bits;
    std::memcpy(&bits, &d2, 8);
    std::atomic_ref<uint64_t> w(*word);
    uint64_t old = w.load();
    while (bits > old && !w.compare_exchange_weak(old, bits)) {
    }
}
}  // namespace dem::batch::dev
#define VPPDEM_KFN
#define VPPDEM_SYNC() vppdem_sync()
#include "dem/batch/device_kernels.inl"

namespace dem::batch::dev {
namespace {

class Emulated final : public Device {
public:
    explicit Emulated(int threads_per_block) : nt_(threads_per_block > 1 ? threads_per_block : 1) {}
    const char* name() const override { return nt_ > 1 ? "emulated (host, threads per block)" : "emulated (host)"; }
    void* alloc(std::size_t bytes) override {
        void* p = std::calloc(bytes ? bytes : 1, 1);
        if (!p) throw std::bad_alloc();
        return p;
    }
    void release(void* p) override { std::free(p); }
    void put(void* dst, const void* src, std::size_t bytes) override { if (bytes) std::memcpy(dst, src, bytes); }
    void get(void* dst, const void* src, std::size_t bytes) override { if (bytes) std::memcpy(dst, src, bytes); }
    void* host_alloc(std::size_t bytes) override { return alloc(bytes); }
    void host_release(void* p) override { std::free(p); }
    void get_async(void* dst, const void* src, std::size_t bytes) override { get(dst, src, bytes); }
    void wait() override {}
    void forces(const Globals& g, const SysView* v, int B) override {
        launch(B, [&](int s, int tid, int nt) { forces_body(g, v[s], tid, nt); });
    }
    void motion(const Globals& g, const SysView* v, int B) override {
        launch(B, [&](int s, int tid, int nt) { motion_body(g, v[s], tid, nt); });
    }
    void chunk(const Globals& g, const SysView* v, int B, int K) override {
        launch(B, [&](int s, int tid, int nt) { chunk_body(g, v[s], tid, nt, K); });
    }
    double kernel_seconds() override { return kernel_s_; }

private:
    // The blocks one after the other; a block's threads together.
    template <class Body> void launch(int B, Body&& body) {
        const auto t0 = std::chrono::steady_clock::now();
        run(B, body);
        kernel_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    template <class Body> void run(int B, Body& body) {
        for (int s = 0; s < B; ++s) {
            if (nt_ == 1) {
                body(s, 0, 1);
                continue;
            }
            std::barrier<> bar(nt_);
            std::vector<std::thread> block;
            for (int tid = 0; tid < nt_; ++tid)
                block.emplace_back([&, tid] {
                    block_barrier = &bar;
                    body(s, tid, nt_);
                    block_barrier = nullptr;
                });
            for (std::thread& t : block) t.join();
        }
    }
    int nt_;
    double kernel_s_ = 0;  // [s]
};

}  // namespace

std::unique_ptr<Device> emulated_device(int threads_per_block) { return std::make_unique<Emulated>(threads_per_block); }

}  // namespace dem::batch::dev
