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
    explicit BatchStepper(int threads = 1, Backend backend = Backend::kHost);

    // The halves of world's step (as World::compute_forces() and World::integrate()); each returns
    // when every member's half is done. compute_forces() of a World not in the batch joins it.
    void compute_forces(World& world);
    void integrate(World& world);
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
    enum class Half { kForces, kMotion };
    void arrive(World& world, Half half);
    // Runs the pending half for all members (the lock held): first, before a forces half, the
    // batch laid out again when members joined or left.
    void run_half();
    std::size_t index_of(const World& world) const;  // its system, or SIZE_MAX

    mutable std::mutex mu_;
    std::condition_variable cv_;
    BatchSystems batch_;
    std::vector<bool> gone_;           // per system: its World left
    std::vector<World*> joining_;      // waiting at a forces half to enter the batch
    std::vector<std::exception_ptr> error_;  // per system: what its half threw
    std::size_t active_ = 0;           // systems not gone
    std::size_t arrived_ = 0;          // of them, waiting for the half
    Half half_ = Half::kForces;        // the half the batch runs next
    uint64_t generation_ = 0;          // halves run (waiters wake when it moves on)
    uint64_t launches_ = 0;
    std::size_t most_ = 0;
    int threads_;
    ThreadTeam team_;
    std::unique_ptr<DeviceBatch> device_;  // the device backend (nullptr: the host's)
};

}  // namespace dem::batch
