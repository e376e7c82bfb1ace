#include "dem/batch/batch_systems.h"

#include <stdexcept>
#include <string>

#include "dem/batch/particle_step.h"
#include "dem/core/parallel.h"
#include "dem/core/thread_team.h"

namespace dem::batch {

std::size_t BatchSystems::add(const World& world) {
    const Particles& p = world.particles;
    if (!world.clumps().empty())
        throw std::invalid_argument("batch: a system with clumps is not supported yet (docs/gpu.md)");
    const std::size_t s = systems();
    gravity.push_back(world.params.gravity);
    dt.push_back(world.params.dt);
    lambda.push_back(world.params.local_damping);
    for (std::size_t i = 0; i < p.size(); ++i) {
        x.push_back(p.pos[i]);
        v.push_back(p.vel[i]);
        w.push_back(p.angvel[i]);
        f.push_back(p.force[i]);
        fx.push_back(p.ext_force.empty() ? Vec3{} : p.ext_force[i]);
        t.push_back(p.torque[i]);
        m.push_back(p.mass[i]);
        inv_m.push_back(p.inv_mass[i]);
        inv_i.push_back(p.inv_inertia[i]);
    }
    first.push_back(int64_t(x.size()));
    return s;
}

void BatchSystems::store(std::size_t s, World& world) const {
    Particles& p = world.particles;
    if (s >= systems() || std::size_t(first[s + 1] - first[s]) != p.size())
        throw std::invalid_argument("batch: system " + std::to_string(s) + " does not match the world");
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = std::size_t(first[s]) + i;
        p.pos[i] = x[k];
        p.vel[i] = v[k];
        p.angvel[i] = w[k];
    }
    world.invalidate_candidates();
}

void advance_host(BatchSystems& b, int threads) {
    const int nt = threads > 1 ? threads : 1;
    ThreadTeam team;
    team.run(nt, [&](int tid) {
        const auto [s0, s1] = thread_range(int64_t(b.systems()), tid, nt);
        for (int64_t s = s0; s < s1; ++s)
            for (int64_t k = b.first[s]; k < b.first[s + 1]; ++k) {
                ParticleState st{b.x[k], b.v[k], b.w[k]};
                advance_particle(st, b.f[k], b.fx[k], b.t[k], b.m[k], b.inv_m[k], b.inv_i[k], b.gravity[s], b.dt[s],
                                 b.lambda[s]);
                b.x[k] = st.x;
                b.v[k] = st.v;
                b.w[k] = st.w;
            }
    });
}

}  // namespace dem::batch
