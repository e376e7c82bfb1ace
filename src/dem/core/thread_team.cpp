#include "dem/core/thread_team.h"

#include <chrono>

#include "dem/core/parallel.h"

namespace dem {

namespace {
// How long a waiting thread polls before it sleeps. Covers the imbalance of a phase of the
// step (a few microseconds); longer spins only steal time from other work on the machine.
constexpr auto kSpin = std::chrono::microseconds(20);
}  // namespace

ThreadTeam::~ThreadTeam() {
    if (workers_.empty()) return;
    stop_ = true;
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    for (std::thread& t : workers_) t.join();
}

void ThreadTeam::wait_until(const std::atomic<uint32_t>& word, uint32_t old_value) {
    // Plain loads, no pause instruction: a pause loop is what makes a hypervisor deschedule
    // the virtual core (the reason this class exists).
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0;; ++k) {
        if (word.load(std::memory_order_acquire) != old_value) return;
        if ((k & 255) == 255 && std::chrono::steady_clock::now() - t0 > kSpin) break;
    }
    while (word.load(std::memory_order_acquire) == old_value) word.wait(old_value, std::memory_order_acquire);
}

void ThreadTeam::run(int nt, const std::function<void(int)>& job) {
    // The caller may itself be a thread of another team (a sweep's case): keep its identity.
    const int outer_id = detail::tls_thread_id, outer_count = detail::tls_thread_count;
    detail::tls_thread_id = 0;
    detail::tls_thread_count = nt <= 1 ? 1 : nt;
    if (nt <= 1) {
        nt_.store(1, std::memory_order_relaxed);
        job(0);
        detail::tls_thread_id = outer_id;
        detail::tls_thread_count = outer_count;
        return;
    }
    // A new worker starts from the generation before this call's (it may run only after the
    // bump below, and must not take the bump for the one it has seen).
    const uint32_t gen = generation_.load(std::memory_order_relaxed);
    while (int(workers_.size()) < nt - 1)
        workers_.emplace_back(&ThreadTeam::worker, this, int(workers_.size()) + 1, gen);
    nt_.store(nt, std::memory_order_relaxed);
    job_ = &job;
    running_.store(nt - 1, std::memory_order_relaxed);
    const uint32_t done = done_.load(std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    job(0);
    wait_until(done_, done);
    detail::tls_thread_id = outer_id;
    detail::tls_thread_count = outer_count;
}

void ThreadTeam::worker(int tid, uint32_t seen) {
    for (;;) {
        wait_until(generation_, seen);
        seen = generation_.load(std::memory_order_acquire);
        if (stop_) return;
        const int nt = nt_.load(std::memory_order_relaxed);
        if (tid >= nt) continue;  // a larger team than this call needs
        detail::tls_thread_id = tid;
        detail::tls_thread_count = nt;
        (*job_)(tid);
        if (running_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
            done_.fetch_add(1, std::memory_order_release);
            done_.notify_all();
        }
    }
}

void ThreadTeam::barrier() {
    const int nt = nt_.load(std::memory_order_relaxed);
    if (nt <= 1) return;
    const uint32_t phase = phase_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == nt) {
        arrived_.store(0, std::memory_order_relaxed);
        phase_.fetch_add(1, std::memory_order_release);
        phase_.notify_all();
    } else {
        wait_until(phase_, phase);
    }
}

}  // namespace dem
