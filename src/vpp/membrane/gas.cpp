#include "vpp/membrane/gas.h"

#include <algorithm>
#include <cmath>

namespace vpp {

double advance_gas(double amount, double v, double dt, const PumpLine& line) {
    // Leak: d(pV)/dt = C (p_atm - p) at fixed V relaxes pV towards p_atm V with rate C / V.
    if (line.leak > 0.0) {
        const double eq = line.p_atm * v;
        amount = eq + (amount - eq) * std::exp(-line.leak * dt / v);
    }
    // The regulator: the pump while p > p_set (d(pV)/dt = -S p = -(S / V) pV), the bleed while
    // p < p_set (as the leak); each stops at p_set V, where the regulator closes.
    const double set = line.p_set * v;
    if (amount > set && line.speed > 0.0) {
        amount = std::max(amount * std::exp(-line.speed * dt / v), set);
    } else if (amount < set && line.bleed > 0.0) {
        const double eq = line.p_atm * v;
        amount = std::min(eq + (amount - eq) * std::exp(-line.bleed * dt / v), set);
    }
    return amount;
}

double isothermal_work(double amount, double v0, double v1) { return amount * std::log(v1 / v0); }

}  // namespace vpp
