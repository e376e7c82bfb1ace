// Wall-clock time per phase of World::step() (params.profile), so a user sees where a run's
// time goes. Off by default: then each lap() is one predictable branch.
// With profiling on, the step puts a barrier after each phase inside its parallel regions,
// so a phase's time is the slowest thread's (the barriers cost a little: compare totals only
// between runs with the same setting).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

namespace dem {

enum class Phase : int {
    kNeighbour,    // wall motion, rebuild test, cell grid and candidate lists
    kContacts,     // particle-particle and particle-wall contact forces
    kBonds,        // bond forces
    kPressure,     // membrane pressure forces
    kGather,       // per-particle force and torque sums, wall reactions
    kIntegration,  // leapfrog update with local damping
    kEnergy,       // energy ledger sums (params.track_energy)
    kOutput,       // the caller's output (files, sampling), booked with lap(Phase::kOutput)
    kCount
};

inline const char* phase_name(Phase p) {
    static constexpr const char* kNames[] = {"neighbour search", "contacts", "bonds", "pressure",
                                             "gather",           "integration", "energy", "output"};
    return kNames[int(p)];
}

class PhaseProfile {
public:
    using Clock = std::chrono::steady_clock;

    bool enabled() const { return enabled_; }
    void enable(bool on) {
        enabled_ = on;
        mark_ = Clock::now();
    }
    void reset() {
        seconds_.fill(0.0);
        mark_ = Clock::now();
    }
    // Restarts the clock without booking (e.g. before the first phase of a step).
    void start() {
        if (enabled_) mark_ = Clock::now();
    }
    // Books the time since the last start() or lap() to phase p.
    void lap(Phase p) {
        if (!enabled_) return;
        const Clock::time_point now = Clock::now();
        seconds_[std::size_t(p)] += std::chrono::duration<double>(now - mark_).count();
        mark_ = now;
    }
    double seconds(Phase p) const { return seconds_[std::size_t(p)]; }
    double total() const {
        double s = 0.0;
        for (double x : seconds_) s += x;
        return s;
    }

private:
    bool enabled_ = false;
    std::array<double, std::size_t(Phase::kCount)> seconds_{};
    Clock::time_point mark_{};
};

}  // namespace dem
