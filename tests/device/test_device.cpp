// The batch engine on a CUDA device (docs/gpu.md), vppdem_device_tests: the device backend gives
// World's bits on the tests' small damper (a batch of one over 10,000 steps; 8 mixed cases over
// 3,000), and `vppdem sweep --backend cuda` writes the files of --backend cpu byte for byte. Each
// test is skipped, naming why, where there is no device. The inputs (the small damper after its
// cycle for seeds 1 and 2, and the sweep's study) are read from $VPPDEM_DEVICE_INPUTS, else from
// inputs/ beside this binary (scripts/device_check.sh --bundle puts them there); missing ones are
// made with the vppdem beside this binary (or $VPPDEM_BINARY).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../physics/batch_compare.h"
#include "dem/batch/device_batch.h"

namespace fs = std::filesystem;
using batch_test::expect_same;
using batch_test::load_case;
using dem::World;

namespace {

fs::path here() {
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    return n > 0 ? fs::path(std::string(buf, std::size_t(n))).parent_path() : fs::current_path();
}

fs::path inputs() {
    const char* e = std::getenv("VPPDEM_DEVICE_INPUTS");
    return e && *e ? fs::path(e) : here() / "inputs";
}

std::string vppdem() {
    const char* e = std::getenv("VPPDEM_BINARY");
    return e && *e ? std::string(e) : (here() / "vppdem").string();
}

int shell(const std::string& cmd, std::string* out = nullptr) {
    FILE* f = popen((cmd + " 2>&1").c_str(), "r");
    if (!f) return -1;
    char buf[4096];
    std::string text;
    while (fgets(buf, sizeof buf, f)) text += buf;
    const int st = pclose(f);
    if (out) *out = text;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string damper_args(int seed) {
    return "--set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 "
           "--set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=1 "
           "--set process.samples_per_cycle=20 --set simulation.threads=1 --set simulation.seed=" +
           std::to_string(seed) + " --no-plot --quiet";
}

// The small damper after its cycle for `seed` (made when missing).
std::string sample(int seed) {
    const fs::path dir = inputs() / std::string("s").append(std::to_string(seed));
    if (!fs::exists(dir / "run.ckpt")) {
        std::string out;
        const int rc = shell(vppdem() + " damper --out " + dir.string() + " " + damper_args(seed), &out);
        if (rc != 0) ADD_FAILURE() << "could not prepare " << dir << ": " << out;
    }
    return (dir / "run.ckpt").string();
}

// The steps of the bitwise tests: `d`, or $VPPDEM_DEVICE_TEST_STEPS (the sanitizer's shorter runs).
int steps_or(int d) {
    const char* e = std::getenv("VPPDEM_DEVICE_TEST_STEPS");
    return e && std::atoi(e) > 0 ? std::atoi(e) : d;
}

#define SKIP_WITHOUT_DEVICE()                                                          \
    do {                                                                               \
        const char* why = nullptr;                                                     \
        if (dem::batch::dev::cuda_devices(&why) == 0)                                  \
            GTEST_SKIP() << "no CUDA device: " << (why ? why : "none");                \
    } while (0)

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST(DeviceBatch, ABatchOfOneGivesTheWorldsBitsOver10000Steps) {
    SKIP_WITHOUT_DEVICE();
    World ref = load_case(sample(1), 60e3, 0.3);
    World mine = ref;
    const uint64_t rebuilds0 = ref.rebuild_count();
    dem::batch::BatchSystems b;
    b.add(mine);
    dem::batch::DeviceBatch d(dem::batch::dev::cuda_device());
    std::printf("device: %s\n", d.device_name());
    d.load(b);
    const int steps = steps_or(10000);
    for (int k = 0; k < steps; ++k) ref.step();
    d.step(b, uint64_t(steps));
    d.pull(b, 0);
    b.store(0);
    std::printf("bus: %.1f MB up, %.1f MB down over %d steps\n", double(d.bytes_up()) / 1e6, double(d.bytes_down()) / 1e6, steps);
    expect_same(ref, mine, "device batch of one");
    if (steps >= 10000) {
        EXPECT_GT(mine.rebuild_count(), rebuilds0);
    }
    for (int k = 0; k < 200; ++k) {
        ref.step();
        mine.step();
    }
    expect_same(ref, mine, "after the hand-back");
}

// Chunks on the GPU (DeviceBatch::run, docs/gpu.md): the device runs the steps between events,
// World's bits for chunks of 1, 16 and 256 steps with events at odd steps, eight mixed cases.
TEST(DeviceBatch, ChunksGiveEachCasesBitsForAnyK) {
    SKIP_WITHOUT_DEVICE();
    const std::vector<batch_test::Case> cases = batch_test::eight_cases();
    const int steps = steps_or(3000);
    std::vector<World> ref;
    for (const batch_test::Case& c : cases) {
        ref.push_back(load_case(sample(c.seed), c.dp, c.mu, c.energy, c.restitution));
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    for (const int K : {1, 16, 256}) {
        std::vector<World> mine;
        for (const batch_test::Case& c : cases) mine.push_back(load_case(sample(c.seed), c.dp, c.mu, c.energy, c.restitution));
        dem::batch::BatchSystems b;
        for (World& w : mine) b.add(w);
        dem::batch::DeviceBatch d(dem::batch::dev::cuda_device());
        d.load(b);
        std::vector<std::exception_ptr> err(cases.size());
        std::vector<uint64_t> until(cases.size());
        for (std::size_t q = 0; q < cases.size(); ++q) until[q] = mine[q].steps + uint64_t(steps) / 3 + 37 * q;
        d.run(b, until, K, {}, err);
        for (std::size_t q = 0; q < cases.size(); ++q) until[q] = ref[q].steps;
        d.run(b, until, K, {}, err);
        for (std::size_t q = 0; q < cases.size(); ++q) {
            if (err[q]) std::rethrow_exception(err[q]);
            d.pull(b, q);
            b.store(q);
            expect_same(ref[q], mine[q], "case " + std::to_string(q) + ", chunks of " + std::to_string(K));
        }
        std::printf("chunks of %d: %llu chunks, %llu layouts, %llu waits over %d steps\n", K,
                    (unsigned long long)d.chunks(), (unsigned long long)d.relayouts(), (unsigned long long)d.waits(), steps);
    }
}

TEST(DeviceBatch, ABatchOfEightMixedCasesGivesEachCasesBits) {
    SKIP_WITHOUT_DEVICE();
    const std::vector<batch_test::Case> cases = batch_test::eight_cases();
    const int steps = steps_or(3000);
    std::vector<World> ref, mine;
    for (const batch_test::Case& c : cases) {
        ref.push_back(load_case(sample(c.seed), c.dp, c.mu, c.energy, c.restitution));
        mine.push_back(ref.back());
        for (int k = 0; k < steps; ++k) ref.back().step();
    }
    dem::batch::BatchSystems b;
    for (World& w : mine) b.add(w);
    dem::batch::DeviceBatch d(dem::batch::dev::cuda_device());
    d.load(b);
    d.step(b, uint64_t(steps));
    for (std::size_t q = 0; q < cases.size(); ++q) {
        d.pull(b, q);
        b.store(q);
        expect_same(ref[q], mine[q], "case " + std::to_string(q));
    }
}

TEST(DeviceSweep, TheCudaBackendWritesTheCpuBackendsFiles) {
    SKIP_WITHOUT_DEVICE();
    fs::path study = inputs() / "small_study.toml";
    if (!fs::exists(study)) study = fs::path(VPPDEM_SOURCE_DIR) / "tests/device/small_study.toml";
    const fs::path work = fs::temp_directory_path() / ("vppdem_device_sweep_" + std::to_string(getpid()));
    fs::remove_all(work);
    const fs::path cpu = work / "cpu", cuda = work / "cuda";
    std::string out;
    ASSERT_EQ(shell(vppdem() + " sweep " + study.string() + " --out " + cpu.string() + " --jobs 2 --no-plot --quiet", &out), 0) << out;
    ASSERT_EQ(shell(vppdem() + " sweep " + study.string() + " --out " + cuda.string() + " --jobs 2 --backend cuda --no-plot", &out), 0)
        << out;
    std::printf("%s", out.c_str());
    int cases = 0;
    for (const auto& e : fs::directory_iterator(cpu)) {
        if (!e.is_directory()) continue;
        ++cases;
        for (const char* f : {"forces.csv", "cycles.csv", "energy.csv"}) {
            ASSERT_TRUE(fs::exists(e.path() / f)) << e.path() / f;
            EXPECT_EQ(slurp(e.path() / f), slurp(cuda / e.path().filename() / f)) << e.path().filename() << "/" << f;
        }
    }
    EXPECT_EQ(cases, 3);
    fs::remove_all(work);
}
