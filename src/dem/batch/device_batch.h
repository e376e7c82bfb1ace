// The batch engine's device backend (docs/gpu.md): the systems of a BatchSystems stepped on a
// device (dev::Device: CUDA, or the emulated device whose kernels run on the host). The device
// keeps the state and runs the step: the per-index bodies, and between layouts the contact
// lifecycle (the touch test, the new contacts' slots in candidate order, the frees, the
// interaction lists) as World's ContactSet does it, the walls' reactions and the ledger's sums,
// so that a forces half is one launch. What must be decided in one place per system with the
// whole state stays World's, on the host, in step()'s order: the walls' motion, the rebuild test
// and the broad phase, the compactions, the prescribed motions, the clock, the ledger's books.
// Per forces half: up, in one copy, each system's reaches and dp, its walls now (and with the
// ledger their next velocities); the forces kernel; down, in one copy, the lifecycles' counts,
// the prescribed particles' forces, the walls' reactions (and with the ledger the block sums).
// Per motion half: up the prescribed particles' positions and velocities at t + dt (World's
// motions); the integrator; down each system's largest move (and with the ledger its sums). At a
// rebuild or a compaction the system's positions and contacts come back whole, World lays them
// out, and they go up whole; World's copy of a system's contacts is otherwise only as current as
// their counts.
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <memory>
#include <vector>

#include "dem/batch/batch_systems.h"
#include "dem/batch/device_api.h"
#include "dem/batch/force_probe.h"
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
    // Chunks (issue 58, docs/gpu.md): every system stepped on until its steps reach until[s] (its
    // caller's next event), the device running up to K steps per launch sequence with no copy and
    // no wait between them, each system stopping on its own where World would find its
    // candidates again or lay its stores out; the host does that (one packed copy each way) and
    // the system goes on. World's clock, moves, walls' reactions, prescribed particles and ledger
    // are current when run() returns, and the bits are World's for any K. Systems with skip[s] are
    // left alone; what a system's host part throws goes to err[s] (it is skipped from then on).
    // The underpressure (World's pressure.dp) is taken at each chunk's start: an air model that
    // changes it every step needs chunks of one step.
    // A caller's probe of forces over the steps of a chunk (its window, force_probe.h): the sums
    // in, summed on by the device, and out; the particles are the system's indices.
    struct Probe {
        ForceProbe sums;
        std::vector<uint32_t> particles;
    };
    void run(BatchSystems& b, const std::vector<uint64_t>& until, int K, const std::vector<bool>& skip,
             std::vector<std::exception_ptr>& err, std::vector<Probe>* probes = nullptr);
    // One launch sequence of run(): the layouts due, then up to K steps of each system that has
    // not reached until[s]. Returns whether any system ran.
    bool run_chunk(BatchSystems& b, const std::vector<uint64_t>& until, int K, const std::vector<bool>& skip,
                   std::vector<std::exception_ptr>& err, std::vector<Probe>* probes = nullptr);
    // `steps` more steps of every system in chunks of K (the tests' and the benchmarks' loop);
    // rethrows the first system's error.
    void run(BatchSystems& b, uint64_t steps, int K);
    uint64_t chunks() const { return chunks_; }  // chunk launches since load
    // System s's state from the device into b (particles, bonds) and into its World's contact
    // stores; then b.store(s) hands it to its World.
    void pull(BatchSystems& b, std::size_t s);
    const char* device_name() const { return dev_->name(); }
    uint64_t bytes_up() const { return up_; }      // host -> device since load, [bytes]
    uint64_t bytes_down() const { return down_; }  // device -> host since load, [bytes]
    // Copies each way and launches since load: each is a wait for the device (its latency).
    uint64_t exchanges() const { return calls_; }
    // Of those, the ones the host waits for (the copies from the device: a copy to the device
    // and a launch return at once).
    uint64_t waits() const { return waits_; }
    // Where the time went since load [s]: the host's per-system parts (World's bookkeeping and
    // the staging; wall-clock of the shared loops) and the rest of the halves (the copies each
    // way, the launches and the waits for the kernels).
    double host_seconds() const { return host_s_; }
    double device_seconds() const { return total_s_ - host_s_; }
    // Finer, for the benchmarks: the kernels' own time [s] (the rest of device_seconds() is the
    // bus, the launches' latency and the waits), the host's parts before and after each half's
    // launch [s] (forces before, forces after, motion before, motion after; the relayouts are in
    // the first), and the relayouts (a system's rebuild or compaction: its contacts down and up).
    double kernel_seconds() const { return dev_->kernel_seconds(); }
    const double* host_part_seconds() const { return part_s_; }
    uint64_t relayouts() const { return relayouts_; }

    struct Sys;
    struct Buf {
        void* p = nullptr;
        std::size_t bytes = 0;
    };

private:
    void ensure(Buf& b, std::size_t bytes);                     // room for bytes (contents not kept)
    void ensure_host(Buf& b, std::size_t bytes);                // the same, page-locked host memory
    void send(void* dst, const void* src, std::size_t bytes);  // host -> device, counted
    void put(Buf& b, const void* src, std::size_t bytes);      // ensure, then send
    void get(void* dst, const void* src, std::size_t bytes);
    void free_all();
    // The system's contacts up whole (stores, candidates, lists, lifecycle counts, materials).
    void upload_contacts(BatchSystems& b, std::size_t s);
    // The system's stores and candidates' slots (and with `positions` its particles' positions)
    // into World's (then its lists are rebuilt by World: a compaction, or engine_relink), in
    // one wait for the device through the staging area `slot` (a host thread's, or pull()'s).
    void download_contacts(BatchSystems& b, std::size_t s, std::size_t slot, bool positions);
    void ensure_stores(BatchSystems& b, std::size_t s);  // device stores with room for every candidate
    void layout_outbox(BatchSystems& b);
    void fill_view(BatchSystems& b, std::size_t s);
    void upload_views();
    // f(s) for every system s, the systems shared among the host threads.
    template <class F> void each(std::size_t B, int part, F&& f);
    void put_life(std::size_t s);  // life_[s] into the outbox's lifecycle section
    void layout_in(BatchSystems& b);  // the sections of what goes up with the forces (in_, h_in_)
    // System s laid out again where World would (a rebuild or a compaction due): its positions
    // and contacts down, World's engine_begin_forces() (the walls at t, the layout), all up again.
    // Returns whether it was.
    bool lay_out_if_due(BatchSystems& b, std::size_t s);
    // System s's walls' and prescribed particles' motions up for a chunk (Sys::refs).
    void upload_refs(BatchSystems& b, std::size_t s, const std::vector<uint32_t>* probe_particles);

    std::unique_ptr<dev::Device> dev_;
    dev::Globals g_;
    std::vector<Buf> globals_;
    std::vector<Sys> sys_;
    std::vector<dev::SysView> views_;
    std::vector<char> forces_on_;  // the systems of the last forces half (its motion half's)
    uint64_t outbox_gen_ = 0, forces_gen_ = 0;  // layouts of the outbox so far, and at the last forces half
    Buf views_buf_;
    std::vector<char> views_up_;  // the views as they last went up
    // What goes up every forces half (in_ on the device, h_in_ staged here): [StepIn per system |
    // walls now | the walls' next velocities (the ledger)], byte offsets o_in_*.
    Buf in_;
    std::vector<char> h_in_;
    std::size_t o_in_now_ = 0, o_in_vnext_ = 0;
    // What goes up every motion half: each prescribed particle's position and velocity at t + dt.
    Buf presc_in_;
    std::vector<Vec3> h_presc_;
    std::vector<std::vector<Vec3>> vnext_scratch_;  // per system
    int threads_ = 1;
    ThreadTeam team_;
    // The outbox (device) and its host copy: one section for what the forces and motion halves
    // bring back, laid out [lifecycles | prescribed | reactions | the forces' totals | the forces'
    // block sums | largest moves | the motion's totals | the motion's block sums] so that each
    // half gets what it reads in one copy (byte offsets o_*). The lifecycles are the device's: the
    // host's copy (life_) is taken after each forces half and changed by a layout (then put back:
    // life_up_).
    Buf sec_;
    Buf h_sec_;  // page-locked (Device::host_alloc): the outbox's copies run at the bus's speed
    char* hs() { return static_cast<char*>(h_sec_.p); }
    // Chunks add two sections in front: [prescribed particles' states | Chunk per system | ...],
    // what a chunk brings back ending where the forces' does.
    std::size_t o_pstate_ = 0, o_chunk_ = 0;
    std::vector<dev::Chunk> h_chunks_;
    uint64_t chunks_ = 0;
    bool chunk_views_ = false;  // fill_view: the views of a chunk
    std::size_t o_life_ = 0, o_presc_ = 0, o_reactions_ = 0, o_ftot_ = 0, o_fsums_ = 0, o_maxd2_ = 0, o_mtot_ = 0,
                o_msums_ = 0, o_end_ = 0;
    // The ledger's totals formed on the device (a batch of dev::kTotalsFrom or more: the block
    // sums, 23 kB a system a step on the paper's damper, stay there).
    bool totals_ = false;
    Vec3* hv(std::size_t o) { return reinterpret_cast<Vec3*>(hs() + o); }
    double* hd(std::size_t o) { return reinterpret_cast<double*>(hs() + o); }
    // Page-locked staging for download_contacts: one per host thread of each(), and pull()'s.
    std::vector<Buf> stage_;
    std::vector<dev::Life> life_;
    std::vector<char> life_up_;
    std::atomic<bool> layout_dirty_{true};
    std::atomic<uint64_t> up_{0}, down_{0}, calls_{0}, waits_{0};
    double host_s_ = 0, total_s_ = 0;
    double part_s_[4] = {0, 0, 0, 0};
    std::atomic<uint64_t> relayouts_{0};
};

}  // namespace dem::batch
