#include "dem/batch/batch_stepper.h"

#include <algorithm>
#include <stdexcept>

#include "dem/core/parallel.h"

namespace dem::batch {

BatchStepper::BatchStepper(int threads, Backend backend) : threads_(threads > 1 ? threads : 1) {
    if (backend == Backend::kEmulated) device_ = std::make_unique<DeviceBatch>(dev::emulated_device(), threads_);
    if (backend == Backend::kCuda) device_ = std::make_unique<DeviceBatch>(dev::cuda_device(), threads_);
}

std::size_t BatchStepper::index_of(const World& world) const {
    for (std::size_t s = 0; s < batch_.systems(); ++s)
        if (batch_.world[s] == &world && !gone_[s]) return s;
    return SIZE_MAX;
}

void BatchStepper::compute_forces(World& world) { arrive(world, Half::kForces); }
void BatchStepper::integrate(World& world) { arrive(world, Half::kMotion); }

void BatchStepper::arrive(World& world, Half half) {
    std::unique_lock<std::mutex> lk(mu_);
    std::size_t s = index_of(world);
    const bool joining = s == SIZE_MAX;
    if (joining) {
        if (half != Half::kForces) throw std::logic_error("batch stepper: integrate() of a World that is not in the batch");
        // Refused here, in the joiner's thread, rather than when the batch is laid out (where it
        // would stop the others).
        if (!world.clumps().empty()) throw std::invalid_argument("batch: a system with clumps is not supported yet (docs/gpu.md)");
        joining_.push_back(&world);
    } else {
        if (half != half_) throw std::logic_error("batch stepper: a member asked for the other half of the step");
        ++arrived_;
    }
    const uint64_t gen = generation_;
    // The last to arrive runs the half (a forces half with nobody else left also runs at once).
    if (half_ == half && arrived_ == active_) run_half();
    // A joiner waits for the forces half that takes it in (perhaps after the members' motion half).
    cv_.wait(lk, [&] {
        if (!joining) return generation_ != gen;
        for (const World* w : joining_)
            if (w == &world) return false;
        return true;
    });
    s = index_of(world);
    if (s != SIZE_MAX && error_[s]) {
        const std::exception_ptr e = error_[s];
        error_[s] = nullptr;
        std::rethrow_exception(e);
    }
}

void BatchStepper::run_half() {
    if (half_ == Half::kForces) {
        // Lay the batch out again when members came or went: every member is waiting here, so
        // their Worlds are the batch's to write.
        bool changed = !joining_.empty();
        for (bool g : gone_) changed |= g;
        if (changed) {
            std::vector<World*> worlds;
            for (std::size_t s = 0; s < batch_.systems(); ++s)
                if (!gone_[s]) {
                    if (device_) device_->pull(batch_, s);
                    batch_.store(s);
                    worlds.push_back(batch_.world[s]);
                }
            worlds.insert(worlds.end(), joining_.begin(), joining_.end());
            joining_.clear();
            batch_ = BatchSystems{};
            for (World* w : worlds) batch_.add(*w);
            gone_.assign(worlds.size(), false);
            error_.assign(worlds.size(), nullptr);
            active_ = worlds.size();
            if (device_) try {
                    device_->load(batch_);
                } catch (...) {
                    for (auto& e : error_) e = std::current_exception();
                }
        }
    }
    const bool forces = half_ == Half::kForces;
    if (device_) {
        // One launch per half for all systems; a system whose host part threw is skipped after.
        std::vector<bool> skip(gone_);
        try {
            if (forces) device_->forces(batch_, skip, error_);
            else device_->motion(batch_, skip, error_);
        } catch (...) {  // the device itself failed: every member hears it
            for (std::size_t s = 0; s < error_.size(); ++s)
                if (!gone_[s] && !error_[s]) error_[s] = std::current_exception();
        }
    } else {
    const int64_t ns = int64_t(batch_.systems());
    const int nt = int(std::min<int64_t>(threads_, std::max<int64_t>(ns, 1)));
    team_.run(nt, [&](int tid) {
        const auto [s0, s1] = thread_range(ns, tid, nt);
        for (int64_t s = s0; s < s1; ++s) {
            if (gone_[std::size_t(s)] || error_[std::size_t(s)]) continue;
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
    half_ = forces ? Half::kMotion : Half::kForces;
    arrived_ = 0;
    ++generation_;
    cv_.notify_all();
}

void BatchStepper::sync(World& world) {
    std::lock_guard<std::mutex> lk(mu_);
    const std::size_t s = index_of(world);
    if (s == SIZE_MAX) return;
    if (device_) device_->pull(batch_, s);
    batch_.store(s);
}

void BatchStepper::leave(World& world) noexcept {
    std::lock_guard<std::mutex> lk(mu_);
    const std::size_t s = index_of(world);
    if (s == SIZE_MAX) return;
    // Usually between its steps; mid-step (its run threw after compute_forces()) the others may
    // be waiting at the motion half: it runs without this one.
    try {
        if (device_) device_->pull(batch_, s);
    } catch (...) {
        // A device that cannot answer leaves the World as the last store left it.
    }
    batch_.store(s);
    gone_[s] = true;
    --active_;
    if (active_ == 0) {
        // Nobody left mid-step: the next member starts a step afresh.
        half_ = Half::kForces;
        arrived_ = 0;
        if (!joining_.empty()) run_half();
        return;
    }
    if (arrived_ == active_) run_half();  // the others were all waiting for this one
}

}  // namespace dem::batch
