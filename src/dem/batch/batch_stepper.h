// Lockstep driving of a batch (docs/gpu.md): independent runs, each in its own thread and each
// stepping its own World as it always does (compute_forces, read what it records, integrate),
// hand their two half steps to one BatchStepper, which advances all of them at once when every
// member has asked: one batch launch per half step for all the runs of a study. A run joins with
// its first compute_forces() and leaves with leave(); members come and go between steps. Between
// its half steps a run may read and change its World as ever (wall reactions, the prescribed
// particles' forces, the energy ledger, parameters) but for the particles' state, which is the
// batch's until sync() (or leave()) hands it back.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <vector>

#include "dem/batch/batch_systems.h"
#include "dem/batch/device_batch.h"
#include "dem/core/thread_team.h"
#include "dem/world/world.h"

namespace dem::batch {

class BatchStepper {
public:
    // Where the batch runs: the host backend (step_forces, step_motion: the systems shared among
    // threads), the device backend on a CUDA device (DeviceBatch; a vppdem built with
    // VPPDEM_CUDA), or the device backend on the emulated device (its kernels on the host: the
    // tests' stand-in for a GPU).
    enum class Backend { kHost, kCuda, kEmulated };
    // `threads`: the host backend's threads for one launch (the systems shared among them).
    // kCuda without a CUDA build or without a device throws, saying which.
    // `chunk`: a device backend's longest chunk [steps] (compute_forces with an event).
    explicit BatchStepper(int threads = 1, Backend backend = Backend::kHost, int chunk = 256);

    // The halves of world's step (as World::compute_forces() and World::integrate()); each returns
    // when its half is done. compute_forces() of a World not in the batch joins it.
    void compute_forces(World& world);
    void integrate(World& world);
    // On a device backend (chunked()): the World stepped on by whole steps until its steps reach
    // `until` (the caller's next event), in chunks that the device runs without the host
    // (DeviceBatch::run), `probe` (may be null) summing the forces of those steps as the caller
    // would have; then its forces half at that step, as compute_forces(world). The others step on
    // meanwhile: each chunk runs as far as the nearest member's event (at most the chunk setting).
    void compute_forces(World& world, uint64_t until, DeviceBatch::Probe* probe);
    bool chunked() const { return device_ != nullptr; }
    // World's particle arrays (state and forces) and bonds made current.
    void sync(World& world);
    // Hands world back (as sync) and leaves the batch, between its steps or between the halves of
    // one (a run that threw: the others go on); no-op for a World not in it.
    void leave(World& world) noexcept;

    uint64_t launches() const { return launches_; }        // batch half steps run so far
    // The most systems one launch stepped.
    std::size_t most_systems() const {
        std::lock_guard<std::mutex> lk(mu_);
        return most_;
    }
    // Worlds waiting at a forces half to join (a test's way to make two runs overlap for sure).
    std::size_t joining() const {
        std::lock_guard<std::mutex> lk(mu_);
        return joining_.size();
    }

private:
    // What a member waits for: nothing (it runs on its own), its forces half (after whole steps
    // up to its event), its motion half.
    enum class Want { kNone, kForces, kMotion };
    struct Request {
        Want want = Want::kNone;
        uint64_t until = 0;                   // the step of its forces half
        DeviceBatch::Probe* probe = nullptr;  // the caller's, while it waits
    };
    void arrive(World& world, Want want, uint64_t until, DeviceBatch::Probe* probe);
    // Serves the waiting members once every member waits (the lock held): first the batch laid
    // out again when members joined or left (when none is between its halves); then the motion
    // halves asked for, else the forces halves of the members at their events, else a chunk of
    // the others, until some member can go on.
    void run_round(std::unique_lock<std::mutex>& lk);
    void lay_out();
    std::size_t index_of(const World& world) const;  // its system, or SIZE_MAX

    mutable std::mutex mu_;
    std::condition_variable cv_;
    BatchSystems batch_;
    std::vector<bool> gone_;           // per system: its World left
    std::vector<World*> joining_;      // waiting at a forces half to enter the batch
    std::vector<Request> joining_request_;
    std::vector<std::exception_ptr> error_;  // per system: what its half threw
    std::vector<Request> request_;     // per system
    std::vector<char> mid_;            // per system: between its halves (its motion half next)
    std::size_t active_ = 0;           // systems not gone
    std::size_t arrived_ = 0;          // of them, waiting
    uint64_t launches_ = 0;
    int chunk_ = 256;
    bool in_round_ = false;            // a member serves the round (the lock let go during a chunk)
    bool chunk_running_ = false;       // the device runs a chunk (the lock let go)
    std::size_t most_ = 0;
    int threads_;
    ThreadTeam team_;
    std::unique_ptr<DeviceBatch> device_;  // the device backend (nullptr: the host's)
};

}  // namespace dem::batch
