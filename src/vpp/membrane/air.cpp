#include "vpp/membrane/air.h"

#include <stdexcept>
#include <string>

namespace vpp {

void membrane_air_step(dem::World& w, const Membrane& m, double solids, double dp_set, const MembraneAirDef& def,
                       MembraneGas& g) {
    const double v = enclosed_volume(m, w.particles.pos) - solids;
    if (!(v > 0.0))
        throw std::runtime_error("air: the gas volume inside the membrane is " + std::to_string(v) +
                                 " m^3 (its enclosure minus the solids); the membrane has collapsed onto them");
    const double p_atm = def.line.p_atm;
    const bool pump = def.model == PressureModel::Pump;
    if (pump && g.amount == 0.0) g.amount = p_atm * v;  // sealed at the atmosphere's pressure
    // The gas's work over the step just taken, at the amount it held (isothermal: exact for a
    // fixed amount; the constant model's gas is at p_atm - dp).
    if (g.volume > 0.0) g.work += pump ? isothermal_work(g.amount, g.volume, v) : (p_atm - w.pressure.dp) * (v - g.volume);
    g.volume = v;
    if (!pump) {
        w.pressure.dp = dp_set;
        return;
    }
    const double p_set = p_atm - dp_set;
    if (def.hold_at_set) {
        g.amount = p_set * v;
    } else {
        PumpLine line = def.line;
        line.p_set = p_set;
        g.amount = advance_gas(g.amount, v, w.params.dt, line);
    }
    w.pressure.dp = g.amount == p_set * v ? dp_set : p_atm - g.amount / v;
}

}  // namespace vpp
