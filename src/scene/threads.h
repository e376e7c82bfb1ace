// The default thread count of every command: the cores this process may use that are not busy
// with other work, so a run never starts more step threads than there are free cores.
//
// Why: The threads of a step wait for each other at every barrier of a time step. When one of them
// shares its core with another busy process, all of them wait for it, and a spinning wait makes
// it worse (dem/core/thread_team.h): on the 2-core machine with a benchmark on one core, a 2-thread damper took 150 s
// where 1 thread took 11 s. An explicit thread count (--threads, simulation.threads) is always
// honoured; only the default adapts.
//
// How busy the cores are is measured from /proc/stat over a short sample (150 ms) rather than
// read from /proc/loadavg: the load average is a 1-minute mean (slow to follow a job that just
// started or ended), counts tasks of the whole machine whatever our affinity mask, and counts
// tasks blocked on I/O as load. /proc/stat gives each CPU's busy and idle time, so the CPUs of
// our affinity mask (sched_getaffinity) can be looked at alone.
#pragma once

#include <string>
#include <vector>

namespace scene {

// CPUs this process may run on (sched_getaffinity), in increasing order; {0..n-1} from
// std::thread::hardware_concurrency() when the mask cannot be read.
std::vector<int> allowed_cpus();

// Free cores among `cpus` between two snapshots of /proc/stat (the text of the file): the sum
// over those CPUs of their idle share of the interval, (idle + iowait) / all time, each in
// [0, 1]. A CPU missing from a snapshot, or with no time passed, counts as free (nothing is
// known against it). Lines other than "cpuN ..." are ignored.
double free_cores(const std::string& stat_before, const std::string& stat_after, const std::vector<int>& cpus);

// Threads for `free` free cores out of `usable`: free rounded to the nearest integer (a core
// busy more than half the time counts as busy), at least 1, at most usable.
int threads_for(double free, int usable);

// The default thread count (threads_for(free_cores over a 150 ms sample, allowed cpus)).
// Measured on the first call, then cached for the life of the process; the usable cores when
// /proc/stat cannot be read.
int default_threads();

// Short description of the default for help texts and logs.
inline constexpr const char* kDefaultThreadsHelp =
    "default: the free cores, i.e. the cores this process may use minus those busy with other "
    "work (measured over 150 ms at start), at least 1";

}  // namespace scene
