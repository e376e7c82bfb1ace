#include "dem/core/particles.h"

namespace dem {

namespace {

// The one sum behind both overloads: `each` calls its argument with every index in order.
template <class Each>
KineticEnergy sum_kinetic_energy(const Particles& p, Each each) {
    KineticEnergy e;
    each([&](uint32_t i) {
        if (p.inv_mass[i] != 0.0) e.translation += 0.5 * p.mass[i] * norm2(p.vel[i]);
        if (p.inv_inertia[i] != 0.0) e.rotation += 0.5 / p.inv_inertia[i] * norm2(p.angvel[i]);
    });
    return e;
}

}  // namespace

KineticEnergy kinetic_energy(const Particles& p, std::span<const uint32_t> ids) {
    return sum_kinetic_energy(p, [&](auto&& f) {
        for (uint32_t i : ids) f(i);
    });
}

KineticEnergy kinetic_energy(const Particles& p, uint32_t first, uint32_t end) {
    return sum_kinetic_energy(p, [&](auto&& f) {
        for (uint32_t i = first; i < end; ++i) f(i);
    });
}

}  // namespace dem
