// The batch engine's device backend (docs/gpu.md): the systems of a BatchSystems stepped on a
// device (dev::Device: CUDA, or the emulated device whose kernels run on the host). What must be
// decided in one place per system stays World's, on the host, in step()'s order (the walls'
// motion, the rebuild and the broad phase, the contact lifecycle, the wall reactions, the
// prescribed motions, the clock, the ledger's books); the device keeps the state and runs the
// per-index bodies. Per forces half: the touch test on the device, the (particle, candidate)
// pairs found come back, World places them, the placements go to the device as patches; the
// contact kernels, the pressure, the bonds, the gather on the device; back come the slots found
// apart, the wall store, the prescribed particles' forces (and with the ledger its block sums and
// the dashpot forces); World frees the slots and the frees go as patches. Per motion half: the
// integrator on the device, back comes each system's largest move (and with the ledger its sums
// and the velocities); World moves its prescribed particles, they go as patches. At a rebuild or
// a compaction the system's positions and contact state come back first and its lists and stores
// go whole afterwards.
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <memory>
#include <vector>

#include "dem/batch/batch_systems.h"
#include "dem/batch/device_api.h"
#include "dem/core/thread_team.h"

namespace dem::batch {

class DeviceBatch {
public:
    // `threads`: the host threads that share the systems' host parts (World's bookkeeping, each
    // system in one thread: the same bits for any count).
    explicit DeviceBatch(std::unique_ptr<dev::Device> device, int threads = 1);
    ~DeviceBatch();
    DeviceBatch(const DeviceBatch&) = delete;
    DeviceBatch& operator=(const DeviceBatch&) = delete;

    // The systems of b onto the device (b just laid out by add(); b must outlive the use).
    void load(BatchSystems& b);
    // The two halves of every system's step (as step_forces and step_motion); systems with
    // skip[s] are left alone; what a system's host part throws goes to err[s] (it is skipped
    // from then on).
    void forces(BatchSystems& b, const std::vector<bool>& skip, std::vector<std::exception_ptr>& err);
    void motion(BatchSystems& b, const std::vector<bool>& skip, std::vector<std::exception_ptr>& err);
    // `steps` whole steps of every system (the tests' and the benchmarks' loop); rethrows the
    // first system's error.
    void step(BatchSystems& b, uint64_t steps);
    // System s's state from the device into b (particles, bonds) and into its World's contact
    // stores; then b.store(s) hands it to its World.
    void pull(BatchSystems& b, std::size_t s);
    const char* device_name() const { return dev_->name(); }
    uint64_t bytes_up() const { return up_; }      // host -> device since load, [bytes]
    uint64_t bytes_down() const { return down_; }  // device -> host since load, [bytes]
    // Where the time went since load [s]: the host's per-system parts (World's bookkeeping, the
    // patches; wall-clock of the shared loops) and the rest of the halves (the copies each way,
    // the launches and the waits for the kernels).
    double host_seconds() const { return host_s_; }
    double device_seconds() const { return total_s_ - host_s_; }

    struct Sys;
    struct Buf {
        void* p = nullptr;
        std::size_t bytes = 0;
    };

private:
    void ensure(Buf& b, std::size_t bytes, bool keep);
    void put(Buf& b, const void* src, std::size_t bytes);
    void get(void* dst, const void* src, std::size_t bytes);
    void free_all();
    void upload_contacts(BatchSystems& b, std::size_t s);    // the system's stores, candidates, lists whole
    void download_contacts(BatchSystems& b, std::size_t s);  // the stores' state into World's
    void ensure_stores(BatchSystems& b, std::size_t s);      // device stores as large as World's
    void layout_outbox(BatchSystems& b);
    void fill_view(BatchSystems& b, std::size_t s);
    void upload_views();
    void flush_patches();
    struct Patches {
        std::vector<dev::Patch> p;
        std::vector<uint32_t> payload;
    };
    static void patch(Patches& to, void* dst, const void* src, std::size_t bytes);
    static void patch_list(Patches& to, Sys& y, const struct InteractionLists& l, uint32_t i);
    // f(s, patches) for every system s, the systems shared among the host threads.
    template <class F> void each(std::size_t B, F&& f);
    void read_stream();

    std::unique_ptr<dev::Device> dev_;
    dev::Globals g_;
    std::vector<Buf> globals_;
    std::vector<Sys> sys_;
    std::vector<dev::SysView> views_;
    Buf views_buf_, patches_buf_, payload_buf_, wallnow_;
    std::vector<char> staged_;             // the patches' records and payload, for one copy
    std::atomic<bool> views_stale_{true};  // views_ changed since they went up
    std::vector<WallNow> h_wallnow_;  // all systems' walls now, staged for one copy
    std::vector<Patches> patches_;  // per host thread
    Patches merged_;
    int threads_ = 1;
    ThreadTeam team_;
    // The outbox sections (device) and their host copies.
    // One section for what the forces and motion halves bring back besides the stream, laid out
    // [prescribed | wall store | dashpot forces | block sums | velocities] so that each half gets
    // what it reads in one copy (bytes offsets o_*).
    Buf stream_, count_, maxd2_, sec_;
    std::vector<char> h_sec_;
    std::size_t o_presc_ = 0, o_walls_ = 0, o_fv_ = 0, o_sums_ = 0, o_vel_ = 0, o_end_ = 0;
    Vec3* hv(std::size_t o) { return reinterpret_cast<Vec3*>(h_sec_.data() + o); }
    double* hd(std::size_t o) { return reinterpret_cast<double*>(h_sec_.data() + o); }
    std::vector<uint32_t> h_stream_;
    std::vector<uint64_t> h_maxd2_;
    uint64_t stream_cap_ = 0;
    std::atomic<bool> layout_dirty_{true};
    std::atomic<uint64_t> up_{0}, down_{0};
    double host_s_ = 0, total_s_ = 0;
};

}  // namespace dem::batch
