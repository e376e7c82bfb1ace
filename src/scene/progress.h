// One-line progress on stderr: stage, percent, simulated time, steps/s, time left.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace scene {

class Progress {
public:
    Progress(std::string stage, uint64_t total, bool quiet)
        : stage_(std::move(stage)), total_(total), quiet_(quiet), start_(clock::now()), last_(start_),
          // A terminal gets a line every 2 s; a log file every 30 s.
          every_(isatty(STDERR_FILENO) ? 2.0 : 30.0) {}

    void update(uint64_t done, double sim_time) {
        if (quiet_ || (done & 255u)) return;  // look at the clock every 256 steps only
        const auto now = clock::now();
        if (std::chrono::duration<double>(now - last_).count() < every_ && done < total_) return;
        last_ = now;
        const double el = std::chrono::duration<double>(now - start_).count();
        const double rate = double(done) / std::max(el, 1e-9);
        const double left = double(total_ - done) / std::max(rate, 1e-9);
        std::fprintf(stderr, "[%s] %5.1f%%  t = %.6g s  %.0f steps/s  %s left\n", stage_.c_str(),
                     100.0 * double(done) / double(std::max<uint64_t>(total_, 1)), sim_time, rate,
                     format_duration(left).c_str());
    }
    void finish() {}

    static std::string format_duration(double s) {
        char buf[32];
        if (s < 60) std::snprintf(buf, sizeof buf, "%.0fs", s);
        else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(s) % 60);
        else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600), (int(s) % 3600) / 60);
        return buf;
    }

private:
    using clock = std::chrono::steady_clock;
    std::string stage_;
    uint64_t total_;
    bool quiet_;
    clock::time_point start_, last_;
    double every_;  // [s] between lines
};

}  // namespace scene
