// The threads of a World's step: a small persistent team with a barrier that spins briefly
// and then sleeps.
//
// Why not OpenMP's parallel regions: libgomp's waiting threads spin for about a millisecond
// with the pause instruction before they sleep. On a virtual machine a pause loop makes the
// hypervisor take the core away (pause-loop exiting), and beside any other busy process the
// spinning threads starve the ones doing the work: measured on the project's 2-core machine,
// 2 threads beside two low-priority compiles ran 10x slower than 1 thread (230 against 2,300
// steps/s, grains-in-cylinder N = 1e4), and OMP_WAIT_POLICY=PASSIVE, which users rarely set,
// brought them back (2,500). This team spins without pause for a bounded time that covers the
// usual imbalance of a phase (a few microseconds), then waits on a futex
// (std::atomic::wait), and parks between steps. Results never depend on the team: work is
// split by pure functions of (items, threads) and every sum is formed per fixed block.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

namespace dem {

class ThreadTeam {
public:
    ThreadTeam() = default;
    ~ThreadTeam();
    ThreadTeam(const ThreadTeam&) = delete;
    ThreadTeam& operator=(const ThreadTeam&) = delete;

    // Runs job(tid) for tid = 0 .. nt-1, the caller being thread 0, and returns when all are
    // done. Workers are started on first use and kept (parked) for the next call.
    void run(int nt, const std::function<void(int)>& job);
    // Inside run(): returns when every thread of the call has reached it.
    void barrier();
    // Inside run(): the thread count of the current call.
    int size() const { return nt_.load(std::memory_order_relaxed); }

private:
    void worker(int tid, uint32_t seen);
    void wait_until(const std::atomic<uint32_t>& word, uint32_t old_value);

    std::vector<std::thread> workers_;
    const std::function<void(int)>* job_ = nullptr;
    std::atomic<int> nt_{1};
    alignas(64) std::atomic<uint32_t> generation_{0};  // bumped to start a call
    alignas(64) std::atomic<int> running_{0};          // workers still in the current call
    alignas(64) std::atomic<uint32_t> done_{0};        // bumped when the last worker finishes
    alignas(64) std::atomic<int> arrived_{0};          // barrier: threads arrived
    alignas(64) std::atomic<uint32_t> phase_{0};       // barrier: bumped when all arrived
    bool stop_ = false;
};

// A ThreadTeam as a member of a copyable object (World): a copy gets a new, empty team.
class TeamHandle {
public:
    TeamHandle() : team_(std::make_unique<ThreadTeam>()) {}
    TeamHandle(const TeamHandle&) : TeamHandle() {}
    TeamHandle& operator=(const TeamHandle&) { return *this; }
    TeamHandle(TeamHandle&&) noexcept = default;
    TeamHandle& operator=(TeamHandle&&) noexcept = default;
    ThreadTeam& operator*() const { return *team_; }
    ThreadTeam* operator->() const { return team_.get(); }

private:
    std::unique_ptr<ThreadTeam> team_;
};

}  // namespace dem
