#include "dem/batch/batch_stepper.h"

#include <algorithm>
#include <stdexcept>

#include "dem/core/parallel.h"

namespace dem::batch {

BatchStepper::BatchStepper(int threads, Backend backend, int chunk)
    : chunk_(chunk > 0 ? chunk : 1), threads_(threads > 1 ? threads : 1) {
    if (backend == Backend::kEmulated) device_ = std::make_unique<DeviceBatch>(dev::emulated_device(), threads_);
    if (backend == Backend::kCuda) device_ = std::make_unique<DeviceBatch>(dev::cuda_device(), threads_);
}

std::size_t BatchStepper::index_of(const World& world) const {
    for (std::size_t s = 0; s < batch_.systems(); ++s)
        if (batch_.world[s] == &world && !gone_[s]) return s;
    return SIZE_MAX;
}

void BatchStepper::compute_forces(World& world) { arrive(world, Want::kForces, 0, nullptr); }

void BatchStepper::compute_forces(World& world, uint64_t until, DeviceBatch::Probe* probe) {
    if (!device_ && until > world.steps)
        throw std::logic_error("batch stepper: whole steps to an event need a device backend (chunked())");
    arrive(world, Want::kForces, until, probe);
}

void BatchStepper::integrate(World& world) { arrive(world, Want::kMotion, 0, nullptr); }

void BatchStepper::arrive(World& world, Want want, uint64_t until, DeviceBatch::Probe* probe) {
    std::unique_lock<std::mutex> lk(mu_);
    std::size_t s = index_of(world);
    if (s == SIZE_MAX) {
        if (want != Want::kForces) throw std::logic_error("batch stepper: integrate() of a World that is not in the batch");
        // Refused here, in the joiner's thread, rather than when the batch is laid out (where it
        // would stop the others).
        if (!world.clumps().empty()) throw std::invalid_argument("batch: a system with clumps is not supported yet (docs/gpu.md)");
        joining_.push_back(&world);
        joining_request_.push_back({want, until, probe});
    } else {
        if ((want == Want::kMotion) != bool(mid_[s]))
            throw std::logic_error("batch stepper: a member asked for the other half of the step");
        request_[s] = {want, until, probe};
        ++arrived_;
    }
    // The last to arrive serves the round (a joiner with nobody else in the batch at once).
    if (arrived_ == active_ && !in_round_) run_round(lk);
    cv_.wait(lk, [&] {
        const std::size_t k = index_of(world);
        return k != SIZE_MAX && request_[k].want == Want::kNone;
    });
    s = index_of(world);
    if (error_[s]) {
        const std::exception_ptr e = error_[s];
        error_[s] = nullptr;
        std::rethrow_exception(e);
    }
}

void BatchStepper::lay_out() {
    // Every member is waiting at a forces half here, so their Worlds are the batch's to write.
    std::vector<World*> worlds;
    std::vector<Request> requests;
    for (std::size_t s = 0; s < batch_.systems(); ++s)
        if (!gone_[s]) {
            if (device_) device_->pull(batch_, s);
            batch_.store(s);
            worlds.push_back(batch_.world[s]);
            requests.push_back(request_[s]);
        }
    worlds.insert(worlds.end(), joining_.begin(), joining_.end());
    requests.insert(requests.end(), joining_request_.begin(), joining_request_.end());
    joining_.clear();
    joining_request_.clear();
    batch_ = BatchSystems{};
    for (World* w : worlds) batch_.add(*w);
    gone_.assign(worlds.size(), false);
    error_.assign(worlds.size(), nullptr);
    request_ = requests;
    mid_.assign(worlds.size(), 0);
    active_ = worlds.size();
    arrived_ = active_;
    if (device_) try {
            device_->load(batch_);
        } catch (...) {
            for (auto& e : error_) e = std::current_exception();
        }
}

void BatchStepper::run_round(std::unique_lock<std::mutex>& lk) {
    in_round_ = true;
    for (;;) {
        bool changed = !joining_.empty(), mid = false;
        for (std::size_t s = 0; s < gone_.size(); ++s) {
            changed |= gone_[s];
            mid |= !gone_[s] && mid_[s];
        }
        if (changed && !mid) lay_out();
        const std::size_t B = batch_.systems();
        bool released = false;
        const auto release = [&](std::size_t s) {
            request_[s].want = Want::kNone;
            --arrived_;
            released = true;
        };
        // A member whose last launch threw hears it now.
        for (std::size_t s = 0; s < B; ++s)
            if (!gone_[s] && request_[s].want != Want::kNone && error_[s]) release(s);
        if (released) break;
        const auto serve = [&](Want want, auto&& pick) {
            std::vector<bool> skip(B, true);
            bool any = false;
            for (std::size_t s = 0; s < B; ++s)
                if (!gone_[s] && request_[s].want == want && pick(s)) {
                    skip[s] = false;
                    any = true;
                }
            if (!any) return false;
            const bool forces = want == Want::kForces;
            if (device_) {
                // One launch for the served systems; a system whose host part threw is skipped after.
                try {
                    if (forces) device_->forces(batch_, skip, error_);
                    else device_->motion(batch_, skip, error_);
                } catch (...) {  // the device itself failed: every member hears it
                    for (std::size_t s = 0; s < B; ++s)
                        if (!gone_[s] && !error_[s]) error_[s] = std::current_exception();
                }
            } else {
                const int64_t ns = int64_t(B);
                const int nt = int(std::min<int64_t>(threads_, std::max<int64_t>(ns, 1)));
                team_.run(nt, [&](int tid) {
                    const auto [s0, s1] = thread_range(ns, tid, nt);
                    for (int64_t s = s0; s < s1; ++s) {
                        if (skip[std::size_t(s)] || error_[std::size_t(s)]) continue;
                        try {
                            if (forces) step_forces(batch_, std::size_t(s));
                            else step_motion(batch_, std::size_t(s));
                        } catch (...) {
                            error_[std::size_t(s)] = std::current_exception();
                        }
                    }
                });
            }
            ++launches_;
            most_ = std::max(most_, active_);
            for (std::size_t s = 0; s < B; ++s)
                if (!skip[s]) {
                    mid_[s] = forces;
                    release(s);
                }
            return true;
        };
        // A chunk of the members not at their events, as far as the nearest event (at most K).
        const auto chunk = [&](uint64_t K) {
            std::vector<bool> skip(B, true);
            std::vector<uint64_t> until(B, 0);
            std::vector<DeviceBatch::Probe> probes(B);
            bool any = false;
            for (std::size_t s = 0; s < B; ++s) {
                const Request& r = request_[s];
                if (gone_[s] || r.want != Want::kForces) continue;
                const uint64_t steps = batch_.world[s]->steps;
                if (steps >= r.until) continue;
                skip[s] = false;
                until[s] = r.until;
                K = std::min(K, r.until - steps);
                if (r.probe) probes[s] = *r.probe;
                any = true;
            }
            if (!any || !device_) return false;
            // The lock is let go while the device runs: a run may come to join meanwhile (it
            // waits in joining_ and enters at the next turn of this loop); the members are
            // waiting, and sync() and leave() wait for the chunk.
            chunk_running_ = true;
            lk.unlock();
            std::exception_ptr failed;
            try {
                device_->run_chunk(batch_, until, int(K), skip, error_, &probes);
            } catch (...) {
                failed = std::current_exception();
            }
            lk.lock();
            chunk_running_ = false;
            cv_.notify_all();
            if (failed)
                for (std::size_t s = 0; s < B; ++s)
                    if (!gone_[s] && !error_[s]) error_[s] = failed;
            for (std::size_t s = 0; s < B; ++s)
                if (!skip[s] && request_[s].probe) request_[s].probe->sums = probes[s].sums;
            most_ = std::max(most_, active_);
            return true;
        };
        const bool motion = serve(Want::kMotion, [](std::size_t) { return true; });
        const bool forces = serve(Want::kForces, [&](std::size_t s) { return batch_.world[s]->steps >= request_[s].until; });
        if (motion || forces) {
            // Members stepping half by half set the pace: the others go a step with each of
            // their forces halves.
            if (forces) chunk(1);
            // A member served may have come back while the lock was let go: then all wait again
            // and this round goes on (nobody else would start one).
            if (arrived_ == active_ && active_ > 0) continue;
            break;
        }
        if (!chunk(uint64_t(chunk_))) break;  // (nobody waits: the last member left)
    }
    in_round_ = false;
    cv_.notify_all();
}

void BatchStepper::sync(World& world) {
    std::unique_lock<std::mutex> lk(mu_);
    cv_.wait(lk, [&] { return !chunk_running_; });
    const std::size_t s = index_of(world);
    if (s == SIZE_MAX) return;
    if (device_) device_->pull(batch_, s);
    batch_.store(s);
}

void BatchStepper::leave(World& world) noexcept {
    std::unique_lock<std::mutex> lk(mu_);
    cv_.wait(lk, [&] { return !chunk_running_; });
    const std::size_t s = index_of(world);
    if (s == SIZE_MAX) return;
    // Usually between its steps; mid-step (its run threw after compute_forces()) the others go on
    // without this one.
    try {
        if (device_) device_->pull(batch_, s);
    } catch (...) {
        // A device that cannot answer leaves the World as the last store left it.
    }
    batch_.store(s);
    gone_[s] = true;
    if (request_[s].want != Want::kNone) --arrived_;
    request_[s].want = Want::kNone;
    --active_;
    // The others were all waiting for this one.
    if (arrived_ == active_ && (active_ > 0 || !joining_.empty()) && !in_round_) {
        try {
            run_round(lk);
        } catch (...) {
            // (a layout's or a launch's failure is each member's error already)
        }
    }
}

}  // namespace dem::batch
