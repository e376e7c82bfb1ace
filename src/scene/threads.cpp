#include "scene/threads.h"

#include <sched.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

namespace scene {

namespace {

struct CpuTime {
    double idle = 0;   // [ticks] idle + iowait
    double total = 0;  // [ticks] all fields up to steal (guest time is already in user/nice)
};

// cpuN -> its times, from the text of /proc/stat.
std::map<int, CpuTime> parse_stat(const std::string& text) {
    std::map<int, CpuTime> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        if (line.size() < 4 || line.compare(0, 3, "cpu") != 0 || !std::isdigit((unsigned char)line[3])) continue;
        std::istringstream ls(line.substr(3));
        int cpu = -1;
        ls >> cpu;
        // user nice system idle iowait irq softirq steal [guest guest_nice]
        double v[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        int n = 0;
        while (n < 8 && ls >> v[n]) ++n;
        if (cpu < 0 || n < 4) continue;
        CpuTime t;
        t.idle = v[3] + v[4];
        for (int k = 0; k < n; ++k) t.total += v[k];
        out[cpu] = t;
    }
    return out;
}

std::string read_proc_stat() {
    std::ifstream in("/proc/stat");
    if (!in) return {};
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

std::vector<int> allowed_cpus() {
    std::vector<int> cpus;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(c, &set)) cpus.push_back(c);
    }
    if (cpus.empty()) {
        const int n = std::max(1, int(std::thread::hardware_concurrency()));
        for (int c = 0; c < n; ++c) cpus.push_back(c);
    }
    return cpus;
}

double free_cores(const std::string& stat_before, const std::string& stat_after, const std::vector<int>& cpus) {
    const auto a = parse_stat(stat_before), b = parse_stat(stat_after);
    double free = 0;
    for (int c : cpus) {
        const auto ia = a.find(c), ib = b.find(c);
        if (ia == a.end() || ib == b.end()) {
            free += 1.0;
            continue;
        }
        const double total = ib->second.total - ia->second.total, idle = ib->second.idle - ia->second.idle;
        free += total > 0 ? std::clamp(idle / total, 0.0, 1.0) : 1.0;
    }
    return free;
}

int threads_for(double free, int usable) {
    const int n = int(std::floor(free + 0.5));
    return std::max(1, std::min(n, std::max(1, usable)));
}

int default_threads() {
    static std::once_flag once;
    static int threads = 1;
    std::call_once(once, [] {
        const std::vector<int> cpus = allowed_cpus();
        const std::string before = read_proc_stat();
        if (before.empty()) {
            threads = int(cpus.size());
            return;
        }
        // This thread sleeps meanwhile, so the sample sees the other work only.
        std::this_thread::sleep_for(std::chrono::milliseconds(150));
        threads = threads_for(free_cores(before, read_proc_stat(), cpus), int(cpus.size()));
    });
    return threads;
}

}  // namespace scene
