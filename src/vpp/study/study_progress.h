// The study's progress line (sweep, calibrate): the cases done, each running case's stage and
// percent, and the time left for the study, printed now and then while its cases run. At the
// paper's size one case takes hours: a line only when a case ends would leave the user in the
// dark for that long.
//
// Time left, from what the cases show (every time in [s] of wall clock):
//  - a running case in its cycling stage (the last, and nearly all of a run): the stage's steps
//    left over its rate since the stage started (or since this line first saw it), less the time
//    since its last report;
//  - any other running case: the mean time of the cases finished in this sweep, less its time so
//    far (at least 0); unknown before one finished;
//  - a case not started: that mean, or, before one finished, the total of a running cycling case
//    (its time so far plus its time left);
//  - the study: the longest running case's, or the running and pending cases' sum over the jobs,
//    whichever is longer. Unknown while any part is: the line says so.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace vpp {

class StudyProgress {
public:
    // `total` cases of this process, `jobs` running at once, `every` [s] between lines.
    StudyProgress(std::string command, std::size_t total, int jobs, double every);

    void started(std::size_t i, const std::string& name, double now);
    // From the case's progress hook: its stage, the stage's steps done and expected (or the most
    // it can take).
    void stage(std::size_t i, const std::string& stage, uint64_t done, uint64_t total, double now);
    // `ran`: it ran in this sweep (its time counts in the mean); false: done earlier or failed.
    void finished(std::size_t i, bool ran, double now);

    // The line when one is due (`every` since the last), else "". Thread-safe, as are the above.
    std::string due(double now);
    // The line as it stands (no trailing newline).
    std::string line(double now) const;
    // [s] the study's time left; < 0 when unknown.
    double time_left(double now) const;

private:
    std::string compose(double now) const;  // line(), under mu_
    double left(double now) const;          // time_left(), under mu_
    struct Running {
        std::string name, stage;
        double start = 0, stage_start = 0, at = 0;  // [s] the case's start, its stage's, the last update
        uint64_t done = 0, total = 0, stage_first = 0;
    };
    double case_left(const Running& r, double now) const;  // < 0: unknown

    mutable std::mutex mu_;
    std::string command_;
    std::size_t total_, done_ = 0;
    int jobs_;
    double every_, last_ = -1e300;
    double ran_seconds_ = 0;  // [s] the finished cases' times
    std::size_t ran_ = 0;
    std::map<std::size_t, Running> running_;
};

}  // namespace vpp
