// The emulated device (device_api.h): the device backend's kernels compiled by the host compiler,
// one thread per system, its memory host memory. It runs everything of the device backend but the
// CUDA launches, so that every machine tests the backend's exchange with World and the kernels'
// bodies (tests/unit/test_device_batch.cpp) before a GPU runs them.
#include <cstdlib>
#include <cstring>
#include <new>

#include "dem/batch/device_api.h"

#define VPPDEM_KFN
#define VPPDEM_SYNC() ((void)0)
namespace dem::batch::dev {
inline uint64_t vppdem_append(uint64_t* c) { return (*c)++; }
inline void vppdem_max_bits(uint64_t* word, double d2) {
    uint64_t bits;
    std::memcpy(&bits, &d2, 8);
    if (bits > *word) *word = bits;
}
}  // namespace dem::batch::dev
#include "dem/batch/device_kernels.inl"

namespace dem::batch::dev {
namespace {

class Emulated final : public Device {
public:
    const char* name() const override { return "emulated (host)"; }
    void* alloc(std::size_t bytes) override {
        void* p = std::calloc(bytes ? bytes : 1, 1);
        if (!p) throw std::bad_alloc();
        return p;
    }
    void release(void* p) override { std::free(p); }
    void put(void* dst, const void* src, std::size_t bytes) override { if (bytes) std::memcpy(dst, src, bytes); }
    void get(void* dst, const void* src, std::size_t bytes) override { if (bytes) std::memcpy(dst, src, bytes); }
    void copy(void* dst, const void* src, std::size_t bytes) override { if (bytes) std::memmove(dst, src, bytes); }
    void zero(void* dst, std::size_t bytes) override { if (bytes) std::memset(dst, 0, bytes); }
    void apply(const Patch* p, uint32_t n, const uint32_t* payload) override {
        for (uint32_t q = 0; q < n; ++q) apply_patch(p, payload, q);
    }
    void touch(const Globals& g, const SysView* v, int B) override {
        for (int s = 0; s < B; ++s) touch_body(g, v[s], 0, 1);
    }
    void forces(const Globals& g, const SysView* v, int B) override {
        for (int s = 0; s < B; ++s) forces_body(g, v[s], 0, 1);
    }
    void motion(const Globals& g, const SysView* v, int B) override {
        for (int s = 0; s < B; ++s) motion_body(g, v[s], 0, 1);
    }
};

}  // namespace

std::unique_ptr<Device> emulated_device() { return std::make_unique<Emulated>(); }

}  // namespace dem::batch::dev
