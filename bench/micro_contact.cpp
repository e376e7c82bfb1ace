// Micro-benchmarks of the pure kernels (Google Benchmark). Whole-scene timings: `vppdem bench`.
#include <benchmark/benchmark.h>

#include "dem/contact/linear_law.h"
#include "dem/detect/geometry.h"

static void BM_SphereSphereLinearLaw(benchmark::State& state) {
    dem::Material m;
    const dem::ContactPhys phys = dem::make_contact_phys(m, 0.01, m, 0.01, 1.0);
    dem::ShearHistory h;
    dem::Vec3 x2{0.0199, 0.0001, 0.0};
    for (auto _ : state) {
        dem::ContactGeom g;
        dem::sphere_sphere({0, 0, 0}, 0.01, x2, 0.01, g);
        auto f = dem::linear_contact_force(phys, g, {0.0, 0.01, 0.0}, 0.0, 1e-7, h);
        benchmark::DoNotOptimize(f);
    }
}
BENCHMARK(BM_SphereSphereLinearLaw);

static void BM_SphereFacet(benchmark::State& state) {
    std::array<dem::Vec3, 3> v{dem::Vec3{0, 0, 0}, dem::Vec3{1, 0, 0}, dem::Vec3{0, 1, 0}};
    for (auto _ : state) {
        dem::ContactGeom g;
        bool t = dem::sphere_facet({0.2, 0.2, 0.005}, 0.01, v, false, g);
        benchmark::DoNotOptimize(t);
        benchmark::DoNotOptimize(g);
    }
}
BENCHMARK(BM_SphereFacet);

BENCHMARK_MAIN();
