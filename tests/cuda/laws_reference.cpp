// The GCC side of tests/cuda: the cases and the laws as the CPU build compiles them.
#include <cstdint>

#include "laws_eval.h"

namespace cuda_test {

namespace {

// splitmix64: a fixed stream on every machine.
struct Stream {
    uint64_t s;
    double uniform(double lo, double hi) {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return lo + (hi - lo) * double(z >> 11) * 0x1.0p-53;
    }
    dem::Vec3 vec(double a) { return {uniform(-a, a), uniform(-a, a), uniform(-a, a)}; }
};

}  // namespace

std::vector<LawCase> make_cases(std::size_t n) {
    Stream g{20261125};
    std::vector<LawCase> out(n);
    for (std::size_t k = 0; k < n; ++k) {
        LawCase& c = out[k];
        c.kn = g.uniform(1e3, 1e7);
        c.ks = c.kn * g.uniform(0.0, 1.0);
        c.mu = k % 5 == 0 ? 0.0 : g.uniform(0.0, 1.0);
        c.cn = k % 3 == 0 ? 0.0 : g.uniform(0.0, 10.0);
        c.overlap = g.uniform(0.0, 1e-4);
        c.spin = g.uniform(-50, 50);
        c.dt = g.uniform(1e-7, 1e-5);
        c.rest = g.uniform(1e-3, 3e-3);
        c.n = dem::normalized(g.vec(1.0));
        c.vrel = g.vec(0.5);
        c.fs = k % 4 == 0 ? dem::Vec3{} : g.vec(1.0);
        c.prev = k % 4 == 0 ? dem::Vec3{} : dem::normalized(c.n + g.vec(0.01));
        c.f = g.vec(10.0);
        c.v = g.vec(1.0);
        c.t = g.vec(1e-3);
        c.w = g.vec(20.0);
        c.inv_mass = g.uniform(10, 1e4);
        c.inv_inertia = g.uniform(1e5, 1e8);
        c.lambda = k % 2 ? 0.2 : 0.0;
        c.p1 = g.vec(0.03);
        c.p2 = g.vec(0.03);
        c.p3 = g.vec(0.03);
        c.p4 = g.vec(0.03);
        c.q = dem::normalized(dem::Quat{g.uniform(-1, 1), g.uniform(-1, 1), g.uniform(-1, 1), g.uniform(-1, 1)});
        c.L = g.vec(1e-6);
        c.I = {g.uniform(1e-9, 2e-9), g.uniform(2e-9, 3e-9), g.uniform(3e-9, 4e-9)};
    }
    return out;
}

LawResult reference(const LawCase& c) { return evaluate(c); }

}  // namespace cuda_test
