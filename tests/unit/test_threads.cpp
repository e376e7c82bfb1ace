// The default thread count (scene/threads.h): free cores from two /proc/stat snapshots.
#include <gtest/gtest.h>

#include <string>

#include "scene/threads.h"

namespace {

// Two snapshots of a 2-CPU machine 150 ms apart (USER_HZ = 100: 15 ticks per CPU):
// cpu0 busy all the time (another process), cpu1 idle but for one tick.
const std::string kBefore =
    "cpu  21941 29972 11072 103602 600 0 272 0 0 0\n"
    "cpu0 8455 13980 4470 56680 34 0 103 0 0 0\n"
    "cpu1 13486 15992 6602 46921 565 0 169 0 0 0\n"
    "intr 400032 0 0 0\n"
    "ctxt 123456\n"
    "cpu_not_a_cpu 1 2 3\n";
const std::string kAfter =
    "cpu  21956 29972 11073 103616 600 0 272 0 0 0\n"
    "cpu0 8470 13980 4470 56680 34 0 103 0 0 0\n"
    "cpu1 13487 15992 6602 46935 565 0 169 0 0 0\n"
    "intr 400100 0 0 0\n";

}  // namespace

TEST(Threads, OneBusyCoreOfTwoLeavesOneFree) {
    const double f = scene::free_cores(kBefore, kAfter, {0, 1});
    EXPECT_NEAR(f, 0.0 + 14.0 / 15.0, 1e-12);  // cpu0: 0 idle of 15; cpu1: 14 idle of 15
    EXPECT_EQ(scene::threads_for(f, 2), 1);
    // Only the CPUs of the affinity mask count.
    EXPECT_NEAR(scene::free_cores(kBefore, kAfter, {1}), 14.0 / 15.0, 1e-12);
    EXPECT_NEAR(scene::free_cores(kBefore, kAfter, {0}), 0.0, 1e-12);
    EXPECT_EQ(scene::threads_for(scene::free_cores(kBefore, kAfter, {0}), 1), 1);  // never 0
}

TEST(Threads, IdleMachineGivesAllUsableCores) {
    const std::string a = "cpu0 100 0 100 1000 10 0 0 0\ncpu1 100 0 100 1000 0 0 0 0\n";
    const std::string b = "cpu0 100 0 100 1015 15 0 0 0\ncpu1 101 0 100 1019 0 0 0 0\n";  // iowait counts as idle
    EXPECT_NEAR(scene::free_cores(a, b, {0, 1}), 1.0 + 19.0 / 20.0, 1e-12);
    EXPECT_EQ(scene::threads_for(scene::free_cores(a, b, {0, 1}), 2), 2);
}

TEST(Threads, HalfBusyCoresRoundToTheNearestCount) {
    // Four CPUs each 40% busy (e.g. two processes wandering between them): 2.4 free -> 2.
    std::string a, b;
    for (int c = 0; c < 4; ++c) {
        a += "cpu" + std::to_string(c) + " 0 0 0 0 0 0 0 0 0 0\n";
        b += "cpu" + std::to_string(c) + " 4 0 0 6 0 0 0 0 0 0\n";
    }
    EXPECT_NEAR(scene::free_cores(a, b, {0, 1, 2, 3}), 2.4, 1e-12);
    EXPECT_EQ(scene::threads_for(2.4, 4), 2);
    EXPECT_EQ(scene::threads_for(2.6, 4), 3);
    EXPECT_EQ(scene::threads_for(7.0, 4), 4);  // never more than usable
}

TEST(Threads, UnknownCpusAndEmptyIntervalsCountAsFree) {
    // Steal time (a hypervisor's) counts as busy; a CPU absent from the file or without ticks
    // in the interval is taken as free: nothing is known against it.
    const std::string a = "cpu0 0 0 0 0 0 0 0 0\ncpu1 5 0 0 5 0 0 0 0\n";
    const std::string b = "cpu0 0 0 0 0 0 0 0 10\ncpu1 5 0 0 5 0 0 0 0\n";
    EXPECT_NEAR(scene::free_cores(a, b, {0, 1, 7}), 0.0 + 1.0 + 1.0, 1e-12);
    EXPECT_NEAR(scene::free_cores("", "", {0, 1}), 2.0, 1e-12);
}

TEST(Threads, DefaultIsBetweenOneAndTheUsableCores) {
    const int n = scene::default_threads();
    EXPECT_GE(n, 1);
    EXPECT_LE(n, int(scene::allowed_cpus().size()));
    EXPECT_EQ(scene::default_threads(), n);  // measured once per process
}
