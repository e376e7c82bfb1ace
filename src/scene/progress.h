// One-line progress on stderr: stage, percent, simulated time, steps/s, time left.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace scene {

// How often a progress line is printed when nobody chose: every 2 s on a terminal, every 30 s
// into a log file (a day's run then writes about 3000 lines).
inline double default_progress_every() { return isatty(STDERR_FILENO) ? 2.0 : 30.0; }

class Progress {
public:
    // `total`: the stage's steps; with `at_most`, the most it can take (a stage that ends when
    // the grains are at rest), and the line says "at most ... left". `every` [s] between lines
    // (<= 0: default_progress_every()).
    Progress(std::string stage, uint64_t total, bool quiet, bool at_most = false, double every = 0)
        : stage_(std::move(stage)), total_(total), quiet_(quiet), at_most_(at_most), start_(clock::now()),
          last_(start_), every_(every > 0 ? every : default_progress_every()) {}

    // `done`: the stage's steps so far, counted from its start (a stage resumed from a
    // checkpoint starts above 0: the rate counts the steps this object saw made).
    void update(uint64_t done, double sim_time) {
        if (quiet_ || (done & 255u)) return;  // look at the clock every 256 steps only
        if (!seen_) {
            seen_ = true;
            first_ = done;
        }
        const auto now = clock::now();
        if (std::chrono::duration<double>(now - last_).count() < every_ && done < total_) return;
        last_ = now;
        const double el = std::chrono::duration<double>(now - start_).count();
        const double rate = double(done - std::min(done, first_)) / std::max(el, 1e-9);
        std::string left = "?";
        if (rate > 0) left = format_duration(double(total_ - std::min(done, total_)) / rate);
        std::fprintf(stderr, "[%s] %5.1f%%  t = %.6g s  %.0f steps/s  %s%s left\n", stage_.c_str(),
                     100.0 * double(std::min(done, total_)) / double(std::max<uint64_t>(total_, 1)), sim_time, rate,
                     at_most_ ? "at most " : "", left.c_str());
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
    bool quiet_, at_most_;
    clock::time_point start_, last_;
    double every_;            // [s] between lines
    bool seen_ = false;
    uint64_t first_ = 0;      // the first count seen: the rate counts from it
};

}  // namespace scene
